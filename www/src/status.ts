// The status line and its neighbours: the run state (which also enables Play / Pause / Cancel),
// the progress readout, the error box and the dismissable notice. They show; they decide nothing.
import { byId } from './dom';
import type { UiError } from './protocol';

/** The page's run state, as data-state on the status line (the e2e tests wait on it). */
export type RunState = 'idle' | 'loading' | 'running' | 'paused' | 'done' | 'invalid' | 'error';

export class StatusLine {
  private readonly line = byId('status');
  private readonly errorBox = byId('error');
  private readonly noticeBox = byId('notice');

  constructor() {
    this.noticeBox.onclick = () => (this.noticeBox.hidden = true);
  }

  /** The run state shown. */
  get state(): RunState {
    return this.line.dataset.state as RunState;
  }

  /** Whether a job is under way (loading or running): Cancel stops it, a new input replaces it. */
  get busy(): boolean {
    return this.state === 'running' || this.state === 'loading';
  }

  /** Clears what described the previous run: progress bar, step statistics, colour legend. */
  clearReadout(): void {
    byId('progress').hidden = true;
    const line = byId('progress-text');
    line.textContent = '';
    line.title = '';
    delete line.dataset.phases;
    byId('phases-toggle').hidden = true;
    byId('phase-times').hidden = true;
    const stats = byId('stats');
    stats.textContent = '';
    delete stats.dataset.step;
    byId('legend').hidden = true;
  }

  set(state: RunState, text: string): void {
    this.line.dataset.state = state;
    this.line.textContent = text;
    const running = state === 'running';
    byId<HTMLButtonElement>('play').disabled = running || state === 'loading';
    byId<HTMLButtonElement>('pause').disabled = !running;
    // A paused run is still under way: Cancel ends it, Play resumes it.
    byId<HTMLButtonElement>('cancel').disabled = !(running || state === 'loading' || state === 'paused');
  }

  /** A long phase of the core is `fraction` done: "distance field: near band 45 %" on the status
   * line (data-progress carries the phase and percentage for scripts). The state stays. */
  progress(phase: string, fraction: number): void {
    const pct = Math.round(100 * fraction);
    const base = this.state === 'loading' ? 'Preparing' : (this.line.textContent ?? '').split(' — ')[0];
    this.line.textContent = `${base} — ${phase} ${pct} %`;
    this.line.dataset.progress = `${phase} ${pct}`;
  }

  /** Shows an error with its hint, or hides the box (null). */
  error(e: UiError | null): void {
    this.errorBox.hidden = !e;
    this.errorBox.textContent = e ? `${e.message}${e.hint ? ' — ' + e.hint : ''}` : '';
  }

  /** Shows a failure: the error and the error state. */
  fail(e: UiError): void {
    this.error(e);
    this.set('error', 'Error');
  }

  /** Shows notices (e.g. keys of a share link that were ignored) until clicked; none hides the box. */
  notice(lines: string[]): void {
    this.noticeBox.hidden = lines.length === 0;
    this.noticeBox.textContent = lines.length ? `${lines.join(' ')} (click to dismiss)` : '';
  }
}

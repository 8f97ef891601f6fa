// The status line and its neighbours: the run state (which also enables Play / Pause / Cancel),
// the error box and the dismissable notice. They show; they decide nothing.
import { byId } from './dom';
import type { UiError } from './protocol';

/** The page's run state, as data-state on the status line (the e2e tests wait on it). */
export type RunState = 'idle' | 'loading' | 'running' | 'done' | 'invalid' | 'error';

export class StatusLine {
  private readonly line = byId('status');
  private readonly errorBox = byId('error');
  private readonly noticeBox = byId('notice');

  /** `cancellable`: whether a running or loading job may be cancelled (wraps may, the MCF lesson may not). */
  constructor(private readonly cancellable: () => boolean) {
    this.noticeBox.onclick = () => (this.noticeBox.hidden = true);
  }

  set(state: RunState, text: string): void {
    this.line.dataset.state = state;
    this.line.textContent = text;
    const running = state === 'running';
    byId<HTMLButtonElement>('play').disabled = running || state === 'loading';
    byId<HTMLButtonElement>('pause').disabled = !running;
    byId<HTMLButtonElement>('cancel').disabled = !(running || state === 'loading') || !this.cancellable();
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

// The MCF lesson: a sphere under mean-curvature flow, plotted against the exact law
// r(t) = √(r₀² − 4t). Its parameters are the subdivision level and the time step τ; changing
// either starts the lesson afresh.
import { byId } from './dom';
import type { FieldControls } from './field-view';
import type { ModeSwitch } from './mode';
import { RadiusPlot } from './plots';
import type { Draw, McfParams, McfStats, Send, StopReason, TauAdvice } from './protocol';
import type { StatusLine } from './status';

export interface LessonDeps {
  mode: ModeSwitch;
  status: StatusLine;
  field: FieldControls;
  draw: Draw;
  send: Send;
  /** Rewrites the share link. */
  share: () => void;
}

export class Lesson {
  private readonly plot = new RadiusPlot(byId('plot'));
  /** The latest statistics (for the closing words). */
  private last: McfStats | null = null;

  constructor(private readonly d: LessonDeps) {
    byId('level').onchange = () => this.reset();
    byId('tau').onchange = () => this.reset();
  }

  params(): McfParams {
    return { level: Number(byId<HTMLSelectElement>('level').value), radius: 1, tau: Number(byId<HTMLInputElement>('tau').value) };
  }

  /** Switches to the lesson and starts it from the initial sphere (no target, no field). */
  reset(): void {
    const { mode, status, field, draw, send, share } = this.d;
    mode.set('mcf');
    field.hide();
    status.error(null);
    status.clearReadout();
    this.plot.clear();
    draw({ type: 'clear-frames' });
    draw({ type: 'target', positions: new Float32Array(0), indices: null });
    draw({ type: 'refit' });
    this.last = null;
    send({ type: 'mcf-init', params: this.params() });
    status.set('idle', 'Ready');
    share();
  }

  play(): void {
    this.d.status.error(null);
    this.d.send({ type: 'play' });
    this.d.status.set('running', 'Running');
  }

  /** The worker judged τ before the run: a warning next to the input when it is not sensible. */
  advice(a: TauAdvice): void {
    const warning = byId('tau-warning');
    warning.hidden = a.sensible;
    warning.textContent = a.warning;
    byId('tau').title = `Sensible: ${a.tauMin.toPrecision(2)} – ${a.tauMax.toPrecision(2)}; this τ takes ${a.steps} steps (the sphere vanishes at t = r₀²/4 = ${a.extinctionTime})`;
  }

  /** The worker stopped the flow: at its end, on a pause, or cancelled (back to the start). */
  stopped(reason: StopReason): void {
    const s = this.last;
    if (reason === 'finished') {
      const where = s ? ` at t = ${s.time.toPrecision(3)}: mean radius ${s.meanRadius.toFixed(3)}, exact ${s.exactRadius.toFixed(3)}` : '';
      this.d.status.set('done', `Done${where}`);
    }
    else if (reason === 'cancelled') this.reset();
    else this.d.status.set('idle', 'Paused');
  }

  /** A frame's statistics: the radius plot and the numbers beside it. */
  frame(s: McfStats, playing: boolean): void {
    this.last = s;
    this.plot.push(s.time, s.meanRadius, s.exactRadius);
    const err = s.exactRadius > 0 ? (100 * (s.meanRadius - s.exactRadius)) / s.exactRadius : NaN;
    byId('stats').textContent =
      `step ${s.step}   t = ${s.time.toFixed(4)}\n` +
      `mean radius ${s.meanRadius.toFixed(5)}   exact ${s.exactRadius.toFixed(5)}   (${err.toFixed(3)} %)\n` +
      `co-volume min/mean/max ${s.covolumeMin.toExponential(2)} / ${s.covolumeMean.toExponential(2)} / ${s.covolumeMax.toExponential(2)}\n` +
      `solver ${s.solverIterations} it, residual ${s.solverResidual.toExponential(1)}   ${s.msPerStep.toFixed(2)} ms/step\n` +
      `${s.vertices} vertices, ${s.faces} faces`;
    byId('stats').dataset.step = String(s.step);
    byId('progress').hidden = true;
    byId('progress-text').textContent = '';
    if (playing) this.d.status.set('running', `Running — step ${s.step}`);
  }

  /** The plotted series (for tests). */
  series(): ReturnType<RadiusPlot['series']> {
    return this.plot.series();
  }
}

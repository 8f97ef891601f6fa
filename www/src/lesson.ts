// The MCF lessons. The sphere: a sphere under mean-curvature flow, plotted against the exact law
// r(t) = √(r₀² − 4t); its parameters are the subdivision level and the time step τ. The loaded
// mesh: the same flow smoothing the mesh the user loaded, its area (and enclosed volume) plotted
// over t/D²; its parameter is τ/D². Changing a parameter starts the lesson afresh. The lesson
// entries come from the catalog; the mesh lesson is offered only while a mesh is loaded.
import { byId } from './dom';
import type { FieldControls } from './field-view';
import type { ModeSwitch } from './mode';
import { LinePlot, RadiusPlot } from './plots';
import { showLegend } from './frame-view';
import type { CatalogLesson, Draw, Frame, LessonKind, McfParams, McfStats, MeshStats, MeshTauAdvice, Send, SphereStats, StopReason, TauAdvice } from './protocol';
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

/** Why the mesh lesson is off before anything is loaded. */
const NO_MESH = 'MCF on the loaded mesh: load a mesh first (drop one, or pick Bunny mesh or Teapot mesh).';

const pct = (x: number) => `${(100 * x).toFixed(1)} %`;

/** What a frame showed beside the surface: the numbers, its time on the plot, its legend. */
interface Shot {
  text: string;
  x: number;
  colour: string;
  range: [number, number];
  coloured: boolean;
}

export class Lesson {
  private readonly plot = new RadiusPlot(byId('plot'));
  private readonly areaPlot = new LinePlot(byId('plot-area'), 'Area, volume / start vs t/D²', ['area', 'volume'], ['#4aa3ff', '#ffb347'], { xLabel: 't/D²', width: 340 });
  /** The lesson shown (or last shown). */
  kind: LessonKind = 'sphere';
  /** Why the loaded input cannot be flowed ('' when it can), and its name. */
  private meshWhy = NO_MESH;
  private meshName = '';
  private entries: CatalogLesson[] = [];
  /** The latest statistics (for the closing words). */
  private last: McfStats | null = null;
  /** Whether this lesson was asked to play or step since it started: a wrap's "stopped", still
   * in flight when the lesson replaced it, must not end the fresh lesson. */
  private asked = false;
  /** What each frame showed, by step, for the scrubber; and the latest step. */
  private readonly shots = new Map<number, Shot>();
  private liveStep = -1;
  /** The step of the frame the scrubber shows (null: the live end). */
  private scrubbedAt: number | null = null;

  constructor(private readonly d: LessonDeps) {
    byId('level').onchange = () => this.start('sphere');
    byId('tau').onchange = () => this.start('sphere');
    byId('tau-mesh').onchange = () => this.start('mesh');
  }

  params(): McfParams {
    return { level: Number(byId<HTMLSelectElement>('level').value), radius: 1, tau: Number(byId<HTMLInputElement>('tau').value) };
  }

  /** A link's parameters (a number it lacks, or a level the menu has not, stays as it is). */
  setParams(p: { level: number; tau: number }): void {
    const level = byId<HTMLSelectElement>('level');
    if ([...level.options].some((o) => Number(o.value) === p.level)) level.value = String(p.level);
    if (Number.isFinite(p.tau)) byId<HTMLInputElement>('tau').value = String(p.tau);
  }

  /** The lesson buttons, from the catalog, at the end of the demo gallery. */
  menu(lessons: CatalogLesson[]): void {
    this.entries = lessons;
    const gallery = byId('gallery');
    for (const b of gallery.querySelectorAll('[data-lesson]')) b.remove();
    for (const l of lessons) {
      const b = document.createElement('button');
      b.dataset.lesson = b.dataset.demo = l.name;
      b.textContent = l.label;
      b.onclick = () => this.start(l.needsMesh ? 'mesh' : 'sphere');
      gallery.append(b);
    }
    this.offer();
  }

  /** Something was loaded: the mesh lesson can flow it when `why` is '' (else it says why not). */
  target(name: string, why: string): void {
    this.meshWhy = why;
    this.meshName = name;
    this.offer();
  }

  /** Enables the entries that can run now; a disabled one says why, on it and below the gallery. */
  private offer(): void {
    for (const l of this.entries) {
      const b = document.querySelector<HTMLButtonElement>(`#gallery [data-lesson="${l.name}"]`);
      if (!b) continue;
      const off = l.needsMesh && this.meshWhy !== '';
      b.disabled = off;
      b.title = off ? this.meshWhy : l.needsMesh ? `${l.title} — ${this.meshName}` : l.title;
    }
    const why = byId('lesson-why');
    why.textContent = this.entries.some((l) => l.needsMesh) ? this.meshWhy : '';
    why.hidden = why.textContent === '';
  }

  /** Starts the lesson afresh (the one shown, or the sphere). */
  reset(): void {
    this.start(this.kind);
  }

  /** Switches to a lesson and starts it: the sphere from its icosphere, or the loaded mesh as loaded. */
  start(kind: LessonKind): void {
    const { mode, status, field, draw, send, share } = this.d;
    this.kind = kind;
    const mesh = kind === 'mesh';
    mode.set('mcf');
    byId('sphere-lesson').hidden = mesh;
    byId('mesh-lesson').hidden = !mesh;
    byId('plot').hidden = mesh;
    byId('plot-area').hidden = !mesh;
    byId('lesson-title').textContent = mesh ? `Mean-curvature flow of ${this.meshName || 'the loaded mesh'}` : 'Mean-curvature flow of a sphere';
    byId('tau-warning').hidden = true;
    field.hide();
    status.error(null);
    status.clearReadout();
    this.plot.clear();
    this.areaPlot.clear();
    this.plot.mark(null);
    this.areaPlot.mark(null);
    draw({ type: 'clear-frames' });
    draw({ type: 'target', positions: new Float32Array(0), indices: null });
    draw({ type: 'refit' });
    this.last = null;
    this.asked = false;
    this.shots.clear();
    this.liveStep = -1;
    this.scrubbedAt = null;
    if (mesh) send({ type: 'mcf-mesh-init', tau: Number(byId<HTMLInputElement>('tau-mesh').value) });
    else send({ type: 'mcf-init', params: this.params() });
    status.set('idle', 'Ready');
    share();
  }

  play(): void {
    this.asked = true;
    this.d.status.error(null);
    this.d.send({ type: 'play' });
    this.d.status.set('running', 'Running');
  }

  /** One step. */
  step(): void {
    this.asked = true;
    this.d.send({ type: 'step', n: 1 });
  }

  /** The worker judged τ before the run: a warning next to the input when it is not sensible. */
  advice(a: TauAdvice | MeshTauAdvice): void {
    const warning = byId('tau-warning');
    warning.hidden = a.sensible;
    warning.textContent = a.warning;
    if ('extinctionTime' in a) {
      byId('tau').title = `Sensible: ${a.tauMin.toPrecision(2)} – ${a.tauMax.toPrecision(2)}; this τ takes ${a.steps} steps (the sphere vanishes at t = r₀²/4 = ${a.extinctionTime})`;
    } else {
      byId('tau-mesh').title = `Sensible: ${a.tauMin.toPrecision(2)} – ${a.tauMax.toPrecision(2)}; this τ/D² takes ${a.steps} steps to the lesson's end at t = ${a.horizon}·D²`;
    }
  }

  /** The worker stopped the flow: at its end, on a pause, or cancelled (back to the start). */
  stopped(reason: StopReason): void {
    if (reason !== 'cancelled' && !this.asked) return;
    const s = this.last;
    if (reason === 'finished') {
      let where = '';
      if (s?.lesson === 'sphere') where = ` at t = ${s.time.toPrecision(3)}: mean radius ${s.meanRadius.toFixed(3)}, exact ${s.exactRadius.toFixed(3)}`;
      else if (s) where = ` at t = ${s.relativeTime.toPrecision(3)}·D² (step ${s.step}): area ${pct(s.areaRatio)} of the start${s.volumeRatio === null ? '' : `, volume ${pct(s.volumeRatio)}`}`;
      // The core says why a mesh lesson ended before its horizon (a pinch, a collapse).
      if (s?.lesson === 'mesh' && s.stoppedEarly) this.d.status.set('invalid', s.stoppedEarly);
      else this.d.status.set('done', `Done${where}`);
    } else if (reason === 'cancelled') this.reset();
    else this.d.status.set('paused', 'Paused');
  }

  /** A frame's statistics: the plot and the numbers beside it (a frame of the other lesson, still in flight, is dropped). */
  frame(msg: Frame & { stats: McfStats }): void {
    const s = msg.stats;
    if (s.lesson !== this.kind) return;
    this.last = s;
    const text = s.lesson === 'sphere' ? this.sphere(s) : this.mesh(s);
    const x = s.lesson === 'sphere' ? s.time : s.relativeTime;
    this.shots.set(s.step, { text, x, colour: msg.colour, range: msg.range, coloured: !!msg.colors });
    this.liveStep = s.step;
    byId('stats').textContent = text;
    byId('stats').dataset.step = String(s.step);
    byId('progress').hidden = true;
    byId('progress-text').textContent = '';
    if (msg.playing) this.d.status.set('running', `Running — step ${s.step}`);
    if (this.scrubbedAt !== null) this.scrubbed(this.scrubbedAt); // an earlier frame is still on screen
  }

  /** The scrubber shows the frame of `step` (null: the live end): its numbers, legend and a
   * mark at its time on the plot follow. */
  scrubbed(step: number | null): void {
    this.scrubbedAt = step;
    const shot = this.shots.get(step ?? this.liveStep);
    if (!shot) return;
    byId('stats').textContent = shot.text;
    showLegend(shot.colour, shot.range, shot.coloured);
    const mark = step === null ? null : shot.x;
    if (this.kind === 'sphere') this.plot.mark(mark);
    else this.areaPlot.mark(mark);
  }

  private sphere(s: SphereStats): string {
    this.plot.push(s.time, s.meanRadius, s.exactRadius);
    const err = s.exactRadius > 0 ? (100 * (s.meanRadius - s.exactRadius)) / s.exactRadius : NaN;
    return (
      `step ${s.step}   t = ${s.time.toFixed(4)}\n` +
      `mean radius ${s.meanRadius.toFixed(5)}   exact ${s.exactRadius.toFixed(5)}   (${err.toFixed(3)} %)\n` +
      `co-volume min/mean/max ${s.covolumeMin.toExponential(2)} / ${s.covolumeMean.toExponential(2)} / ${s.covolumeMax.toExponential(2)}\n` +
      `solver ${s.solverIterations} it, residual ${s.solverResidual.toExponential(1)}   ${s.msPerStep.toFixed(2)} ms/step\n` +
      `${s.vertices} vertices, ${s.faces} faces`
    );
  }

  private mesh(s: MeshStats): string {
    // (uPlot leaves a gap for null: an open mesh has no volume.)
    this.areaPlot.push(s.relativeTime, s.areaRatio, s.volumeRatio as number);
    const volume = s.volumeRatio === null ? 'open: no volume' : `volume ${pct(s.volumeRatio)}`;
    const shape = s.closed ? 'closed' : `open, ${s.boundaryVertices} boundary vertices pinned`;
    return (
      `step ${s.step}   t = ${s.relativeTime.toPrecision(3)}·D²   (τ = ${s.tau.toExponential(2)}, D = ${s.diagonal.toPrecision(4)})\n` +
      `area ${pct(s.areaRatio)} of the start   ${volume}\n` +
      `|H| mean ${s.meanAbsH.toPrecision(3)}, max ${s.maxAbsH.toPrecision(3)}   (1/D = ${(1 / s.diagonal).toPrecision(3)})\n` +
      `co-volume min/mean/max ${s.covolumeMin.toExponential(2)} / ${s.covolumeMean.toExponential(2)} / ${s.covolumeMax.toExponential(2)}\n` +
      `solver ${s.solverIterations} it, residual ${s.solverResidual.toExponential(1)}   ${s.msPerStep.toFixed(2)} ms/step\n` +
      `${s.vertices} vertices, ${s.faces} faces, ${shape}`
    );
  }

  /** The plotted series (for tests). */
  series(): ReturnType<RadiusPlot['series']> {
    return this.plot.series();
  }

  /** The mesh lesson's plotted series: t/D², area and volume ratios (for tests). */
  areaSeries(): { t: number[]; area: number[]; volume: number[] } {
    const [t, area, volume] = this.areaPlot.series();
    return { t, area, volume };
  }
}

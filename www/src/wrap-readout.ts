// What a running wrap shows besides the surface: the progress bar, the step statistics and the
// per-step plots (distance, co-volume, vertices, κ histogram); and the control curves ε(δ), η(δ)
// of the chosen settings, which the worker computes whenever the settings change.
import { byId } from './dom';
import { HistogramPlot, LinePlot } from './plots';
import type { Certificate, ControlCurves, Frame } from './protocol';
import { describePhases } from './stopwatch';
import { TopologyTimeline, type TimelineState } from './topology';

/** The elements around the plots that describe a run (the progress bar and line, the step
 * statistics, the input's description, the legend and the surgery line). */
const SHOWN_IDS = ['progress', 'progress-text', 'stats', 'target-info', 'legend'];

/** What one of them shows: its text (none for an element with children), tooltip, visibility,
 * data attributes and a progress bar's value. */
interface Shown {
  el: HTMLElement;
  text: string | null;
  title: string;
  hidden: boolean;
  data: Record<string, string | undefined>;
  value: [number, number] | null;
}

function look(el: HTMLElement): Shown {
  const value: [number, number] | null = el instanceof HTMLProgressElement ? [el.value, el.max] : null;
  return { el, text: el.childElementCount ? null : el.textContent, title: el.title, hidden: el.hidden, data: { ...el.dataset }, value };
}

function putBack(s: Shown): void {
  if (s.text !== null) s.el.textContent = s.text;
  s.el.title = s.title;
  s.el.hidden = s.hidden;
  for (const k of Object.keys(s.el.dataset)) delete s.el.dataset[k];
  Object.assign(s.el.dataset, s.data);
  if (s.value && s.el instanceof HTMLProgressElement) [s.el.max, s.el.value] = [s.value[1], s.value[0]];
}

/** A readout as shown, set aside while a new run shows its own. */
interface ReadoutState {
  lines: number[][][];
  kappa: number[][];
  topology: TimelineState;
  shown: Shown[];
  where: string;
}

export class WrapReadout {
  // Titles fit the narrowest plot (175 px); each host's tooltip (index.html) says more.
  private readonly distance = new LinePlot(byId('plot-distance'), 'Distance to target', ['mean |d|', 'max |d|'], ['#4aa3ff', '#ff7a59'], { log: true });
  private readonly covolume = new LinePlot(byId('plot-covolume'), 'Co-volume', ['min', 'mean', 'max'], ['#ff7a59', '#4aa3ff', '#9fd39f'], { log: true });
  private readonly vertices = new LinePlot(byId('plot-vertices'), 'Vertices', ['vertices'], ['#ffb347']);
  private readonly kappa = new HistogramPlot(byId('plot-kappa'), 'Quality κ(J_Δ)', 'κ (1 = equilateral)');
  private readonly controls = new LinePlot(byId('plot-controls'), 'Controls ε(δ), η(δ)', ['ε', 'η facing', 'η side-on'], ['#4aa3ff', '#ffb347', '#ff7a59'], { xLabel: 'δ = d − d₀' });

  /** The progress line's step and vertex count, from the last frame. */
  private where = '';

  /** Genus per step and surgery events, for the scrubber and the health badge. */
  readonly topology = new TopologyTimeline();

  /** The kept result's readout while a new run shows its own; null when none is set aside. */
  private aside: ReadoutState | null = null;

  /** Sets what is shown aside (it is the kept result's): a run that fails puts it back. */
  setAside(): void {
    const lines = [this.distance, this.covolume, this.vertices].map((p) => p.series());
    this.aside = { lines, kappa: this.kappa.bars(), topology: this.topology.snapshot(), shown: SHOWN_IDS.map((id) => look(byId(id))), where: this.where };
  }

  /** Shows again what was set aside (the kept result's readout); false when nothing was. */
  restore(): boolean {
    const a = this.aside;
    if (!a) return false;
    [this.distance, this.covolume, this.vertices].forEach((p, i) => p.set(a.lines[i]));
    this.kappa.put(a.kappa);
    this.topology.put(a.topology);
    a.shown.forEach(putBack);
    this.where = a.where;
    return true;
  }

  /** Empties the per-step plots for a new run. */
  clear(): void {
    this.topology.clear();
    this.distance.clear();
    this.covolume.clear();
    this.vertices.clear();
    this.kappa.clear();
  }

  /** A wrap frame: progress, statistics and the reports of the steps since the last frame. */
  frame(msg: Frame): void {
    const r = msg.report;
    if (msg.histogram) this.kappa.set(msg.histogram.lo, msg.histogram.hi, msg.histogram.counts);
    const limit = msg.stepLimit ?? 0;
    const el = ((msg.elapsedMs ?? 0) / 1000).toFixed(1);
    const p = byId<HTMLProgressElement>('progress');
    p.hidden = false;
    p.max = Math.max(1, limit);
    p.value = r?.step ?? 0;
    const verts = r?.vertices ?? msg.positions.length / 3;
    this.where = `step ${r?.step ?? 0}/${limit} · ${verts} vertices`;
    byId('progress-text').textContent = `${this.where} · ${el} s`;
    byId('stats').dataset.step = String(r?.step ?? 0);
    this.topology.add(msg.reports ?? []);
    for (const q of msg.reports ?? []) {
      this.distance.push(q.step, Math.max(1e-9, q.distance_mean), Math.max(1e-9, q.distance_max));
      this.covolume.push(q.step, Math.max(1e-12, q.covolume_min), q.covolume_mean, q.covolume_max);
      this.vertices.push(q.step, q.vertices);
    }
    if (r) {
      byId('stats').textContent =
        `step ${r.step}   τ = ${r.tau.toPrecision(3)}${r.retries ? ` (${r.retries} retries)` : ''}\n` +
        `field distance mean ${r.distance_mean.toExponential(2)}  max ${r.distance_max.toExponential(2)}\n` +
        `settled ${(100 * r.settled_fraction).toFixed(1)} %   ${r.vertices} vertices, ${r.faces} faces\n` +
        `ms: assembly ${r.times.assembly.toFixed(0)}  solve ${r.times.solve.toFixed(0)}  remesh ${r.times.remesh.toFixed(0)}  total ${r.times.total.toFixed(0)}`;
    }
  }

  /** The run completed in `ms` of work: the progress line gives the total, and a line that
   * opens below the header says where the time went (every phase in the tooltip). */
  timed(ms: number, phases: [string, number][]): void {
    const line = byId('progress-text');
    const summary = describePhases(phases);
    line.textContent = `${this.where} · ${(ms / 1000).toFixed(1)} s`;
    line.title = phases.map(([p, ms]) => `${p}: ${Math.round(ms)} ms`).join('\n');
    line.dataset.phases = JSON.stringify(phases.map(([p, ms]) => [p, Math.round(ms)]));
    byId('phase-times').textContent = summary ? `where the time went: ${summary}` : '';
    byId('progress').hidden = true; // full: the line says it all
    byId('phases-toggle').hidden = !summary;
  }

  /** The result's own distance to the target (the certificate's exact measure) in place of the
   * field's, which the steps read. */
  exact(c: Certificate): void {
    const stats = byId('stats');
    const lines = (stats.textContent ?? '').split('\n');
    if (lines.length < 2 || c.distance_max === undefined || c.distance_max === null) return;
    const f = c.faithfulness;
    const spacings = f ? `  (${f.distance_max_spacings.toFixed(1)} local spacings; p99 ${f.distance_p99_spacings.toFixed(2)})` : '';
    lines[1] = `distance to the target max ${c.distance_max.toExponential(2)}${spacings}`;
    stats.textContent = lines.join('\n');
  }

  curves(c: ControlCurves): void {
    this.controls.set([c.delta, c.epsilon, c.eta_facing, c.eta_side]);
  }

  distanceSeries(): ReturnType<LinePlot['series']> {
    return this.distance.series();
  }

  controlSeries(): ReturnType<LinePlot['series']> {
    return this.controls.series();
  }
}

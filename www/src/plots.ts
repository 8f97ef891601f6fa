// The live plots: the lesson's radius against the exact law r(t) = sqrt(r0² − 4t), the wrap's
// per-step lines and the κ histogram. Each is as wide as its host element, which the style
// sheet sizes (#plots: one row that shares the view's width, scrolling sideways when narrow).
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { tickLabel } from './ticks';

/** Redraws waiting for a frame, at most one per plot (the latest wins). One runs per animation
 * frame, and DRAW_GAP_MS apart: several uPlot redraws and the page's layout in one frame made
 * main-thread tasks of over 100 ms on a loaded 2-core machine; one redraw is a few milliseconds. */
const pendingDraws = new Map<object, () => void>();
const DRAW_GAP_MS = 60;
let lastDrawAt = -Infinity;
let scheduled = false;

/** Queues `draw` under `key` (a plot for its data, its host element for its size). */
function drawLater(key: object, draw: () => void): void {
  pendingDraws.set(key, draw);
  scheduleDraw();
}

function scheduleDraw(): void {
  if (scheduled || pendingDraws.size === 0) return;
  scheduled = true;
  const wait = Math.max(0, lastDrawAt + DRAW_GAP_MS - performance.now());
  setTimeout(() => requestAnimationFrame(drawOne), wait);
}

function drawOne(now: number): void {
  scheduled = false;
  lastDrawAt = now;
  const next = pendingDraws.entries().next();
  if (!next.done) {
    const [key, draw] = next.value;
    pendingDraws.delete(key);
    draw();
  }
  scheduleDraw();
}

/** Keeps `plot` as wide as `el` (uPlot draws at a fixed pixel size). */
function followWidth(el: HTMLElement, plot: uPlot, height: number): void {
  let last = 0;
  new ResizeObserver(() => {
    const w = Math.floor(el.clientWidth);
    if (w > 0 && w !== last) {
      last = w;
      drawLater(el, () => plot.setSize({ width: w, height }));
    }
  }).observe(el);
}

/** A vertical line at x = `at()` (the scrubbed frame's time), drawn over the plot when set. */
function markerHook(at: () => number | null): uPlot.Hooks.Arrays {
  const draw = (u: uPlot) => {
    const x = at();
    if (x === null) return;
    const px = u.valToPos(x, 'x', true);
    const ctx = u.ctx;
    ctx.save();
    ctx.strokeStyle = '#e6e6e6';
    ctx.setLineDash([4, 3]);
    ctx.beginPath();
    ctx.moveTo(px, u.bbox.top);
    ctx.lineTo(px, u.bbox.top + u.bbox.height);
    ctx.stroke();
    ctx.restore();
  };
  return { draw: [draw] };
}

/** Marks x on `plot` (null: no mark); the host's data-marker says where, for scripts. */
function setMark(el: HTMLElement, plot: uPlot, x: number | null): void {
  if (x === null) delete el.dataset.marker;
  else el.dataset.marker = String(x);
  drawLater(plot, () => plot.redraw(false));
}

export class RadiusPlot {
  private readonly t: number[] = [];
  private readonly mesh: number[] = [];
  private readonly exact: number[] = [];
  private readonly plot: uPlot;
  private marked: number | null = null;

  constructor(private readonly el: HTMLElement) {
    this.plot = new uPlot(
      {
        hooks: markerHook(() => this.marked),
        width: 340,
        height: 170,
        title: 'Mean radius vs exact √(r₀² − 4t)',
        scales: { x: { time: false } },
        axes: [{ label: 't', stroke: '#9aa3b2', grid: { stroke: '#2c303a' } }, { stroke: '#9aa3b2', grid: { stroke: '#2c303a' } }],
        series: [
          { label: 't' },
          { label: 'mesh', stroke: '#4aa3ff', width: 2 },
          { label: 'exact', stroke: '#ffb347', width: 1.5, dash: [6, 4] },
        ],
      },
      [[], [], []],
      el,
    );
    followWidth(el, this.plot, 170);
  }

  clear(): void {
    this.t.length = this.mesh.length = this.exact.length = 0;
    drawLater(this.plot, () => this.plot.setData([[], [], []]));
  }

  push(t: number, mesh: number, exact: number): void {
    if (this.t.length && t <= this.t[this.t.length - 1]) return;
    this.t.push(t);
    this.mesh.push(mesh);
    this.exact.push(exact);
    drawLater(this.plot, () => this.plot.setData([this.t, this.mesh, this.exact]));
  }

  /** Marks time `t` (the scrubbed frame's); null removes the mark. */
  mark(t: number | null): void {
    this.marked = t;
    setMark(this.el, this.plot, t);
  }

  /** The plotted series, for tests and export. */
  series(): { t: number[]; mesh: number[]; exact: number[] } {
    return { t: [...this.t], mesh: [...this.mesh], exact: [...this.exact] };
  }
}

const AXIS = { stroke: '#9aa3b2', grid: { stroke: '#2c303a' }, ticks: { stroke: '#2c303a' } };

const tickLabels = (_u: uPlot, ticks: (number | null)[]): string[] => ticks.map(tickLabel);

/** A small line plot over a shared x (step) axis; data arrive one row at a time. */
export class LinePlot {
  private readonly cols: number[][];
  private readonly plot: uPlot;
  private marked: number | null = null;

  constructor(private readonly el: HTMLElement, title: string, labels: string[], colours: string[], opts: { log?: boolean; width?: number; height?: number; xLabel?: string } = {}) {
    this.cols = [[], ...labels.map(() => [])];
    this.plot = new uPlot(
      {
        hooks: markerHook(() => this.marked),
        width: opts.width ?? 262,
        height: opts.height ?? 170,
        title,
        scales: { x: { time: false }, y: opts.log ? { distr: 3 } : {} },
        // Three significant digits: uPlot's default rounds ticks 0.0005 apart to 0.001, 0.001, …
        axes: [{ ...AXIS, label: opts.xLabel ?? 'step', values: tickLabels }, { ...AXIS, size: 56, values: tickLabels }],
        series: [{ label: opts.xLabel ?? 'step' }, ...labels.map((label, i) => ({ label, stroke: colours[i], width: 1.5 }))],
        legend: { live: false },
      },
      this.cols as uPlot.AlignedData,
      el,
    );
    followWidth(el, this.plot, opts.height ?? 170);
  }

  clear(): void {
    for (const c of this.cols) c.length = 0;
    this.redraw();
  }

  push(x: number, ...ys: number[]): void {
    const xs = this.cols[0];
    if (xs.length && x <= xs[xs.length - 1]) return;
    xs.push(x);
    ys.forEach((y, i) => this.cols[i + 1].push(y));
    this.redraw();
  }

  private redraw(): void {
    drawLater(this.plot, () => this.plot.setData(this.cols as uPlot.AlignedData));
  }

  /** Replaces all data (x plus one column per series). */
  set(cols: number[][]): void {
    cols.forEach((c, i) => (this.cols[i] = c.slice()));
    this.redraw();
  }

  series(): number[][] {
    return this.cols.map((c) => [...c]);
  }

  /** Marks x (the scrubbed frame's); null removes the mark. */
  mark(x: number | null): void {
    this.marked = x;
    setMark(this.el, this.plot, x);
  }
}

/** Bars of a histogram (counts per bin, from the core). */
export class HistogramPlot {
  private readonly plot: uPlot;
  private data: number[][] = [[], []];

  constructor(el: HTMLElement, title: string, xLabel: string) {
    this.plot = new uPlot(
      {
        width: 262,
        height: 170,
        title,
        scales: { x: { time: false } },
        axes: [{ ...AXIS, label: xLabel }, { ...AXIS, size: 56 }],
        series: [{ label: xLabel }, { label: 'triangles', stroke: '#4aa3ff', fill: 'rgba(74,163,255,0.45)', paths: uPlot.paths.bars!({ size: [0.9, 40] }) }],
        legend: { live: false },
      },
      this.data as uPlot.AlignedData,
      el,
    );
    followWidth(el, this.plot, 170);
  }

  set(lo: number, hi: number, counts: number[]): void {
    const w = (hi - lo) / Math.max(1, counts.length);
    this.data = [counts.map((_, i) => lo + (i + 0.5) * w), counts.slice()];
    this.redraw();
  }

  clear(): void {
    this.data = [[], []];
    this.redraw();
  }

  /** The bars shown (bin centres, counts), to put back with `put`. */
  bars(): number[][] {
    return this.data.map((c) => [...c]);
  }

  put(data: number[][]): void {
    this.data = data.map((c) => [...c]);
    this.redraw();
  }

  private redraw(): void {
    const data = this.data;
    drawLater(this.plot, () => this.plot.setData(data as uPlot.AlignedData));
  }
}

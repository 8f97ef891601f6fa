// Live plot of the mean radius against the exact law r(t) = sqrt(r0² − 4t).
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';

export class RadiusPlot {
  private readonly t: number[] = [];
  private readonly mesh: number[] = [];
  private readonly exact: number[] = [];
  private readonly plot: uPlot;

  constructor(el: HTMLElement) {
    this.plot = new uPlot(
      {
        width: 340,
        height: 220,
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
  }

  clear(): void {
    this.t.length = this.mesh.length = this.exact.length = 0;
    this.plot.setData([[], [], []]);
  }

  push(t: number, mesh: number, exact: number): void {
    if (this.t.length && t <= this.t[this.t.length - 1]) return;
    this.t.push(t);
    this.mesh.push(mesh);
    this.exact.push(exact);
    this.plot.setData([this.t, this.mesh, this.exact]);
  }

  /** The plotted series, for tests and export. */
  series(): { t: number[]; mesh: number[]; exact: number[] } {
    return { t: [...this.t], mesh: [...this.mesh], exact: [...this.exact] };
  }
}

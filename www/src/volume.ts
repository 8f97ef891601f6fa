// The volume panel: a histogram of the voxel values with a draggable iso-value marker (Otsu
// pre-selected), and three orthogonal slices with the iso contour. It only draws what the worker
// computed (VolumeView in the core) and reports the user's choices; no numerics beyond mapping
// values to grey levels.
import type { VolumeInfo, VolumeSliceMsg } from './protocol';

/** What the panel asks of the page. */
export interface VolumeCallbacks {
  /** The iso-value or the volume of a 4-D file was chosen (on release of the marker, Enter in
   * the field, or a frame change). */
  onIso: (iso: number, frame: number) => void;
  /** A slice is wanted: index axis 0, 1 or 2 at voxel `index`. */
  onSlice: (axis: number, index: number) => void;
}

const AXES = ['x', 'y', 'z'];

export class VolumePanel {
  private info: VolumeInfo | null = null;
  private iso = 0;
  private hist: { min: number; max: number; counts: Float64Array } | null = null;
  private readonly histCanvas: HTMLCanvasElement;
  private readonly isoInput: HTMLInputElement;
  private readonly label: HTMLElement;
  private readonly frameRow: HTMLElement;
  private readonly frameInput: HTMLInputElement;
  private readonly sliceCanvases: HTMLCanvasElement[] = [];
  private readonly sliceRanges: HTMLInputElement[] = [];
  private readonly slices: (VolumeSliceMsg | null)[] = [null, null, null];
  private dragging = false;

  constructor(private readonly root: HTMLElement, private readonly cb: VolumeCallbacks) {
    root.classList.add('volume-panel');
    root.innerHTML = '';
    this.label = el('div', 'volume-label');
    root.append(this.label);
    this.histCanvas = el('canvas', 'volume-hist') as HTMLCanvasElement;
    this.histCanvas.width = 320;
    this.histCanvas.height = 90;
    this.histCanvas.title = 'Voxel-value histogram (log counts); drag the marker to choose the iso-value';
    root.append(this.histCanvas);
    const row = el('label', 'volume-iso');
    row.textContent = 'iso-value ';
    this.isoInput = document.createElement('input');
    this.isoInput.type = 'number';
    this.isoInput.step = 'any';
    this.isoInput.id = 'volume-iso';
    row.append(this.isoInput);
    root.append(row);
    this.frameRow = el('label', 'volume-frame');
    this.frameRow.textContent = 'volume (4-D file) ';
    this.frameInput = document.createElement('input');
    this.frameInput.type = 'number';
    this.frameInput.min = '1';
    this.frameInput.step = '1';
    this.frameInput.id = 'volume-frame';
    this.frameRow.append(this.frameInput);
    this.frameRow.hidden = true;
    root.append(this.frameRow);
    this.frameInput.addEventListener('change', () => {
      const n = Math.round(Number(this.frameInput.value));
      if (this.info && n >= 1 && n <= this.info.frames) this.cb.onIso(this.iso, n - 1);
    });
    const grid = el('div', 'volume-slices');
    for (let a = 0; a < 3; a++) {
      const box = el('div', 'volume-slice');
      const c = el('canvas') as HTMLCanvasElement;
      c.title = `Slice normal to ${AXES[a]} with the iso contour`;
      const r = document.createElement('input');
      r.type = 'range';
      r.min = '0';
      r.addEventListener('input', () => this.cb.onSlice(a, Number(r.value)));
      box.append(c, r);
      grid.append(box);
      this.sliceCanvases.push(c);
      this.sliceRanges.push(r);
    }
    root.append(grid);
    this.isoInput.addEventListener('change', () => {
      const v = Number(this.isoInput.value);
      if (Number.isFinite(v)) this.choose(v);
    });
    const toIso = (e: PointerEvent) => {
      if (!this.hist) return this.iso;
      const r = this.histCanvas.getBoundingClientRect();
      const t = Math.min(1, Math.max(0, (e.clientX - r.left) / Math.max(1, r.width)));
      return this.hist.min + t * (this.hist.max - this.hist.min);
    };
    this.histCanvas.addEventListener('pointerdown', (e) => {
      this.dragging = true;
      this.histCanvas.setPointerCapture(e.pointerId);
      this.setIso(toIso(e));
    });
    this.histCanvas.addEventListener('pointermove', (e) => {
      if (this.dragging) this.setIso(toIso(e));
    });
    this.histCanvas.addEventListener('pointerup', (e) => {
      if (!this.dragging) return;
      this.dragging = false;
      this.choose(toIso(e));
    });
    root.hidden = true;
  }

  /** Shows a newly read volume: its facts, histogram, the iso-value in use, and mid slices. */
  show(info: VolumeInfo, histogram: { min: number; max: number; counts: Float64Array }, iso: number): void {
    this.info = info;
    this.hist = histogram;
    this.root.hidden = false;
    const [nx, ny, nz] = info.dims;
    const vs = info.voxelSize.map((v) => v.toPrecision(3)).join(' × ');
    this.label.textContent =
      `${info.format} ${nx}×${ny}×${nz} voxels of ${vs} mm, ${info.datatype}, values ${fmt(info.min)}…${fmt(info.max)}` +
      (info.frames > 1 ? `, volume ${info.frameIndex + 1} of ${info.frames}` : '') +
      `; Otsu ${info.otsu === undefined ? '—' : fmt(info.otsu)}; frame: ${info.frame}`;
    this.frameRow.hidden = info.frames < 2;
    this.frameInput.max = String(info.frames);
    this.frameInput.value = String(info.frameIndex + 1);
    for (let a = 0; a < 3; a++) {
      this.sliceRanges[a].max = String(info.dims[a] - 1);
      this.sliceRanges[a].value = String(Math.floor(info.dims[a] / 2));
      this.slices[a] = null;
      this.cb.onSlice(a, Math.floor(info.dims[a] / 2));
    }
    this.setIso(iso);
  }

  hide(): void {
    this.root.hidden = true;
    this.info = null;
  }

  /** A slice arrived from the worker. */
  slice(s: VolumeSliceMsg): void {
    if (!this.info || s.axis < 0 || s.axis > 2) return;
    this.slices[s.axis] = s;
    this.drawSlice(s.axis);
  }

  /** The iso-value currently marked. */
  value(): number {
    return this.iso;
  }

  private choose(iso: number): void {
    this.setIso(iso);
    this.cb.onIso(this.iso, this.info?.frameIndex ?? 0);
  }

  private setIso(iso: number): void {
    this.iso = iso;
    this.isoInput.value = String(Number(iso.toPrecision(6)));
    this.histCanvas.dataset.iso = String(iso);
    this.drawHistogram();
    for (let a = 0; a < 3; a++) this.drawSlice(a);
  }

  private drawHistogram(): void {
    const h = this.hist;
    const ctx = this.histCanvas.getContext('2d');
    if (!h || !ctx) return;
    const { width: w, height: ht } = this.histCanvas;
    ctx.clearRect(0, 0, w, ht);
    let top = 0;
    for (const c of h.counts) top = Math.max(top, Math.log1p(c));
    const bw = w / h.counts.length;
    ctx.fillStyle = '#4aa3ff';
    h.counts.forEach((c, i) => {
      const y = top > 0 ? (Math.log1p(c) / top) * (ht - 4) : 0;
      ctx.fillRect(i * bw, ht - y, Math.max(1, bw), y);
    });
    const span = h.max - h.min || 1;
    const x = ((this.iso - h.min) / span) * w;
    ctx.fillStyle = '#ff7a59';
    ctx.fillRect(Math.round(x) - 1, 0, 3, ht);
  }

  private drawSlice(axis: number): void {
    const s = this.slices[axis];
    const c = this.sliceCanvases[axis];
    if (!s || !this.info) return;
    const { width: w, height: h, values } = s;
    if (c.width !== w || c.height !== h) {
      c.width = w;
      c.height = h;
    }
    const ctx = c.getContext('2d');
    if (!ctx || w === 0 || h === 0) return;
    const img = ctx.createImageData(w, h);
    const lo = this.info.min;
    const span = this.info.max - lo || 1;
    const iso = this.iso;
    // Rows from the top: flip v so that the higher index is up.
    for (let v = 0; v < h; v++) {
      for (let u = 0; u < w; u++) {
        const k = u + w * v;
        const val = values[k];
        const o = 4 * (u + w * (h - 1 - v));
        // The iso contour: a pixel whose right or upper neighbour lies on the other side.
        const side = val > iso;
        const edge = (u + 1 < w && values[k + 1] > iso !== side) || (v + 1 < h && values[k + w] > iso !== side);
        if (edge) {
          img.data[o] = 255;
          img.data[o + 1] = 122;
          img.data[o + 2] = 89;
        } else {
          const g = Math.max(0, Math.min(255, Math.round((255 * (val - lo)) / span)));
          img.data[o] = img.data[o + 1] = img.data[o + 2] = g;
        }
        img.data[o + 3] = 255;
      }
    }
    ctx.putImageData(img, 0, 0);
  }
}

function el(tag: string, cls?: string): HTMLElement {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  return e;
}

function fmt(x: number): string {
  return Math.abs(x) >= 1e4 || (Math.abs(x) < 1e-2 && x !== 0) ? x.toExponential(2) : String(Number(x.toPrecision(4)));
}

// The Distance field fieldset: a slice of the target's distance field or one of its isosurfaces,
// computed in the worker and drawn by the render worker. Shown once a wrap's target is loaded.
import { byId } from './dom';
import type { Draw, FieldView, FromWorker, Send } from './protocol';

/** What the field view shows now (read by tests through window.__lsw.fieldShown). */
export interface FieldShown {
  view: FieldView;
  label: string;
  width: number;
  height: number;
  triangles: number;
}

const NOTHING: FieldShown = { view: 'off', label: '', width: 0, height: 0, triangles: 0 };

export class FieldControls {
  shown: FieldShown = { ...NOTHING };
  private readonly select = byId<HTMLSelectElement>('field-view');
  private readonly position = byId<HTMLInputElement>('field-t');

  constructor(private readonly draw: Draw, private readonly send: Send) {
    this.select.onchange = () => {
      byId('field-t-name').textContent = this.view() === 'iso' ? 'Level' : 'Position';
      this.request();
    };
    // Slices are cheap (one node plane): follow the slider; isosurfaces run marching cubes: on release.
    this.position.oninput = () => {
      if (this.view() !== 'iso' && this.view() !== 'off') this.request();
    };
    this.position.onchange = () => {
      if (this.view() === 'iso') this.request();
    };
  }

  private view(): FieldView {
    return this.select.value as FieldView;
  }

  /** Asks the worker for the chosen view (again after it was restarted). */
  request(): void {
    this.send({ type: 'field', view: this.view(), t: Number(this.position.value) });
  }

  /** A target is loaded: its field can be shown. */
  reveal(): void {
    byId('field-box').hidden = false;
  }

  /** Hides the control and clears what it drew (the lesson has no target). */
  hide(): void {
    byId('field-box').hidden = true;
    byId('field-legend').hidden = true;
    this.draw({ type: 'field' });
    this.shown = { ...NOTHING };
  }

  /** Draws what the worker computed (its buffers are transferred to the render worker). */
  show(msg: Extract<FromWorker, { type: 'field' }>): void {
    const transfer: Transferable[] = [];
    if (msg.slice) transfer.push(msg.slice.corners.buffer, msg.slice.rgba.buffer);
    if (msg.iso) transfer.push(msg.iso.positions.buffer, msg.iso.indices.buffer);
    this.shown = { view: msg.view, label: msg.label, width: msg.slice?.width ?? 0, height: msg.slice?.height ?? 0, triangles: (msg.iso?.indices.length ?? 0) / 3 };
    this.draw({ type: 'field', slice: msg.slice, iso: msg.iso }, transfer);
    byId('field-label').textContent = msg.label;
    byId('field-legend').hidden = !msg.slice;
    byId('field-min').textContent = msg.range[0].toPrecision(3);
    byId('field-max').textContent = msg.range[1].toPrecision(3);
  }
}

// The camera and the View fieldset. The render worker owns the camera; the page turns pointer,
// wheel and double-click into orbit messages and remembers the view (angles, zoom, wireframe,
// shading, colour map) so that a share link can carry it.
import { byId } from './dom';
import type { ColourMap, Draw, Send } from './protocol';
import { DEFAULT_VIEW, type ViewState } from './share';

/** Drag orbits, the wheel zooms, a double-click refits the camera to the surface. */
export function bindOrbit(canvas: HTMLCanvasElement, draw: Draw): void {
  let dragging: { x: number; y: number } | null = null;
  canvas.addEventListener('pointerdown', (e) => {
    dragging = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!dragging) return;
    draw({ type: 'rotate', dx: e.clientX - dragging.x, dy: e.clientY - dragging.y });
    dragging = { x: e.clientX, y: e.clientY };
  });
  canvas.addEventListener('pointerup', () => (dragging = null));
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    draw({ type: 'zoom', factor: Math.exp(e.deltaY * 0.001) });
  }, { passive: false });
  canvas.addEventListener('dblclick', () => draw({ type: 'refit' }));
}

/** Orbit angles (yaw, pitch) of the view buttons; the camera's pitch stops short of ±π/2. */
const VIEWS: Record<string, [number, number]> = { front: [0, 0], side: [Math.PI / 2, 0], top: [0, 1.5] };

export class ViewControls {
  /** The view as a share link has it. */
  view: ViewState = { ...DEFAULT_VIEW };
  /** The colour map last chosen (by the user or a link); shown whenever the menu offers it. */
  private wanted = DEFAULT_VIEW.cmap;
  private readonly cmap = byId<HTMLSelectElement>('cmap');
  /** The colour menu offered now (it depends on the mode). */
  private menu: [string, string][] = [];

  /** The user ticked or cleared Show target: their choice stands over a run's. */
  private targetChosen = false;

  /** `send` gets the colour map (the computation worker colours the vertices); `changed` runs after every change of the view. */
  constructor(private readonly draw: Draw, private readonly send: Send, private readonly changed: () => void) {
    byId('fit').onclick = () => draw({ type: 'fit' });
    for (const b of document.querySelectorAll<HTMLButtonElement>('[data-view]')) {
      const [yaw, pitch] = VIEWS[b.dataset.view!];
      b.onclick = () => draw({ type: 'look', yaw, pitch });
    }
    byId<HTMLInputElement>('wireframe').onchange = (e) => {
      this.view.wire = (e.target as HTMLInputElement).checked;
      draw({ type: 'wireframe', on: this.view.wire });
      changed();
    };
    byId<HTMLInputElement>('smooth').onchange = (e) => {
      this.view.smooth = (e.target as HTMLInputElement).checked;
      draw({ type: 'smooth', on: this.view.smooth });
      changed();
    };
    byId<HTMLInputElement>('show-target').onchange = (e) => {
      this.targetChosen = true;
      draw({ type: 'show-target', on: (e.target as HTMLInputElement).checked });
    };
    this.cmap.onchange = () => {
      this.wanted = this.cmap.value;
      this.show(this.cmap.value);
    };
  }

  /** The target overlay as a run wants it (on while wrapping, off once done, where it would
   * cover the result), unless the user chose it with the checkbox. */
  targetOverlay(on: boolean): void {
    if (this.targetChosen) return;
    byId<HTMLInputElement>('show-target').checked = on;
    this.draw({ type: 'show-target', on });
  }

  /** The render worker moved the camera. */
  camera(yaw: number, pitch: number, zoom: number): void {
    this.view = { ...this.view, yaw, pitch, zoom };
    this.changed();
  }

  /**
   * Offers a menu of colour maps (value, label): the wanted map if it is there, else the menu's
   * first, so the menu, the legend and the worker always agree.
   */
  offer(items: [string, string][]): void {
    if (!items.length) return;
    this.menu = items;
    this.cmap.replaceChildren(...items.map(([value, label]) => new Option(label, value)));
    const v = items.some(([x]) => x === this.wanted) ? this.wanted : items[0][0];
    this.cmap.value = v;
    if (v !== this.view.cmap) this.show(v);
  }

  /** Shows the map a result's verdict points at (null: the map last chosen again), without
   * making it the user's choice. */
  highlight(map: string | null): void {
    const v = map ?? this.wanted;
    if (v === this.view.cmap || !this.menu.some(([x]) => x === v)) return;
    this.cmap.value = v;
    this.show(v);
  }

  private show(map: string): void {
    this.view.cmap = map;
    this.sendColour();
    this.changed();
  }

  /** Takes a view from a share link: the controls show it, both workers get it. */
  apply(view: ViewState): void {
    this.view = view;
    this.wanted = view.cmap;
    byId<HTMLInputElement>('wireframe').checked = view.wire;
    byId<HTMLInputElement>('smooth').checked = view.smooth;
    if (this.menu.length) this.offer(this.menu);
    else this.cmap.value = view.cmap;
    this.draw({ type: 'wireframe', on: view.wire });
    this.draw({ type: 'smooth', on: view.smooth });
    this.draw({ type: 'set-view', yaw: view.yaw, pitch: view.pitch, zoom: view.zoom });
    this.sendColour();
  }

  /** Tells the computation worker the colour map (again after it was restarted). */
  sendColour(): void {
    this.send({ type: 'colour', map: this.view.cmap as ColourMap });
  }
}

// A worker frame onto the page: the surface goes to the render worker (its buffers transferred,
// so the frame's arrays are empty afterwards; it records them for the scrubber) and the colour
// legend follows the colour map.
import { byId } from './dom';
import { legends } from './catalog-ui';
import type { Draw, Frame } from './protocol';

/** Draws and records a frame and shows its legend. */
export function drawFrame(draw: Draw, msg: Frame): void {
  const transfer: Transferable[] = [msg.positions.buffer, msg.normals.buffer];
  if (msg.indices) transfer.push(msg.indices.buffer);
  if (msg.colors) transfer.push(msg.colors.buffer);
  const step = msg.mode === 'mcf' ? msg.stats?.step ?? 0 : msg.report?.step ?? 0;
  draw({ type: 'geometry', positions: msg.positions, normals: msg.normals, indices: msg.indices, colors: msg.colors, step, record: true, final: !!msg.report?.done || !!msg.final }, transfer);
  showLegend(msg.colour, msg.range, !!msg.colors);
}

/** The legend of colour map `colour` over `range` (hidden for plain shading). */
export function showLegend(colour: string, range: [number, number], coloured: boolean): void {
  byId('legend').hidden = !coloured;
  byId('legend-title').textContent = legends[colour] ?? colour;
  // A value a billionth of the range's size is rounding noise of zero ("2.216e-16" said nothing).
  const tiny = 1e-9 * Math.max(Math.abs(range[0]), Math.abs(range[1]));
  const shown = (v: number) => (Math.abs(v) <= tiny ? '0' : v.toPrecision(4));
  byId('legend-min').textContent = shown(range[0]);
  byId('legend-max').textContent = shown(range[1]);
}

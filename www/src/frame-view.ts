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
  byId('legend').hidden = !msg.colors;
  byId('legend-title').textContent = legends[msg.colour] ?? msg.colour;
  byId('legend-min').textContent = msg.range[0].toPrecision(4);
  byId('legend-max').textContent = msg.range[1].toPrecision(4);
}

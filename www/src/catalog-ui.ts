// The page's lists come from the core's catalog (src/wasm/catalog.rs): the file types the picker
// accepts, the preset menu, the colour-map menus (wrap and lesson), the export buttons and the
// legend titles. Nothing
// here names a format, preset or colour map.
import { byId } from './dom';
import type { Catalog } from './protocol';

/** Legend titles by colour-map name (filled by `applyCatalog`). */
export const legends: Record<string, string> = { none: '' };

/** The colour menu of each mode: (value, label) pairs, 'none' last (filled by `applyCatalog`). */
const colourMenus: Record<'wrap' | 'mcf', [string, string][]> = { wrap: [], mcf: [] };

/** Replaces `select`'s options with `items` (value, label), keeping the current value if it is still offered. */
function fill(select: HTMLSelectElement, items: [string, string][]): void {
  const keep = select.value;
  select.replaceChildren(...items.map(([value, label]) => new Option(label, value)));
  if (items.some(([v]) => v === keep)) select.value = keep;
}

/** Fills the page's lists from `c`. */
export function applyCatalog(c: Catalog): void {
  const readable = c.formats.filter((f) => f.read).flatMap((f) => f.extensions);
  // `nii.gz` is one extension to the core; the picker matches on the last dot.
  byId<HTMLInputElement>('file').accept = [...new Set(readable.map((e) => '.' + e.split('.').pop()))].join(',');
  fill(byId<HTMLSelectElement>('preset'), c.presets.map((p, i) => [p, c.presetLabels[i] ?? p]));
  const item = (m: Catalog['colourMaps'][number]): [string, string] => [m.name, m.label];
  colourMenus.wrap = [...c.colourMaps.map(item), ['none', 'none']];
  colourMenus.mcf = [...c.colourMaps.filter((m) => c.lessonColourMaps.includes(m.name)).map(item), ['none', 'none']];
  for (const m of c.colourMaps) legends[m.name] = m.legend;
  const labels = new Map(c.formats.map((f) => [f.name, f.label]));
  byId('drop').textContent = `Drop to wrap: ${[...new Set(c.formats.filter((f) => f.read).map((f) => f.label))].join(', ')}`;
  byId('exports').replaceChildren(
    ...c.exportFormats.map((f) => {
      const b = document.createElement('button');
      b.dataset.format = f;
      b.textContent = labels.get(f) ?? f.toUpperCase();
      return b;
    }),
  );
}

/** The colour menu of `mode`: the lesson has no target, so no distance, co-volume or features. */
export function colourMenu(mode: 'wrap' | 'mcf'): [string, string][] {
  return colourMenus[mode];
}

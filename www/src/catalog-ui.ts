// The page's lists come from the core's catalog (src/wasm/catalog.rs): the file types the picker
// accepts, the preset and colour-map menus, the export buttons and the legend titles. Nothing
// here names a format, preset or colour map.
import { byId } from './dom';
import type { Catalog } from './protocol';

/** Legend titles by colour-map name (filled by `applyCatalog`). */
export const legends: Record<string, string> = { none: '' };

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
  const cmap = byId<HTMLSelectElement>('cmap');
  const keep = cmap.value;
  fill(cmap, [...c.colourMaps.map((m): [string, string] => [m.name, m.label]), ['none', 'none']]);
  if (keep) cmap.value = keep;
  for (const m of c.colourMaps) legends[m.name] = m.legend;
  const labels = new Map(c.formats.map((f) => [f.name, f.label]));
  byId('exports').replaceChildren(
    ...c.exportFormats.map((f) => {
      const b = document.createElement('button');
      b.dataset.format = f;
      b.textContent = labels.get(f) ?? f.toUpperCase();
      return b;
    }),
  );
}

// The run's settings: the simple controls in front (Detail, Close gaps, Start surface) and the advanced panel
// (lil-gui) with every setting by stage, built entirely from what the core reports: the preset's
// settings JSON (fields, types, defaults), the doc comment of every field, the options of every
// enum field, the range of every bounded number, the Detail table and the Close gaps choices
// (catalog). Nothing about individual settings is written here except the keys those set.
import GUI from 'lil-gui';
import { byId } from './dom';
import type { Catalog, DetailLevel, Send, SettingRange } from './protocol';
import { diff, flatten, unflatten, type Flat, type Leaf } from './share';

/** The keys the simple controls set (the Detail table's two settings, the start surface and the
 * width up to which gaps close). */
const CELLS = 'field.cells_per_min_dimension';
const MIN_EDGE = 'remesh.min_edge_multiplier';
const START = 'start.surface';
const CLOSE_GAPS = 'surgery.close_gaps';
/** The preset a fresh page starts with (the core's default). */
export const DEFAULT_PRESET = 'full-wrap';

/** Whether `v` lies in `r` (the core refuses a wrap with a setting outside it). */
function inRange(v: number, r: SettingRange): boolean {
  const aboveMin = r.min === null || (r.min_open ? v > r.min : v >= r.min);
  return aboveMin && (r.max === null || v <= r.max);
}

/** Shows (or, with '', hides) the line under the panel that says why a value was refused. */
function warn(text: string): void {
  const el = byId('settings-warning');
  el.hidden = !text;
  el.textContent = text;
}

/** Display form of a leaf: arrays and optional numbers become text fields. */
function shown(v: Leaf): string | number | boolean {
  if (Array.isArray(v)) return v.join(', ');
  if (v === null) return '';
  return v;
}

export class SettingsPanel {
  private gui: GUI | null = null;
  private view: Record<string, string | number | boolean> = {};
  private values: Flat = {};
  private base: Flat = {};
  preset = DEFAULT_PRESET;

  constructor(
    private readonly container: HTMLElement,
    readonly presets: Record<string, Flat>,
    private readonly docs: Record<string, string>,
    private readonly enums: Record<string, string[]>,
    private readonly ranges: Record<string, SettingRange>,
    private readonly onChange: () => void,
  ) {}

  /** The current value of a setting. */
  value(key: string): Leaf | undefined {
    return this.values[key];
  }

  /** Sets settings (keys unknown to the preset are ignored), shows them, and reports the change. */
  assign(values: Flat): void {
    for (const [k, v] of Object.entries(values)) {
      if (!(k in this.base)) continue;
      this.values[k] = v;
      this.view[k] = shown(v);
    }
    for (const c of this.gui?.controllersRecursive() ?? []) c.updateDisplay();
    this.onChange();
  }

  /** Picks a preset and applies `changed` on top (keys unknown to the preset are ignored). */
  set(preset: string, changed: Flat = {}): void {
    this.preset = this.presets[preset] ? preset : DEFAULT_PRESET;
    const keys = Object.keys(this.values);
    this.base = this.presets[this.preset];
    this.values = { ...this.base };
    for (const [k, v] of Object.entries(changed)) if (k in this.base) this.values[k] = v;
    // The presets share their keys: show the new values in the panel as it is. Building it
    // again made a demo's click lay out the whole page twice (~40 ms on a 2-core machine).
    const same = this.gui && keys.length === Object.keys(this.base).length && keys.every((k) => k in this.base);
    if (!same) return this.build();
    for (const [k, v] of Object.entries(this.values)) this.view[k] = shown(v);
    for (const c of this.gui!.controllersRecursive()) c.updateDisplay();
    this.gui!.title(`Advanced settings (${this.preset})`);
  }

  /** Full settings as the nested JSON object the core takes. */
  settings(): Record<string, unknown> {
    return unflatten(this.values);
  }

  /** Settings that differ from the preset. */
  changed(): Flat {
    return diff(this.values, this.base);
  }

  /** What a share link writes: every parameter, the tuning version, and the tuning values that
   * differ from the preset's row of that version (a link decodes the rest from its row). */
  forLink(): Flat {
    const sameRow = this.values['tuning.version'] === this.base['tuning.version'];
    const fromRow = (k: string, v: Leaf) => sameRow && k.startsWith('tuning.') && k !== 'tuning.version' && JSON.stringify(v) === JSON.stringify(this.base[k]);
    return Object.fromEntries(Object.entries(this.values).filter(([k, v]) => !fromRow(k, v)));
  }

  /** Every setting's value (flattened). */
  all(): Flat {
    return { ...this.values };
  }

  private build(): void {
    this.gui?.destroy();
    const gui = new GUI({ container: this.container, title: `Advanced settings (${this.preset})`, width: 340 });
    gui.close();
    this.gui = gui;
    this.view = {};
    const folders = new Map<string, GUI>();
    for (const [key, value] of Object.entries(this.values)) {
      const dot = key.lastIndexOf('.');
      const group = dot > 0 ? key.slice(0, dot) : '';
      let folder: GUI = gui;
      if (group) {
        if (!folders.has(group)) folders.set(group, gui.addFolder(group).close());
        folder = folders.get(group)!;
      }
      this.view[key] = shown(value);
      const options = this.enums[key];
      const c = options ? folder.add(this.view, key, options) : folder.add(this.view, key);
      c.name(key.slice(dot + 1));
      const range = this.ranges[key];
      const said = range && this.docs[key]?.includes(range.text);
      const doc = [this.docs[key], range && !said && `Range: ${range.text}.`].filter(Boolean).join('\n');
      if (doc) c.domElement.title = doc;
      c.domElement.dataset.setting = key;
      // The version names the row the values below were taken from; changing it alone changes nothing.
      if (key === 'tuning.version') c.disable();
      c.onFinishChange((v: string | number | boolean) => {
        const parsed = this.parse(v, this.base[key]);
        const outside = typeof parsed === 'number' && range && !inRange(parsed, range);
        warn(outside ? `${key} = ${parsed} is outside its range ${range.text}; kept ${shown(this.values[key])}.` : '');
        if (parsed === undefined || outside) {
          this.view[key] = shown(this.values[key]);
          c.updateDisplay();
          return;
        }
        this.values[key] = parsed;
        this.onChange();
      });
    }
    gui.add({ reset: () => { this.set(this.preset); this.onChange(); } }, 'reset').name('↺ reset to preset');
  }

  /** Converts a display value back to the leaf type of `base`; undefined when invalid. */
  private parse(v: string | number | boolean, base: Leaf): Leaf | undefined {
    if (Array.isArray(base)) {
      const parts = String(v).split(/[\s,]+/).filter(Boolean).map(Number);
      return parts.every((x) => Number.isFinite(x) && x >= 0) ? parts.map(Math.round) : undefined;
    }
    if (base === null) {
      if (String(v).trim() === '') return null;
      const n = Number(v);
      return Number.isFinite(n) ? n : undefined;
    }
    if (typeof base === 'number') return typeof v === 'number' && Number.isFinite(v) ? v : undefined;
    return v as Leaf;
  }
}

/**
 * The run's settings as one source: the preset <select>, the simple controls and the advanced
 * panel. The panel exists once the worker has reported the presets; until then there are no
 * settings (`panel` is null). The worker computes the control curves of the settings, so every
 * change is sent to it.
 */
/** What `RunSettings.snapshot` keeps: the preset and changes in force, and the user's own. */
export interface SettingsState {
  preset: string;
  changed: Flat;
  own: { preset: string; changed: Flat } | null;
}

export class RunSettings {
  panel: SettingsPanel | null = null;
  private readonly detail = byId<HTMLSelectElement>('detail');
  private readonly start = byId<HTMLSelectElement>('start-surface');
  private readonly gaps = byId<HTMLSelectElement>('close-gaps');
  private levels: DetailLevel[] = [];
  /** The user's own preset and changed settings while a gallery demo's preset is in force (null
   * when the settings in force are the user's: a change they make adopts the demo's). */
  private own: { preset: string; changed: Flat } | null = null;

  /** `container`: where the panel goes; `changed`: runs after the user changed the settings (the share link follows). */
  constructor(
    private readonly select: HTMLSelectElement,
    private readonly container: HTMLElement,
    private readonly send: Send,
    private readonly changed: () => void,
  ) {
    select.onchange = () => {
      this.own = null;
      this.panel?.set(select.value);
      this.sync();
      this.sendCurves();
      changed();
    };
    this.detail.onchange = () => this.panel?.assign(this.levelValues(this.detail.value, this.startSurface()) ?? {});
    this.gaps.onchange = () => this.panel?.assign({ [CLOSE_GAPS]: Number(this.gaps.value) });
    // A new start surface keeps the Detail level: λ_min depends on the start (src/flow/detail.rs).
    this.start.onchange = () => {
      const level = this.level(this.startSurface());
      this.panel?.assign({ [START]: this.start.value, ...(level ? this.levelValues(level, this.start.value) : {}) });
    };
  }

  /** Builds the panel and the simple controls from the worker's presets (nested JSON), docs,
   * enum options and catalog; returns the presets flattened. */
  build(presets: Record<string, Record<string, unknown>>, docs: Record<string, string>, enums: Record<string, string[]>, catalog: Pick<Catalog, 'detail' | 'closeGaps' | 'settingRanges'>): Record<string, Flat> {
    const flat = Object.fromEntries(Object.entries(presets).map(([k, v]) => [k, flatten(v)]));
    const ranges = Object.fromEntries(catalog.settingRanges.map((r) => [r.key, r]));
    this.panel = new SettingsPanel(this.container, flat, docs, enums, ranges, () => {
      this.own = null;
      this.sync();
      this.sendCurves();
      this.changed();
    });
    this.levels = catalog.detail;
    const custom = new Option('custom', 'custom');
    custom.disabled = true;
    this.detail.replaceChildren(...this.levels.map((l) => new Option(l.name, l.name)), custom);
    const other = new Option('custom', 'custom');
    other.disabled = true;
    this.gaps.replaceChildren(...catalog.closeGaps.map((g) => new Option(g.label, String(g.value))), other);
    this.gaps.parentElement!.title = docs[CLOSE_GAPS] ?? '';
    this.start.replaceChildren(...(enums[START] ?? []).map((s) => new Option(s, s)));
    this.start.parentElement!.title = docs[START] ?? '';
    return flat;
  }

  private startSurface(): string {
    return String(this.panel?.value(START) ?? 'auto');
  }

  /** The two settings of Detail level `name` for the current preset and start surface `start`. */
  private levelValues(name: string, start: string): Flat | null {
    const v = this.levels.find((l) => l.name === name)?.presets[this.panel?.preset ?? ''];
    return v && v.min_edge[start] !== undefined ? { [CELLS]: v.cells, [MIN_EDGE]: v.min_edge[start] } : null;
  }

  /** The Detail level whose values are in force with start surface `start`, if any. */
  private level(start: string): string | null {
    const p = this.panel;
    const found = this.levels.find((l) => {
      const v = this.levelValues(l.name, start);
      return v && p?.value(CELLS) === v[CELLS] && p?.value(MIN_EDGE) === v[MIN_EDGE];
    });
    return found?.name ?? null;
  }

  /** Shows in the simple controls what the settings hold ("custom" when no level matches). */
  private sync(): void {
    if (!this.panel) return;
    this.start.value = this.startSurface();
    this.detail.value = this.level(this.startSurface()) ?? 'custom';
    const gaps = String(this.panel.value(CLOSE_GAPS) ?? 0);
    this.gaps.value = [...this.gaps.options].some((o) => o.value === gaps) ? gaps : 'custom';
  }

  /** Applies a link's preset and changed settings. */
  apply(preset: string, changed: Flat): void {
    this.panel!.set(preset, changed);
    this.select.value = this.panel!.preset;
    this.sync();
  }

  /** A demo's preset: the one its button names (genus 2 → isosurface), else the current one for
   * the lesson, else full-wrap. It is borrowed: the user's own settings are kept for their next
   * file; a demo of the user's own preset runs with their settings. */
  forDemo(demo: string, named: string | undefined): void {
    const panel = this.panel;
    if (!panel) return;
    const mine = this.own ?? { preset: panel.preset, changed: panel.changed() };
    const preset = named ?? (demo === 'mcf' ? panel.preset : DEFAULT_PRESET);
    if (preset === mine.preset) return void this.restoreOwn();
    if (preset === panel.preset) return;
    this.own = mine;
    this.show(preset, {});
  }

  /** The user's own file or address: their settings come back if a demo borrowed the preset;
   * returns the borrowed preset's label then (else null). */
  restoreOwn(): string | null {
    const own = this.own;
    if (!own || !this.panel) return null;
    const borrowed = this.label(this.panel.preset);
    this.own = null;
    this.show(own.preset, own.changed);
    return borrowed;
  }

  /** The settings in force and the user's own set aside, to put back with `put`. */
  snapshot(): SettingsState {
    return { preset: this.panel?.preset ?? DEFAULT_PRESET, changed: this.panel?.changed() ?? {}, own: this.own };
  }

  put(s: SettingsState): void {
    this.own = s.own;
    this.show(s.preset, s.changed);
  }

  /** The preset in force for the status line: '' for the default, else " (preset: label)". */
  inForce(): string {
    const p = this.panel?.preset ?? DEFAULT_PRESET;
    return p === DEFAULT_PRESET ? '' : ` (preset: ${this.label(p)})`;
  }

  private label(preset: string): string {
    return [...this.select.options].find((o) => o.value === preset)?.textContent ?? preset;
  }

  /** Puts `preset` with `changed` in force, shows it and recomputes the control curves. */
  private show(preset: string, changed: Flat): void {
    this.apply(preset, changed);
    this.sendCurves();
  }

  /** Full settings as the nested JSON object the core takes (the panel must exist). */
  values(): Record<string, unknown> {
    return this.panel!.settings();
  }

  /** Asks the worker for the control curves of the current settings. */
  sendCurves(): void {
    this.send({ type: 'curves', settings: this.values() });
  }
}

export { flatten };

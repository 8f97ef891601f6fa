// The advanced settings panel (lil-gui), built entirely from what the core reports: the preset's
// settings JSON (fields, types, defaults), the doc comment of every field and the options of
// every enum field (both read from the Rust sources by `settingsDocs` / `settingsEnums`).
// Nothing about individual settings is written here.
import GUI from 'lil-gui';
import type { Send } from './protocol';
import { diff, flatten, unflatten, type Flat, type Leaf } from './share';

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
  preset = 'full-wrap';

  constructor(
    private readonly container: HTMLElement,
    readonly presets: Record<string, Flat>,
    private readonly docs: Record<string, string>,
    private readonly enums: Record<string, string[]>,
    private readonly onChange: () => void,
  ) {}

  /** Picks a preset and applies `changed` on top (keys unknown to the preset are ignored). */
  set(preset: string, changed: Flat = {}): void {
    this.preset = this.presets[preset] ? preset : 'full-wrap';
    this.base = this.presets[this.preset];
    this.values = { ...this.base };
    for (const [k, v] of Object.entries(changed)) if (k in this.base) this.values[k] = v;
    this.build();
  }

  /** Full settings as the nested JSON object the core takes. */
  settings(): Record<string, unknown> {
    return unflatten(this.values);
  }

  /** Settings that differ from the preset. */
  changed(): Flat {
    return diff(this.values, this.base);
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
      const base = this.base[key];
      const options = this.enums[key];
      const c = options ? folder.add(this.view, key, options) : folder.add(this.view, key);
      c.name(key.slice(dot + 1));
      const doc = this.docs[key];
      if (doc) c.domElement.title = doc;
      c.domElement.dataset.setting = key;
      c.onFinishChange((v: string | number | boolean) => {
        const parsed = this.parse(v, base);
        if (parsed === undefined) {
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
 * The run's settings as one source: the preset <select> and the advanced panel. The panel exists
 * once the worker has reported the presets; until then there are no settings (`panel` is null).
 * The worker computes the control curves of the settings, so every change is sent to it.
 */
export class RunSettings {
  panel: SettingsPanel | null = null;

  /** `container`: where the panel goes; `changed`: runs after the user changed the settings (the share link follows). */
  constructor(
    private readonly select: HTMLSelectElement,
    private readonly container: HTMLElement,
    private readonly send: Send,
    private readonly changed: () => void,
  ) {
    select.onchange = () => {
      this.panel?.set(select.value);
      this.sendCurves();
      changed();
    };
  }

  /** Builds the panel from the worker's presets (nested JSON), docs and enum options; returns the presets flattened. */
  build(presets: Record<string, Record<string, unknown>>, docs: Record<string, string>, enums: Record<string, string[]>): Record<string, Flat> {
    const flat = Object.fromEntries(Object.entries(presets).map(([k, v]) => [k, flatten(v)]));
    this.panel = new SettingsPanel(this.container, flat, docs, enums, () => {
      this.sendCurves();
      this.changed();
    });
    return flat;
  }

  /** Applies a link's preset and changed settings. */
  apply(preset: string, changed: Flat): void {
    this.panel!.set(preset, changed);
    this.select.value = this.panel!.preset;
  }

  /** A demo's preset: the one its button names (genus 2 → isosurface), else the current one for the lesson, else full-wrap. */
  forDemo(demo: string, named: string | undefined): void {
    const panel = this.panel;
    const preset = named ?? (demo === 'mcf' ? panel?.preset : 'full-wrap') ?? 'full-wrap';
    if (panel && preset !== panel.preset) {
      panel.set(preset);
      this.select.value = preset;
      this.sendCurves();
    }
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

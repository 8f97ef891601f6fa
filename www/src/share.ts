// App state <-> URL hash, versioned. The hash is plain `key=value` pairs (URLSearchParams):
//   v=4  d=<dataset: demo id | https URL>  p=<preset>  s.<setting path>=<JSON literal>  view.<key>=<value>
//   f.name, f.size, f.sha=<the dropped file the link was made with: name, bytes, SHA-256 prefix>
// Version 2 added the f.* keys; version 3 writes every setting, not only those that differ from
// the defaults; version 4 names the core's tuning table version (s.tuning.version) and writes only
// the tuning values that differ from that version's row. A link's settings decode against its
// tuning version's row (links of versions 1–3: row 1), so a link reproduces its result after later
// versions change a default.
// Decoding never evaluates anything: values are parsed with JSON.parse or as plain strings and
// checked against the defaults' types; anything unknown, old or malformed falls back to the
// default and is reported in `notices` (shown as text, never as HTML).

/** The current hash format. */
export const SHARE_VERSION = 4;
/** Versions whose settings this app reads (each one adds keys to the one before). */
const READABLE_VERSIONS = ['1', '2', '3', '4'];
/** The tuning version of links made before links named one. */
const UNNAMED_TUNING = 1;

/** A dropped file as a link names it: it cannot travel in the link, so the receiver drops it again. */
export interface FileStamp {
  name: string;
  /** Bytes. */
  size: number;
  /** Leading hex digits of the file's SHA-256, or '' where the browser could not compute it. */
  sha: string;
}

/** A JSON-like value (settings leaves). */
export type Leaf = number | string | boolean | null | number[];

/** Flattened settings: `path → value` (nested objects joined with "."). */
export type Flat = Record<string, Leaf>;

/** What the view shows (no camera matrices: orbit angles and zoom only). */
export interface ViewState {
  wire: boolean;
  smooth: boolean;
  cmap: string;
  yaw: number;
  pitch: number;
  zoom: number;
}

export const DEFAULT_VIEW: ViewState = { wire: true, smooth: true, cmap: 'distance', yaw: 0.35, pitch: 0.4, zoom: 1 };

/** What `decode` checks a link against besides the presets. */
export interface DecodeOptions {
  /** The preset when the link names none or an unknown one. */
  defaultPreset?: string;
  /** Setting keys of earlier links (`tau`, `flow.regrow_depth`) → current keys (`flow.tau`,
   * `tuning.flow.regrow_depth`); the core supplies it (`settingAliases`). */
  aliases?: Record<string, string>;
  /** Colour-map names a link may ask for (the core's catalog, plus 'none'); without it only the default. */
  colourMaps?: readonly string[];
  /** The core's tuning table (catalog `tuning.rows`): version → its values. */
  tuningRows?: Record<string, Record<string, unknown>>;
}

export interface ShareState {
  /** Dataset: a gallery id (`demo:bunny`) or an http(s) URL; null when none is shareable. */
  dataset: string | null;
  preset: string;
  /** Settings that differ from the preset's defaults. */
  changed: Flat;
  /** Every setting's value: what `encode` writes when present (else `changed`), so that the
   * link does not depend on this version's defaults. `decode` leaves it unset. */
  settings?: Flat;
  view: ViewState;
  /** Volumes: the iso-value wrapped (absent for meshes, clouds and Otsu's default). */
  iso?: number;
  /** The dropped file the state was made with (absent for gallery shapes and addresses). */
  file?: FileStamp;
  /** The sphere lesson's subdivision level and time step (dataset demo:mcf only). */
  lesson?: { level: number; tau: number };
}

export interface Decoded {
  state: ShareState;
  /** Human-readable notes about keys that were ignored or reset. */
  notices: string[];
}

/** Flattens nested settings into `a.b` paths (arrays are leaves). */
export function flatten(obj: Record<string, unknown>, prefix = '', out: Flat = {}): Flat {
  for (const [k, v] of Object.entries(obj)) {
    const key = prefix ? `${prefix}.${k}` : k;
    if (v && typeof v === 'object' && !Array.isArray(v)) flatten(v as Record<string, unknown>, key, out);
    else out[key] = v as Leaf;
  }
  return out;
}

/** Inverse of `flatten`. Only plain own keys are created (no prototype keys). */
export function unflatten(flat: Flat): Record<string, unknown> {
  const out: Record<string, unknown> = Object.create(null);
  for (const [path, v] of Object.entries(flat)) {
    const parts = path.split('.');
    if (parts.some((p) => p === '__proto__' || p === 'constructor' || p === 'prototype')) continue;
    let node = out;
    for (const p of parts.slice(0, -1)) {
      if (!node[p] || typeof node[p] !== 'object') node[p] = Object.create(null);
      node = node[p] as Record<string, unknown>;
    }
    node[parts[parts.length - 1]] = v;
  }
  return JSON.parse(JSON.stringify(out));
}

/** Settings keys whose value differs from `base`. */
export function diff(current: Flat, base: Flat): Flat {
  const out: Flat = {};
  for (const [k, v] of Object.entries(current)) if (JSON.stringify(v) !== JSON.stringify(base[k])) out[k] = v;
  return out;
}

/** Whether `v` has the same JSON type as the default `d` (null defaults take number or null). */
function sameType(v: unknown, d: Leaf): boolean {
  if (d === null) return v === null || (typeof v === 'number' && Number.isFinite(v));
  if (Array.isArray(d)) return Array.isArray(v) && v.every((x) => typeof x === 'number' && Number.isFinite(x));
  if (typeof d === 'number') return typeof v === 'number' && Number.isFinite(v);
  return typeof v === typeof d;
}

/** A dataset reference is a gallery id or an http(s) URL; anything else is refused. */
export function validDataset(d: string): boolean {
  if (/^demo:[a-z0-9-]{1,40}$/.test(d)) return true;
  try {
    const u = new URL(d);
    return u.protocol === 'https:' || u.protocol === 'http:';
  } catch {
    return false;
  }
}

/** Encodes the state as a hash (without the leading "#"). Keys are sorted for stable links. */
export function encode(state: ShareState): string {
  const q = new URLSearchParams();
  q.set('v', String(SHARE_VERSION));
  if (state.dataset) q.set('d', state.dataset);
  q.set('p', state.preset);
  if (state.iso !== undefined && Number.isFinite(state.iso)) q.set('iso', String(state.iso));
  if (state.file) {
    q.set('f.name', state.file.name);
    q.set('f.size', String(state.file.size));
    if (state.file.sha) q.set('f.sha', state.file.sha);
  }
  if (state.lesson) {
    q.set('mcf.level', String(state.lesson.level));
    q.set('mcf.tau', String(state.lesson.tau));
  }
  const written = state.settings ?? state.changed;
  for (const k of Object.keys(written).sort()) q.set(`s.${k}`, JSON.stringify(written[k]));
  const v = state.view;
  for (const k of Object.keys(DEFAULT_VIEW) as (keyof ViewState)[]) {
    if (v[k] === DEFAULT_VIEW[k]) continue;
    q.set(`view.${k}`, typeof v[k] === 'number' ? String(Math.round((v[k] as number) * 1e4) / 1e4) : String(v[k]));
  }
  return q.toString();
}

/**
 * Decodes a hash against `presets` (name → flattened default settings) and `opts`. Never
 * throws: whatever cannot be used is dropped and explained in `notices`.
 */
export function decode(hash: string, presets: Record<string, Flat>, opts: DecodeOptions = {}): Decoded {
  const { defaultPreset = 'full-wrap', aliases = {}, colourMaps = [DEFAULT_VIEW.cmap, 'none'], tuningRows = {} } = opts;
  const notices: string[] = [];
  const state: ShareState = { dataset: null, preset: defaultPreset, changed: {}, view: { ...DEFAULT_VIEW } };
  const raw = hash.replace(/^#/, '');
  if (!raw) return { state, notices };
  let q: URLSearchParams;
  try {
    q = new URLSearchParams(raw);
  } catch {
    notices.push('The link could not be read; defaults are used.');
    return { state, notices };
  }
  const version = q.get('v');
  const old = version === null || !READABLE_VERSIONS.includes(version);
  if (old) {
    notices.push(
      version === null || !/^\d{1,4}$/.test(version)
        ? 'The link has no version mark; only its dataset and preset are used, settings are defaults.'
        : `The link was made by version ${version} of the app (this is ${SHARE_VERSION}); only its dataset and preset are used, settings are defaults.`,
    );
  }
  const d = q.get('d') ?? q.get('dataset');
  if (d !== null) {
    if (validDataset(d)) state.dataset = d;
    else notices.push(`Ignored the dataset "${d.slice(0, 60)}": not a gallery id or an http(s) URL.`);
  }
  const p = q.get('p') ?? q.get('preset');
  if (p !== null) {
    if (Object.prototype.hasOwnProperty.call(presets, p)) state.preset = p;
    else notices.push(`Unknown preset "${p.slice(0, 40)}"; using ${defaultPreset}.`);
  }
  const preset = presets[state.preset] ?? {};
  const defaults = old ? preset : atTuning(preset, tuningOf(q, version), tuningRows, notices);
  const given: Flat = {};
  const unknown: string[] = [];
  const file = decodeFile(q, notices);
  if (file) state.file = file;
  for (const [key, value] of q) {
    if (key === 'v' || key === 'd' || key === 'p' || key === 'dataset' || key === 'preset' || key.startsWith('f.')) continue;
    if (key === 'iso') {
      const n = Number(value);
      if (value.trim() !== '' && Number.isFinite(n)) state.iso = n;
      else notices.push(`Ignored iso = "${value.slice(0, 40)}": not a number; the volume's Otsu threshold is used.`);
      continue;
    }
    if (key === 'mcf.level' || key === 'mcf.tau') {
      const n = Number(value);
      if (value.trim() === '' || !Number.isFinite(n)) notices.push(`Ignored ${key} = "${value.slice(0, 40)}": not a number.`);
      else state.lesson = { ...(state.lesson ?? { level: NaN, tau: NaN }), [key.slice(4)]: n };
      continue;
    }
    if (key.startsWith('s.') && !old) {
      const path = Object.prototype.hasOwnProperty.call(aliases, key.slice(2)) ? aliases[key.slice(2)] : key.slice(2);
      if (!Object.prototype.hasOwnProperty.call(defaults, path)) {
        unknown.push(key);
        continue;
      }
      let parsed: unknown;
      try {
        parsed = JSON.parse(value);
      } catch {
        parsed = value; // bare strings (enum values) may come unquoted
      }
      if (!sameType(parsed, defaults[path])) notices.push(`Setting ${path} = "${value.slice(0, 40)}" has the wrong type; using the default.`);
      else given[path] = parsed as Leaf;
    } else if (key.startsWith('view.')) {
      const k = key.slice(5) as keyof ViewState;
      if (!Object.prototype.hasOwnProperty.call(DEFAULT_VIEW, k)) {
        unknown.push(key);
        continue;
      }
      const dv = DEFAULT_VIEW[k];
      if (typeof dv === 'boolean') {
        if (value === 'true' || value === 'false') (state.view[k] as boolean) = value === 'true';
        else unknown.push(key);
      } else if (typeof dv === 'number') {
        const n = Number(value);
        if (Number.isFinite(n) && Math.abs(n) < 1e6) (state.view[k] as number) = n;
        else unknown.push(key);
      } else if (k === 'cmap') {
        if (colourMaps.includes(value)) state.view.cmap = value;
        else unknown.push(key);
      }
    } else if (!(key.startsWith('s.') && old)) {
      unknown.push(key);
    }
  }
  if ('tuning.version' in given && !tuningRows[String(given['tuning.version'])]) delete given['tuning.version'];
  // What differs from the preset's current settings: the link's values, and its tuning row's.
  state.changed = diff({ ...defaults, ...given }, preset);
  if (unknown.length) notices.push(`Ignored unknown key${unknown.length > 1 ? 's' : ''}: ${unknown.slice(0, 8).map((k) => k.slice(0, 40)).join(', ')}.`);
  return { state, notices };
}

/** The tuning version a link names: its own, or that of the links before versions were named. */
function tuningOf(q: URLSearchParams, version: string | null): number | null {
  const named = q.get('s.tuning.version');
  if (named !== null) return Number.isSafeInteger(Number(named)) ? Number(named) : null;
  return version !== null && Number(version) < 4 ? UNNAMED_TUNING : null;
}

/** `preset` with its tuning values replaced by those of tuning `version` (null: as it is). */
function atTuning(preset: Flat, version: number | null, rows: Record<string, Record<string, unknown>>, notices: string[]): Flat {
  if (version === null || !('tuning.version' in preset) || preset['tuning.version'] === version) return preset;
  const row = rows[String(version)];
  if (!row) {
    notices.push(`The link's tuning version ${version} is unknown to this app; the current tuning is used.`);
    return preset;
  }
  return { ...preset, ...flatten(row, 'tuning') };
}

/** The f.* keys: a name (no control characters), a byte count and an optional SHA-256 prefix. */
function decodeFile(q: URLSearchParams, notices: string[]): FileStamp | undefined {
  const name = q.get('f.name'), size = q.get('f.size'), sha = q.get('f.sha') ?? '';
  if (name === null && size === null && !sha) return undefined;
  const n = Number(size);
  const control = (c: string) => c.charCodeAt(0) < 32 || c.charCodeAt(0) === 127;
  const nameOk = name !== null && name.length > 0 && name.length <= 255 && ![...name].some(control);
  if (!nameOk || size === null || !Number.isSafeInteger(n) || n < 0 || !/^([0-9a-f]{8,64})?$/.test(sha)) {
    notices.push('Ignored the link\'s file (f.name, f.size, f.sha): malformed.');
    return undefined;
  }
  return { name: name!, size: n, sha };
}

/** Bytes for people: "812 B", "1.2 MB". */
export function formatBytes(n: number): string {
  if (n < 1024) return `${n} B`;
  const units = ['kB', 'MB', 'GB', 'TB'];
  let v = n / 1024, i = 0;
  while (v >= 1024 && i < units.length - 1) {
    v /= 1024;
    i++;
  }
  return `${v.toPrecision(v < 10 ? 2 : 3)} ${units[i]}`;
}

/** A file stamp in words: "bunny.ply (1.2 MB, fingerprint 3fa2c9e1d07b4a55)". */
export function describeFile(f: FileStamp): string {
  return `${f.name} (${formatBytes(f.size)}${f.sha ? `, fingerprint ${f.sha}` : ''})`;
}

/** Whether `got` is the file `expected` names: same size and fingerprint (a renamed copy is the
 * same file); without both fingerprints, same size and name. */
export function sameFile(expected: FileStamp, got: FileStamp): boolean {
  if (expected.size !== got.size) return false;
  return expected.sha && got.sha ? expected.sha === got.sha : expected.name === got.name;
}

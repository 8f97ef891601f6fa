// Messages between the UI thread and the worker: the one source of truth for both sides.
// Meshes travel as flat typed arrays (Transferables), never as JSON.

// What the core hands the page (statistics, reports, advice, the certificate and the verdict,
// what was read, errors) has its TypeScript type generated from the Rust type that is serialised
// (tsify, into the wasm-bindgen declarations): not mirrored here. The facade returns them as
// plain objects; the worker casts its `JsValue`s to these types.
import type {
  Certificate, ControlCurves, Histogram, LeftOut, MeshStats, MeshTauAdvice, Repairs, SphereStats, StartedOver, StepReport, TargetInfo, TauAdvice, UiError,
  Verdict, VolumeInfo,
} from '../pkg/lsw';
export type {
  Certificate, ContactReport, ControlCurves, FitTimes, Histogram, LeftOut, MeshFlowStats, MeshStats, MeshTauAdvice, Outcome, PhaseTimes, RemeshReport,
  RemeshTimings, Repairs, SphereStats, StartedOver, StepReport, SurgeryEvent, SurgeryKind, TargetInfo, TargetKind, TauAdvice, ThirdPass, UiError, Verdict,
  VerdictState, VolumeInfo,
} from '../pkg/lsw';

/** Statistics of either MCF lesson, told apart by `lesson` (`McfSession.stats()`). */
export type McfStats = SphereStats | MeshStats;

/** Which MCF lesson: the sphere against its exact law, or the loaded mesh. */
export type LessonKind = McfStats['lesson'];

/** The sphere lesson's parameters (the arguments of `new McfSession(level, radius, tau)`). */
export interface McfParams {
  level: number;
  radius: number;
  tau: number;
}

/** A file format of the core's catalog (mirrors `io::formats::FormatInfo`). */
export interface CatalogFormat {
  /** Short lower-case name (`TargetInfo.format`, `export(name)` for writable ones). */
  name: string;
  /** Name for people ("PLY", "glTF", "NIfTI"). */
  label: string;
  /** Extensions without the dot, the usual one first; `nii.gz` is one extension. */
  extensions: string[];
  kind: 'mesh' | 'cloud' | 'mesh-or-cloud' | 'volume';
  read: boolean;
  write: boolean;
}

/** A colour map of the core's catalog (mirrors `flow::colour::ColourMapInfo`). */
export interface CatalogColourMap {
  /** The name `WrapSession.scalar` takes. */
  name: ColourMap;
  /** Menu label. */
  label: string;
  /** Legend title next to the colour bar. */
  legend: string;
  /** Unit of the values ('' when dimensionless). */
  unit: string;
  /** Per-vertex property name in exported files, or null when not exported. */
  exportName: string | null;
}

/** The app's lists from their Rust sources: `JSON.parse(catalog())` (see src/wasm/catalog.rs). */
export interface Catalog {
  formats: CatalogFormat[];
  colourMaps: CatalogColourMap[];
  /** Preset names in menu order (`presetSettings(name)`). */
  presets: string[];
  /** Their menu labels. */
  presetLabels: string[];
  /** Names of the formats `export` and `exportMesh` write. */
  exportFormats: string[];
  /** The Detail levels, coarse first: per preset the grid cells and λ_min by start surface name
   * they set (see src/flow/detail.rs). */
  detail: DetailLevel[];
  /** The "Close gaps up to" choices: `surgery.close_gaps` values, automatic first (src/flow/detail.rs). */
  closeGaps: { label: string; value: number }[];
  /** The colour maps the MCF lesson offers (a subset of `colourMaps`). */
  lessonColourMaps: string[];
  /** The MCF lessons, in menu order (mirrors `flow::LessonInfo`). */
  lessons: CatalogLesson[];
  /** Ranges of numeric settings the core enforces (unbounded limits are null). */
  settingRanges: SettingRange[];
  /** The tuning table (src/flow/settings/tuning.rs): the current version, what each version
   * changed, and every version's values. */
  tuning: { current: number; versions: { version: number; changes: string }[]; rows: Record<string, Record<string, unknown>> };
}

/** An MCF lesson of the catalog: `name` "mcf" (the sphere) or "mcf-mesh" (the loaded mesh). */
export interface CatalogLesson {
  name: string;
  label: string;
  title: string;
  /** Offered only while a mesh (not a point cloud or a volume) is loaded. */
  needsMesh: boolean;
}

/** A Detail level (`Catalog.detail`): `field.cells_per_min_dimension` and, by start surface,
 * `remesh.min_edge_multiplier` for every preset. */
export interface DetailLevel {
  name: string;
  presets: Record<string, { cells: number; min_edge: Record<string, number> }>;
}

/** The allowed range of a numeric setting (`Catalog.settingRanges`; unbounded limits are null). */
export interface SettingRange {
  key: string;
  min: number | null;
  max: number | null;
  min_open: boolean;
  text: string;
}

/** A per-vertex scalar the core can colour by (a `Catalog.colourMaps` name, `WrapSession.scalar`), or 'none'. */
export type ColourMap = string;

/** Points left out on reading, as a clause of the input's description ('' when none). */
export function leftOutNote(l?: LeftOut): string {
  return l ? `; ${l.points} ${l.why} left out` : '';
}

/** What reading mended, as a clause of the input's description ('' when nothing). */
export function repairsNote(r?: Repairs): string {
  if (!r) return '';
  const parts = [
    [r.merged_vertices, 'coincident vertices merged'],
    [r.dropped_faces, 'repeated faces dropped'],
    [r.flipped_faces, 'faces turned to agree'],
    [r.split_vertices, 'vertices split where parts touch'],
    [r.filled_holes, 'small holes closed'],
  ].filter(([n]) => Number(n) > 0).map(([n, what]) => `${n} ${what}`);
  return parts.length ? ` (mended: ${parts.join(', ')})` : '';
}

/** How the distance field is shown: off, a node plane normal to x / y / z, or an isosurface. */
export type FieldView = 'off' | 'x' | 'y' | 'z' | 'iso';

/** A field slice ready to draw: a quad (4 corners, target units) with an RGBA texture. */
export interface FieldSlice {
  width: number;
  height: number;
  /** Corners (u₀,v₀), (u₁,v₀), (u₁,v₁), (u₀,v₁) as 12 floats; texture row 0 is v₀. */
  corners: Float32Array;
  /** width × height RGBA bytes, u fastest. */
  rgba: Uint8Array;
}

/** A field isosurface ready to draw (target units). */
export interface FieldIso {
  positions: Float32Array;
  indices: Uint32Array;
}

/** Where a wrap's input comes from. */
export type Source =
  | { kind: 'bytes'; bytes: ArrayBuffer; name: string }
  | { kind: 'demo'; id: string }
  | { kind: 'url'; url: string };

/** UI → worker. */
export type ToWorker =
  | { type: 'mcf-init'; params: McfParams }
  /** Starts the lesson on the loaded mesh with relative time step τ/D². */
  | { type: 'mcf-mesh-init'; tau: number }
  | { type: 'wrap-load'; source: Source; settings: Record<string, unknown>; autoplay: boolean; run: number; iso?: number }
  | { type: 'play' }
  | { type: 'pause' }
  | { type: 'step'; n: number }
  | { type: 'cancel' }
  | { type: 'colour'; map: ColourMap }
  | { type: 'export'; format: string; kept?: { positions: Float32Array; indices: Uint32Array } }
  | { type: 'curves'; settings: Record<string, unknown> }
  /** Show the distance field: `t` ∈ [0, 1] is the slice position or the isosurface level's fraction. */
  | { type: 'field'; view: FieldView; t: number }
  /** Volumes: wrap again at this iso-value and volume of a 4-D file; `run` as for a reset. */
  | { type: 'volume-iso'; iso: number; frame: number; settings: Record<string, unknown>; run: number }
  /** Volumes: send the slice normal to index axis `axis` at voxel `index`. */
  | { type: 'volume-slice'; axis: number; index: number };

/**
 * A frame of the evolving surface, ready to upload: the worker computes normals and colours so
 * the UI thread only copies buffers. `indices` is present when connectivity changed.
 */
export interface Frame {
  type: 'frame';
  mode: 'mcf' | 'wrap';
  /** The page's run number of the wrap this frame belongs to (stale frames are dropped). */
  run: number;
  positions: Float32Array;
  normals: Float32Array;
  indices?: Uint32Array;
  /** RGB per vertex from the colour map, or null for plain shading. */
  colors: Float32Array | null;
  /** Range of the coloured scalar, for the legend. */
  range: [number, number];
  colour: ColourMap;
  /** MCF demo statistics (mode mcf). */
  stats?: McfStats;
  /** MCF: the lesson's last frame (kept by the scrubber whatever its stride). */
  final?: boolean;
  /** Wrap step report (mode wrap; absent before the first step). */
  report?: StepReport;
  /** Reports of every step since the previous frame (for the per-step plots). */
  reports?: StepReport[];
  /** κ histogram of this frame (mode wrap). */
  histogram?: Histogram;
  /** Step limit of the wrap's settings (for the progress bar). */
  stepLimit?: number;
  /** Working milliseconds since the wrap was started (load included, pauses not). */
  elapsedMs?: number;
  playing: boolean;
}

export type StopReason = 'paused' | 'finished' | 'cancelled' | 'ready';

/** Worker → UI. */
export type FromWorker =
  | { type: 'ready'; presets: Record<string, Record<string, unknown>>; docs: Record<string, string>; enums: Record<string, string[]>; aliases: Record<string, string>; catalog: Catalog }
  | Frame
  | { type: 'loading'; what: string }
  /** A long phase (distance field, start surface, final fit) is `fraction` (0–1) done. */
  | { type: 'progress'; phase: string; fraction: number }
  /** The lesson's τ, judged before it runs (sent with every new lesson). */
  | { type: 'mcf-advice'; advice: TauAdvice | MeshTauAdvice }
  /** What was loaded. `lessonMesh`: '' when the mesh lesson can flow it, else why not. */
  | { type: 'target'; run: number; positions: Float32Array; indices: Uint32Array; info: TargetInfo; name: string; lessonMesh: string }
  /** The worker stopped stepping: paused, finished, cancelled, or loaded and `ready` to play (no autoplay). */
  | { type: 'stopped'; reason: StopReason }
  /** `phases`: `elapsedMs` by phase, [name, ms] in the order they first ran (see Stopwatch). */
  | { type: 'result'; run: number; hash: string; name: string; positions: Float32Array; normals: Float32Array; indices: Uint32Array; elapsedMs: number; phases: [string, number][]; steps: number; certificate: Certificate; verdict: Verdict; stopReason: string | null; start: string; wasmBytes: number; isolated: number; specks: number; startedOver: StartedOver | null }
  | { type: 'exported'; bytes: Uint8Array; format: string }
  | { type: 'curves'; curves: ControlCurves }
  /** The field view asked for (neither slice nor iso: nothing to show). `label` describes it. */
  | { type: 'field'; run: number; view: FieldView; slice?: FieldSlice; iso?: FieldIso; range: [number, number]; label: string }
  | { type: 'error'; error: UiError }
  /** The input is a voxel volume: its facts, value histogram and the iso-value being wrapped. */
  | { type: 'volume'; run: number; info: VolumeInfo; histogram: { min: number; max: number; counts: Float64Array }; iso: number }
  | VolumeSliceMsg;

/** One slice of voxel values (`VolumeView.slice`): `width × height`, u fastest. */
export interface VolumeSliceMsg {
  type: 'volume-slice';
  axis: number;
  index: number;
  width: number;
  height: number;
  values: Float32Array;
}

/** Turns anything thrown (a facade error object, an Error, a string) into a UiError. */
export function toUiError(e: unknown): UiError {
  if (e && typeof e === 'object' && 'code' in e && 'message' in e) {
    const o = e as { code: unknown; message: unknown; hint?: unknown };
    return { code: String(o.code), message: String(o.message), hint: o.hint ? String(o.hint) : '' };
  }
  if (e instanceof Error) return { code: 'internal', message: e.message, hint: 'Reload the page; if it persists, report a bug.' };
  return { code: 'internal', message: String(e), hint: 'Reload the page; if it persists, report a bug.' };
}

const GIB = 1024 ** 3;

/** The most linear memory a wasm32 instance can have: 4 GiB. */
export const WASM_MEMORY_LIMIT = 4 * GIB;

/** A trap with more than this share of {@link WASM_MEMORY_LIMIT} in use is taken for an
 * allocation that failed: the core aborts then, which wasm reports as a bare "unreachable" (a
 * 20 M-point cloud stopped so with 2.6 GiB in use, and the page said only "unreachable"). */
const TRAP_NEAR_LIMIT = 0.5;

/** The error codes after which the wasm instance may be unusable (a trap or a failed allocation,
 * see {@link failureError}): the page starts a fresh worker. */
export const RESTART_CODES: readonly string[] = ['internal', 'out-of-memory', 'corrupt-data'];

/** What the worker reports for anything thrown while `wasmBytes` of linear memory were in use:
 * core errors as they are; a failed allocation (a RangeError, an allocation message, or a trap
 * with most of the memory in use) as `out-of-memory`; a trap while reading a file (`phase`, the
 * worker's current phase) as `corrupt-data`; any other trap as an internal error (the
 * {@link RESTART_CODES}). */
export function failureError(e: unknown, wasmBytes: number, phase = ''): UiError {
  const error = toUiError(e);
  if (error.code !== 'internal') return error;
  const trapped = e instanceof WebAssembly.RuntimeError;
  const restarted = 'The page has restarted its computation; the last result shown is kept.';
  if (e instanceof RangeError || /memory|allocation/i.test(error.message) || (trapped && wasmBytes > TRAP_NEAR_LIMIT * WASM_MEMORY_LIMIT)) {
    return {
      code: 'out-of-memory',
      message: `This input needs more memory than the browser gives the wrap (${(wasmBytes / GIB).toFixed(1)} GiB in use of at most ${WASM_MEMORY_LIMIT / GIB} GiB).`,
      hint: `${restarted} Use a smaller input (thin the cloud, or lower field.cells_per_min_dimension in the advanced settings), or wrap it with the native CLI (lsw wrap), which has no such limit.`,
    };
  }
  if (trapped && phase === 'reading') {
    // A reader's crate stopped on the file's data (corrupt LAZ point data panics the decoder).
    return { code: 'corrupt-data', message: `Reading the file stopped on its data (wasm: ${error.message}): it is probably corrupt.`, hint: `${restarted} Re-export or re-download the file; the native CLI (lsw info FILE) names what is wrong.` };
  }
  if (trapped) {
    return { code: 'internal', message: `The computation stopped on an internal error (wasm: ${error.message}).`, hint: `${restarted} If it happens again with this input, please report a bug.` };
  }
  return error;
}

/** UI → render worker. Geometry buffers are transferred, not copied. */
export type ToRender =
  | { type: 'init'; canvas: OffscreenCanvas; width: number; height: number; pixelRatio: number }
  | { type: 'resize'; width: number; height: number }
  | { type: 'geometry'; positions: Float32Array; normals: Float32Array; indices?: Uint32Array; colors: Float32Array | null; step?: number; record?: boolean; final?: boolean }
  | { type: 'target'; positions: Float32Array; indices: Uint32Array | null }
  /** `aside`: 'set' — the frames are the kept result's: keep them for 'restore-frames'; 'keep' —
   * drop them but keep those set aside before; none — drop both (the lesson). */
  | { type: 'clear-frames'; aside?: 'set' | 'keep' }
  | { type: 'restore-frames' }
  | { type: 'show-frame'; index: number }
  | { type: 'refit' }
  | { type: 'fit' }
  /** Looks from these orbit angles and frames the surface (front, side, top buttons). */
  | { type: 'look'; yaw: number; pitch: number }
  | { type: 'rotate'; dx: number; dy: number }
  | { type: 'zoom'; factor: number }
  | { type: 'set-view'; yaw: number; pitch: number; zoom: number }
  | { type: 'wireframe'; on: boolean }
  | { type: 'smooth'; on: boolean }
  | { type: 'show-target'; on: boolean }
  /** Shows a field slice or isosurface; neither clears the field view. */
  | { type: 'field'; slice?: FieldSlice; iso?: FieldIso }
  | { type: 'probe' };

/** Posts to the computation worker; the page's modules take this rather than the Worker, which is replaced after a crash. */
export type Send = (m: ToWorker, transfer?: Transferable[]) => void;

/** Posts to the render worker. */
export type Draw = (m: ToRender, transfer?: Transferable[]) => void;

/** Render worker → UI: probe answers, recorded-frame counts and the camera (for share links). */
export type FromRender =
  | { type: 'probe'; meshPixelFraction: number }
  | { type: 'frames'; count: number; steps: number[]; bytes: number; showing: number }
  | { type: 'view'; yaw: number; pitch: number; zoom: number };

/** Render worker → UI: the answer to a probe. */
export interface RenderProbe {
  type: 'probe';
  meshPixelFraction: number;
}

/** Computation worker → its crease helper (crease-worker.ts): `WrapSession.creaseJob()`'s numbers. */
export interface CreaseRequest {
  job: Float64Array;
}

/** Crease helper → computation worker: `cloudCreases`' numbers for `WrapSession.setCreases`, or
 * null when the helper failed (the final fit then finds the creases itself). */
export interface CreaseReply {
  creases: Float64Array | null;
}

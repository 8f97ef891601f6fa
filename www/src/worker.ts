// The worker owns the wasm module and the step loops (MCF teaching demo and wraps); the UI thread
// never computes. It honours pause / cancel between steps; the page terminates and restarts it
// when a single step (or the field construction) runs too long to answer a cancel in time.
import init, {
  McfSession, WrapSession, presetSettings, settingsDocs, settingsEnums, settingAliases, catalog, demoShape, demoMesh, controlCurves, exportMesh,
  VolumeView, phantomVolume, colourRange,
} from '../pkg/lsw.js';
import type { Catalog, ColourMap, CreaseReply, CreaseRequest, FieldView, FromWorker, Histogram, McfStats, MeshTauAdvice, Outcome, Source, StartedOver, StepReport, TargetInfo, TauAdvice, ToWorker, VolumeInfo } from './protocol';
import { failureError } from './protocol';
import { lessonBatch } from './schedule';
import { colorize } from './colormap';
import { Stopwatch } from './stopwatch';

const ready = init();
/** Bytes of the wasm instance's linear memory (it only grows): the tab's memory for the core. */
let wasmMemory: WebAssembly.Memory | null = null;
void ready.then((exports) => (wasmMemory = exports.memory));
let mode: 'mcf' | 'wrap' = 'mcf';
let mcf: McfSession | null = null;
/** Steps of the lesson's whole run, from its start (for the frames' spacing). */
let lessonSteps = 0;
/** A copy of the loaded mesh for the mesh lesson (null while a point cloud or a volume is loaded). */
let lessonMesh: { positions: Float32Array; indices: Uint32Array } | null = null;
let wrap: WrapSession | null = null;
/** The last completed wrap (kept until a new one completes). */
let result: WrapSession | null = null;
let source: { bytes: Uint8Array; name: string } | null = null;
/** The source read as a voxel volume (null for meshes and clouds), and the iso-value chosen. */
let volume: { view: VolumeView; iso: number | null; frame: number } | null = null;
let wrapSettings: Record<string, unknown> = {};
let playing = false;
let msPerStep = 1;
let sentIndices = false;
let colour: ColourMap = 'distance';
/** The current wrap's working time: loading and stepping count, pauses do not. */
const clock = new Stopwatch();
let runId = 0;
/** The page's number for the current wrap, echoed in frames so the page can drop stale ones. */
let pageRun = 0;

function post(msg: FromWorker, transfer: Transferable[] = []): void {
  (self as unknown as Worker).postMessage(msg, transfer);
}

function fail(e: unknown): void {
  playing = false;
  post({ type: 'error', error: failureError(e, wasmMemory?.buffer.byteLength ?? 0, clock.currentPhase) });
}

/** Colours for a scalar of the map `map`, or null for plain shading; the range is the core's
 * (`fixed`: one kept from an earlier frame). */
function colours(map: string, values: Float32Array | null, fixed?: [number, number]): { colors: Float32Array | null; range: [number, number] } {
  if (!values) return { colors: null, range: [0, 1] };
  const [lo, hi] = fixed ?? colourRange(map, values);
  const range: [number, number] = [lo, hi];
  const colors = new Float32Array(values.length * 3);
  colorize(values, range[0], range[1], colors);
  return { colors, range };
}

// ---- MCF teaching demo -------------------------------------------------------------------------

/** The colour maps the lesson offers (the catalog's `lessonColourMaps`), the first its default. */
let lessonMaps: string[] = ['curvature'];
/** The mesh lesson keeps each map's range from its first frame: the same colour means the same
 * value all along, and a singularity forming (a thin part collapsing, where |H| explodes) shows
 * as saturated red instead of stretching the legend until the rest is one colour. */
const lessonRanges = new Map<string, [number, number]>();

function sendMcfFrame(): void {
  if (!mcf) return;
  const positions = mcf.positions();
  const normals = mcf.normals();
  const stats = mcf.stats() as McfStats;
  // A wrap's map the lesson does not have (distance, …) shows its first one.
  const map = colour === 'none' || lessonMaps.includes(colour) ? colour : lessonMaps[0];
  const values = map === 'none' ? null : mcf.scalar(map);
  const { colors, range } = colours(map, values, mcf.lesson() === 'mesh' ? lessonRanges.get(map) : undefined);
  if (values && mcf.lesson() === 'mesh' && !lessonRanges.has(map)) lessonRanges.set(map, range);
  const transfer: Transferable[] = [positions.buffer, normals.buffer];
  if (colors) transfer.push(colors.buffer);
  let indices: Uint32Array | undefined;
  if (!sentIndices) {
    indices = mcf.indices();
    transfer.push(indices.buffer);
    sentIndices = true;
  }
  const final = mcf.stepsLeft() === 0;
  post({ type: 'frame', mode: 'mcf', run: pageRun, positions, normals, indices, colors, range, colour: map, stats, playing, final }, transfer);
}

/**
 * Up to `n` lesson steps, never past its end (the core stops it at 15 % of the radius, before
 * the sphere vanishes); true when the lesson is over. A non-finite radius is a failure to
 * explain, never an end.
 */
function mcfSteps(session: McfSession, n: number): boolean {
  session.step(Math.min(n, session.stepsLeft()));
  const stats = session.stats() as McfStats;
  msPerStep = stats.msPerStep;
  const [what, value] = stats.lesson === 'sphere' ? ["sphere's mesh radius", stats.meanRadius] : ["mesh's area", stats.area];
  if (!Number.isFinite(value)) {
    throw {
      code: 'diverged',
      message: `The ${what} is no longer a number after step ${stats.step} (t = ${stats.time.toPrecision(3)}).`,
      hint: 'Choose a smaller time step τ (see the warning next to it).',
    };
  }
  return session.stepsLeft() === 0;
}

/** Replaces the lesson's session (the running wrap stops first) and posts its τ advice and first frame. */
function startLesson(make: () => McfSession): void {
  dropRun();
  mode = 'mcf';
  const next = make();
  mcf?.free();
  mcf = next;
  lessonSteps = next.stepsLeft();
  sentIndices = false;
  lessonRanges.clear();
  post({ type: 'mcf-advice', advice: next.tauAdvice() as TauAdvice | MeshTauAdvice });
  sendMcfFrame();
}

/** Why the mesh lesson cannot flow what was loaded ('' when it can). */
function lessonMeshWhy(indices: Uint32Array): string {
  if (volume) return 'A voxel volume is loaded: the lesson flows meshes. Export the wrap and drop it back in to flow it.';
  if (indices.length === 0) return 'A point cloud is loaded: it has no triangles to flow. Load a mesh, or export the wrap and drop it back in.';
  return '';
}

function mcfLoop(): void {
  if (!playing || !mcf || mode !== 'mcf') return;
  try {
    const over = mcfSteps(mcf, lessonBatch(msPerStep, lessonSteps));
    if (over) playing = false;
    sendMcfFrame();
    if (over) post({ type: 'stopped', reason: 'finished' });
    else setTimeout(mcfLoop, 0);
  } catch (e) {
    fail(e);
  }
}

// ---- Distance field view ----------------------------------------------------------------------

let fieldView: FieldView = 'off';
let fieldT = 0.5;

/** Posts the field view asked for, of the current wrap (or the kept one). */
function sendField(): void {
  const session = mode === 'wrap' ? (wrap ?? result) : null;
  if (fieldView === 'off' || !session) {
    post({ type: 'field', run: pageRun, view: fieldView, range: [0, 1], label: '' });
    return;
  }
  if (fieldView === 'iso') {
    const diagonal = (session.targetInfo() as TargetInfo).diagonal || 1;
    const o = session.fieldIsosurface(fieldT * 0.25 * diagonal) as unknown as { level: number; positions: Float32Array; indices: Uint32Array };
    const label = `isosurface d = ${o.level.toPrecision(3)} · ${o.indices.length / 3} triangles`;
    post({ type: 'field', run: pageRun, view: fieldView, iso: { positions: o.positions, indices: o.indices }, range: [o.level, o.level], label }, [o.positions.buffer, o.indices.buffer]);
    return;
  }
  const axis = fieldView === 'x' ? 0 : fieldView === 'y' ? 1 : 2;
  const o = session.fieldSlice(axis, fieldT) as unknown as { index: number; width: number; height: number; coordinate: number; corners: Float32Array; values: Float32Array };
  let lo = Infinity, hi = -Infinity;
  for (const v of o.values) if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!(hi > lo)) { lo = Number.isFinite(lo) ? lo : 0; hi = lo + 1; }
  const rgb = new Float32Array(o.values.length * 3);
  colorize(o.values, lo, hi, rgb);
  const rgba = new Uint8Array(o.values.length * 4);
  for (let i = 0; i < o.values.length; i++) {
    rgba[4 * i] = Math.round(255 * rgb[3 * i]);
    rgba[4 * i + 1] = Math.round(255 * rgb[3 * i + 1]);
    rgba[4 * i + 2] = Math.round(255 * rgb[3 * i + 2]);
    rgba[4 * i + 3] = 255;
  }
  const n = axis === 0 ? 'x' : axis === 1 ? 'y' : 'z';
  const label = `slice ${n} = ${o.coordinate.toPrecision(4)} (${o.width}×${o.height} nodes) · d ${lo.toPrecision(3)} – ${hi.toPrecision(3)}`;
  post(
    { type: 'field', run: pageRun, view: fieldView, slice: { width: o.width, height: o.height, corners: o.corners, rgba }, range: [lo, hi], label },
    [o.corners.buffer, rgba.buffer],
  );
}

// ---- Wraps -------------------------------------------------------------------------------------

/** Flat typed arrays from the npm packages' nested arrays. */
function flat(mesh: { positions: number[][]; cells: number[][] }): { p: Float32Array; c: Uint32Array } {
  return { p: Float32Array.from(mesh.positions.flat()), c: Uint32Array.from(mesh.cells.flat()) };
}

/** Bytes and a file name for a gallery id (`demo:…`). */
async function demoBytes(id: string): Promise<{ bytes: Uint8Array; name: string }> {
  const name = id.replace(/^demo:/, '');
  const sampled = name.endsWith('-points');
  const base = name.replace(/-points$/, '');
  if (base === 'bunny' || base === 'teapot') {
    const mod = base === 'bunny' ? await import('bunny') : await import('teapot');
    const { p, c } = flat((mod as unknown as { default: { positions: number[][]; cells: number[][] } }).default ?? mod);
    return { bytes: demoMesh(p, c, sampled ? 30000 : 0, 1), name: `${name}.ply` };
  }
  if (base === 'phantom') return { bytes: phantomVolume(96), name: 'phantom.nii' };
  return { bytes: demoShape(base), name: `${name}.ply` };
}

/** Opens the source as a voxel volume when it is one (NIfTI, NRRD, VTI, MetaImage). */
function openVolume(input: { bytes: Uint8Array; name: string }): void {
  volume?.view.free();
  volume = null;
  try {
    volume = { view: new VolumeView(input.bytes, input.name, 0), iso: null, frame: 0 };
  } catch {
    // Not a volume: the wrap reads it as a mesh or cloud (and reports its own errors).
  }
}

/** Posts the volume's facts and histogram, and the iso-value being wrapped. */
function postVolume(): void {
  if (!volume) return;
  const info = volume.view.info() as VolumeInfo;
  const h = volume.view.histogram(128) as { min: number; max: number; counts: Float64Array };
  const iso = volume.iso ?? info.otsu ?? 0.5 * (info.min + info.max);
  post({ type: 'volume', run: pageRun, info, histogram: h, iso }, [h.counts.buffer]);
}

/** Downloads a URL, turning network and CORS refusals into a readable error. */
async function fetchBytes(url: string): Promise<{ bytes: Uint8Array; name: string }> {
  let res: Response;
  try {
    res = await fetch(url, { mode: 'cors' });
  } catch {
    throw {
      code: 'network',
      message: `Could not download ${url}: the network refused, or the server does not allow other sites to read the file (CORS).`,
      hint: 'Check the address; the server must send Access-Control-Allow-Origin. Or download the file and drop it on the page.',
    };
  }
  if (!res.ok) throw { code: 'http', message: `Downloading ${url} failed: HTTP ${res.status} ${res.statusText}.`, hint: 'Check the address, or download the file and drop it on the page.' };
  const name = decodeURIComponent(new URL(url).pathname.split('/').pop() || 'download');
  return { bytes: new Uint8Array(await res.arrayBuffer()), name };
}

async function sourceBytes(s: Source): Promise<{ bytes: Uint8Array; name: string }> {
  if (s.kind === 'bytes') return { bytes: new Uint8Array(s.bytes), name: s.name };
  if (s.kind === 'demo') return demoBytes(s.id);
  return fetchBytes(s.url);
}

function scalarOf(session: WrapSession): Float32Array | null {
  if (colour === 'none') return null;
  return session.scalar(colour);
}

/** Reports of the steps taken since the last frame. */
let pendingReports: StepReport[] = [];

function sendWrapFrame(session: WrapSession): void {
  const was = clock.currentPhase;
  clock.phase('frames');
  const positions = session.positions();
  const normals = session.normals();
  const indices = session.indices();
  const values = scalarOf(session);
  const { colors, range } = colours(colour, values);
  const report = session.report() as StepReport | undefined;
  const histogram = session.kappaHistogram(40, 2.0) as Histogram;
  const transfer: Transferable[] = [positions.buffer, normals.buffer, indices.buffer];
  if (colors) transfer.push(colors.buffer);
  post(
    {
      type: 'frame', mode: 'wrap', run: pageRun, positions, normals, indices, colors, range, colour, report, reports: pendingReports, histogram, playing,
      stepLimit: session.stepLimit(), elapsedMs: clock.ms,
    },
    transfer,
  );
  pendingReports = [];
  clock.phase(was);
}

function finish(session: WrapSession): void {
  stopCreaseHelper();
  playing = false;
  clock.resume(); // (a single step from the page runs with the clock paused)
  clock.phase('certificate');
  if (result && result !== session) result.free();
  result = session;
  const positions = session.positions();
  const normals = session.normals();
  const indices = session.indices();
  const report = session.report() as StepReport | undefined;
  post({ type: 'loading', what: 'Checking the result (certificate)…' });
  const outcome = session.outcome() as Outcome;
  clock.pause();
  post(
    {
      type: 'result', run: pageRun, hash: session.resultHash(), name: source?.name ?? 'result', positions, normals, indices, elapsedMs: clock.ms, phases: clock.phases(), steps: report?.step ?? 0,
      certificate: outcome.certificate, verdict: outcome.verdict, stopReason: session.stopReason() ?? null, start: session.startSurface(), wasmBytes: wasmMemory?.buffer.byteLength ?? 0,
      isolated: session.isolatedPoints(),
      specks: session.specksLeftOut(),
      startedOver: (session.startedOver() as StartedOver | undefined) ?? null,
    },
    [positions.buffer, normals.buffer, indices.buffer],
  );
  post({ type: 'stopped', reason: 'finished' });
}

/** Shortest time between two frames of a running wrap. A frame costs the page a mesh upload, a
 * software-rendered draw and plot redraws: at ~30 frames a second these took the cores that the
 * wrap and the page's own tasks need (main-thread tasks of over 100 ms on a loaded 2-core
 * machine); ~12 a second still reads as motion. */
const FRAME_MS = 80;
let lastFrameAt = -Infinity;

/** Runs steps for about 30 ms, posts a frame when FRAME_MS have passed (and at the end), and
 * yields so pause / cancel get through. */
function wrapLoop(id: number): void {
  if (!playing || !wrap || mode !== 'wrap' || id !== runId) return;
  const session = wrap;
  try {
    const t0 = performance.now();
    clock.phase('steps');
    let done = session.isDone();
    while (!done && performance.now() - t0 < 30) {
      done = session.step(1);
      pendingReports.push(session.report() as StepReport);
    }
    if (done || performance.now() - lastFrameAt >= FRAME_MS) {
      lastFrameAt = performance.now();
      sendWrapFrame(session);
    }
    if (done) finish(session);
    else setTimeout(() => wrapLoop(id), 0);
  } catch (e) {
    dropRun();
    fail(e);
  }
}

/** The helper finding the running wrap's cloud creases (crease-worker.ts), while it works. */
let creaseHelper: Worker | null = null;

/** Hands a cloud's crease detection to a helper worker, which runs it on the other core while
 * the steps run here; its answer goes to the session before the final fit (which finds them
 * itself, the same, if none came by then). */
function startCreaseHelper(session: WrapSession): void {
  stopCreaseHelper();
  // (A browser without workers inside workers leaves them to the fit.)
  if (typeof Worker === 'undefined') return;
  const job = session.creaseJob();
  if (!job) return;
  let helper: Worker;
  try {
    helper = new Worker(new URL('./crease-worker.ts', import.meta.url), { type: 'module' });
  } catch {
    return;
  }
  creaseHelper = helper;
  helper.onmessage = (ev: MessageEvent<CreaseReply>) => {
    if (creaseHelper !== helper) return;
    stopCreaseHelper();
    if (!ev.data.creases || wrap !== session) return;
    try {
      session.setCreases(ev.data.creases);
    } catch {
      // (Not creases after all: the fit finds them itself.)
    }
  };
  helper.onerror = () => {
    if (creaseHelper === helper) stopCreaseHelper();
  };
  const request: CreaseRequest = { job };
  helper.postMessage(request, [job.buffer]);
}

/** Ends the crease helper (its memory goes with it). */
function stopCreaseHelper(): void {
  creaseHelper?.terminate();
  creaseHelper = null;
}

/** Forgets the running wrap (the kept result stays). */
function dropRun(): void {
  stopCreaseHelper();
  playing = false;
  pendingReports = [];
  runId++;
  if (wrap && wrap !== result) wrap.free();
  wrap = null;
}

async function loadWrap(src: Source, settings: Record<string, unknown>, autoplay: boolean, iso?: number): Promise<void> {
  dropRun();
  const id = runId;
  mode = 'wrap';
  clock.restart(src.kind === 'url' ? 'downloading' : 'reading');
  post({ type: 'loading', what: src.kind === 'url' ? 'Downloading…' : 'Reading…' });
  const input = await sourceBytes(src);
  if (id !== runId) return;
  source = input;
  openVolume(input);
  if (volume && iso !== undefined) volume.iso = iso;
  wrapSettings = settings;
  await startSession(autoplay, id);
}

async function startSession(autoplay: boolean, id: number): Promise<void> {
  if (!source) return;
  post({ type: 'loading', what: 'Building the distance field…' });
  // Let the status message out before the (possibly long) construction.
  await new Promise((r) => setTimeout(r, 0));
  if (id !== runId) return;
  if (volume) postVolume();
  // The core reports its long phases (field build, start surface, final fit) as they run.
  // (Its phases time the run too; between them the time counts as "other".)
  const progress = (phase: string, fraction: number) => {
    clock.phase(fraction < 1 ? phase : 'other');
    post({ type: 'progress', phase, fraction });
  };
  const session = volume
    ? WrapSession.fromVolumeView(volume.view, JSON.stringify(wrapSettings), volume.iso ?? undefined, false, progress)
    : new WrapSession(source.bytes, source.name, JSON.stringify(wrapSettings), progress);
  wrap = session;
  startCreaseHelper(session);
  const tp = session.targetPositions();
  const ti = session.targetIndices();
  const why = lessonMeshWhy(ti);
  lessonMesh = why ? null : { positions: tp.slice(), indices: ti.slice() };
  post({ type: 'target', run: pageRun, positions: tp, indices: ti, info: session.targetInfo() as TargetInfo, name: source.name, lessonMesh: why }, [tp.buffer, ti.buffer]);
  sendWrapFrame(session);
  if (fieldView !== 'off') sendField();
  if (autoplay) {
    playing = true;
    wrapLoop(id);
  } else {
    clock.pause();
    post({ type: 'stopped', reason: 'ready' });
  }
}

self.onmessage = async (ev: MessageEvent<ToWorker>) => {
  await ready;
  const msg = ev.data;
  try {
    switch (msg.type) {
      case 'mcf-init':
        startLesson(() => new McfSession(msg.params.level, msg.params.radius, msg.params.tau));
        break;
      case 'mcf-mesh-init':
        startLesson(() => {
          if (!lessonMesh) throw { code: 'bad-target', message: 'No mesh is loaded to flow.', hint: 'Load a mesh (drop one, or pick Bunny mesh or Teapot mesh), then choose MCF on the loaded mesh.' };
          return McfSession.fromMesh(lessonMesh.positions, lessonMesh.indices, msg.tau);
        });
        break;
      case 'wrap-load':
        pageRun = msg.run;
        await loadWrap(msg.source, msg.settings, msg.autoplay, msg.iso);
        break;
      case 'play':
        if (playing) break;
        playing = true;
        if (mode === 'mcf') mcfLoop();
        else if (wrap) {
          if (wrap === result || wrap.isDone()) {
            playing = false;
            post({ type: 'stopped', reason: 'finished' });
          } else {
            clock.resume();
            wrapLoop(runId);
          }
        } else {
          playing = false;
          post({ type: 'stopped', reason: 'paused' });
        }
        break;
      case 'pause':
        playing = false;
        clock.pause();
        // The steps since the last frame (frames are paced) show before the pause is reported.
        if (mode === 'wrap' && wrap && pendingReports.length > 0) sendWrapFrame(wrap);
        post({ type: 'stopped', reason: 'paused' });
        break;
      case 'cancel':
        if (mode === 'wrap') dropRun();
        playing = false;
        clock.pause();
        post({ type: 'stopped', reason: 'cancelled' });
        break;
      case 'colour':
        colour = msg.map;
        if (!playing) {
          if (mode === 'mcf') sendMcfFrame();
          else if (wrap ?? result) sendWrapFrame((wrap ?? result)!);
        }
        break;
      case 'step':
        playing = false;
        if (mode === 'mcf') {
          if (mcf && mcfSteps(mcf, msg.n)) post({ type: 'stopped', reason: 'finished' });
          sendMcfFrame();
        } else if (wrap && wrap !== result) {
          clock.resume();
          clock.phase('steps');
          const done = wrap.step(msg.n);
          clock.pause();
          pendingReports.push(wrap.report() as StepReport);
          sendWrapFrame(wrap);
          if (done) finish(wrap);
        }
        break;
      case 'export': {
        const session = result ?? wrap;
        let bytes: Uint8Array;
        if (session) bytes = session.export(msg.format);
        else if (msg.kept) bytes = exportMesh(msg.kept.positions, msg.kept.indices, msg.format);
        else throw { code: 'no-result', message: 'There is no result to export yet.', hint: 'Drop a file or pick a demo, and let the wrap finish.' };
        post({ type: 'exported', bytes, format: msg.format }, [bytes.buffer]);
        break;
      }
      case 'curves':
        post({ type: 'curves', curves: controlCurves(JSON.stringify(msg.settings), 121) });
        break;
      case 'volume-iso':
        if (mode === 'wrap' && source && volume) {
          pageRun = msg.run;
          dropRun();
          volume.iso = msg.iso;
          if (msg.frame !== volume.frame) {
            const view = new VolumeView(source.bytes, source.name, msg.frame);
            volume.view.free();
            volume.view = view;
            volume.frame = msg.frame;
          }
          wrapSettings = msg.settings;
          clock.restart('setup');
          await startSession(true, runId);
        }
        break;
      case 'volume-slice':
        if (volume) {
          const [nx, ny, nz] = (volume.view.info() as VolumeInfo).dims;
          const [width, height] = msg.axis === 0 ? [ny, nz] : msg.axis === 1 ? [nx, nz] : [nx, ny];
          const values = volume.view.slice(msg.axis, msg.index);
          post({ type: 'volume-slice', axis: msg.axis, index: msg.index, width, height, values }, [values.buffer]);
        }
        break;
      case 'field':
        fieldView = msg.view;
        fieldT = Math.min(1, Math.max(0, Number.isFinite(msg.t) ? msg.t : 0.5));
        sendField();
        break;
    }
  } catch (e) {
    if (msg.type === 'wrap-load' || msg.type === 'volume-iso') dropRun();
    fail(e);
  }
};

ready.then(
  () => {
    const lists = JSON.parse(catalog()) as Catalog;
    lessonMaps = lists.lessonColourMaps;
    const presets: Record<string, Record<string, unknown>> = {};
    for (const p of lists.presets) presets[p] = JSON.parse(presetSettings(p));
    post({ type: 'ready', presets, docs: JSON.parse(settingsDocs()), enums: JSON.parse(settingsEnums()), aliases: JSON.parse(settingAliases()), catalog: lists });
  },
  (e) => fail(e),
);

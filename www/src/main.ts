// Wiring only: UI events → worker messages; worker frames → render worker, plots and status.
// The UI thread neither computes nor draws: the flow runs in one worker, three.js in another.
import type { Certificate, ColourMap, FieldView, FromRender, FromWorker, McfParams, Source, StepReport, TargetInfo, ToRender, ToWorker, UiError } from './protocol';
import { HistogramPlot, LinePlot, RadiusPlot } from './plots';
import { SettingsPanel } from './panel';
import { decode, DEFAULT_VIEW, encode, flatten, validDataset, type Flat, type ViewState } from './share';
import { explain, showCertificate, showPending } from './health';
import { VolumePanel } from './volume';

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;
const status = $('status');
const health = $('health');
const canvas = $<HTMLCanvasElement>('canvas');
const plot = new RadiusPlot($('plot'));
const distancePlot = new LinePlot($('plot-distance'), 'Distance to target per step', ['mean |d|', 'max |d|'], ['#4aa3ff', '#ff7a59'], { log: true });
const covolumePlot = new LinePlot($('plot-covolume'), 'Co-volume min / mean / max', ['min', 'mean', 'max'], ['#ff7a59', '#4aa3ff', '#9fd39f'], { log: true });
const verticesPlot = new LinePlot($('plot-vertices'), 'Vertices', ['vertices'], ['#ffb347']);
const kappaPlot = new HistogramPlot($('plot-kappa'), 'κ(J_Δ) of the current frame (1 = equilateral)', 'κ');
const controlPlot = new LinePlot($('plot-controls'), 'Controls ε(δ), η(δ) (stabilised units)', ['ε', 'η facing', 'η side-on'], ['#4aa3ff', '#ffb347', '#ff7a59'], { xLabel: 'δ = d − d₀' });
const renderer = new Worker(new URL('./render-worker.ts', import.meta.url), { type: 'module' });
const draw = (m: ToRender, transfer: Transferable[] = []) => renderer.postMessage(m, transfer);

type State = 'idle' | 'loading' | 'running' | 'done' | 'invalid' | 'error';
type Mode = 'mcf' | 'wrap';

let worker: Worker;
let mode: Mode = 'mcf';
let panel: SettingsPanel | null = null;
let presetsFlat: Record<string, Flat> = {};
/** Dataset of the current wrap for share links: a gallery id or URL; null for a dropped file. */
let dataset: string | null = null;
let inputName = 'result';
let view: ViewState = { ...DEFAULT_VIEW };
/** The last completed wrap, kept so that cancel / errors can show it again and export it. */
let kept: { positions: Float32Array; normals: Float32Array; indices: Uint32Array; hash: string; name: string; target: { positions: Float32Array; indices: Uint32Array } | null; valid: boolean; why: string; certificate: Certificate; stopReason: string | null } | null = null;
let currentTarget: { positions: Float32Array; indices: Uint32Array } | null = null;
let cancelTimer: ReturnType<typeof setTimeout> | null = null;
let restarting = false;
let runStart = 0;
let lastDoneMs = 0;
/** Size of the core's wasm memory at the last result (bytes). */
let wasmBytes = 0;
/** Number of the current wrap run; frames of older runs still in flight are ignored. */
let runSeq = 0;

const send = (m: ToWorker, transfer: Transferable[] = []) => worker.postMessage(m, transfer);
/** Volumes: the iso-value chosen in the panel (for share links), and one asked for by a link. */
let volumeIso: number | null = null;
let linkIso: number | null = null;
const volumePanel = new VolumePanel($('volume'), {
  onIso: (iso, frame) => {
    if (!panel) return;
    volumeIso = Number(iso.toPrecision(6));
    updateShare();
    setState('loading', `Wrapping at iso-value ${iso.toPrecision(4)}…`);
    send({ type: 'volume-iso', iso, frame, settings: panel.settings(), run: ++runSeq });
  },
  onSlice: (axis, index) => send({ type: 'volume-slice', axis, index }),
});

function setState(state: State, text: string): void {
  status.dataset.state = state;
  status.textContent = text;
  const running = state === 'running';
  $<HTMLButtonElement>('play').disabled = running || state === 'loading';
  $<HTMLButtonElement>('pause').disabled = !running;
  $<HTMLButtonElement>('cancel').disabled = !(running || state === 'loading') || mode !== 'wrap';
}

function showError(e: UiError | null): void {
  const el = $('error');
  el.hidden = !e;
  el.textContent = e ? `${e.message}${e.hint ? ' — ' + e.hint : ''}` : '';
}

function showNotice(lines: string[]): void {
  const el = $('notice');
  el.hidden = lines.length === 0;
  el.textContent = lines.length ? `${lines.join(' ')} (click to dismiss)` : '';
}

function setMode(m: Mode): void {
  mode = m;
  $('hash').hidden = m === 'mcf';
  $('mcf-box').hidden = m !== 'mcf';
  $('mcf-plots').hidden = m !== 'mcf';
  $('wrap-plots').hidden = m !== 'wrap';
}

// ---- Rendering setup and camera ---------------------------------------------------------------

if (!('transferControlToOffscreen' in canvas)) {
  showError({ code: 'unsupported', message: 'This browser cannot draw from a worker (no OffscreenCanvas).', hint: 'Use a current Chrome, Edge, Firefox or Safari (16.4 or newer).' });
  setState('error', 'Unsupported browser');
} else {
  const offscreen = canvas.transferControlToOffscreen();
  draw({ type: 'init', canvas: offscreen, width: canvas.clientWidth, height: canvas.clientHeight, pixelRatio: Math.min(2, devicePixelRatio) }, [offscreen]);
  new ResizeObserver(() => draw({ type: 'resize', width: canvas.clientWidth, height: canvas.clientHeight })).observe(canvas);
}

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
$('fit').onclick = () => draw({ type: 'fit' });
$('notice').onclick = () => ($('notice').hidden = true);

let frameSteps: number[] = [];
renderer.addEventListener('message', (ev: MessageEvent<FromRender>) => {
  const m = ev.data;
  if (m.type === 'view') {
    view = { ...view, yaw: m.yaw, pitch: m.pitch, zoom: m.zoom };
    updateShare();
  } else if (m.type === 'frames') {
    const s = $<HTMLInputElement>('scrub');
    const atEnd = Number(s.value) >= Number(s.max);
    frameSteps = m.steps;
    s.max = String(Math.max(0, m.count - 1));
    s.disabled = m.count < 2;
    if (atEnd || m.showing < 0) s.value = s.max;
    $('scrub-label').textContent = m.count ? `step ${frameSteps[Number(s.value)] ?? '–'} · ${m.count} frames, ${(m.bytes / 1048576).toFixed(1)} MB` : '';
  }
});
$<HTMLInputElement>('scrub').oninput = (e) => {
  const s = e.target as HTMLInputElement;
  const i = Number(s.value);
  draw({ type: 'show-frame', index: i >= Number(s.max) ? -1 : i });
  $('scrub-label').textContent = `step ${frameSteps[i] ?? '–'}`;
};

// ---- Share links ------------------------------------------------------------------------------

function shareHash(): string {
  const iso = mode === 'wrap' && volumeIso !== null ? volumeIso : undefined;
  return encode({ dataset: mode === 'mcf' ? 'demo:mcf' : dataset, preset: panel?.preset ?? 'full-wrap', changed: panel?.changed() ?? {}, view, iso });
}

function updateShare(): void {
  if (!panel) return;
  const hash = shareHash();
  history.replaceState(null, '', `${location.pathname}#${hash}`);
  $<HTMLInputElement>('share-url').value = location.href;
}

$('copy-link').onclick = async () => {
  updateShare();
  const url = $<HTMLInputElement>('share-url').value;
  if (mode === 'wrap' && !dataset) showNotice(['A dropped file cannot travel in a link: the link keeps the settings and view; the receiver drops the same file.']);
  try {
    await navigator.clipboard.writeText(url);
    $('copy-link').textContent = 'Copied ✓';
  } catch {
    $<HTMLInputElement>('share-url').select();
    $('copy-link').textContent = 'Select and copy the link below';
  }
  setTimeout(() => ($('copy-link').textContent = 'Copy link'), 2000);
};

// ---- Starting things --------------------------------------------------------------------------

function mcfParams(): McfParams {
  return { level: Number($<HTMLSelectElement>('level').value), radius: 1, tau: Number($<HTMLInputElement>('tau').value) };
}

/** The distance-field control: shown once a wrap's target is loaded. */
let fieldShown: { view: FieldView; label: string; width: number; height: number; triangles: number } = { view: 'off', label: '', width: 0, height: 0, triangles: 0 };
function fieldView(): FieldView {
  return $<HTMLSelectElement>('field-view').value as FieldView;
}
function sendField(): void {
  send({ type: 'field', view: fieldView(), t: Number($<HTMLInputElement>('field-t').value) });
}
function hideField(): void {
  $('field-box').hidden = true;
  draw({ type: 'field' });
  fieldShown = { view: 'off', label: '', width: 0, height: 0, triangles: 0 };
}

function mcfReset(): void {
  setMode('mcf');
  hideField();
  showError(null);
  plot.clear();
  draw({ type: 'clear-frames' });
  draw({ type: 'target', positions: new Float32Array(0), indices: null });
  draw({ type: 'refit' });
  send({ type: 'mcf-init', params: mcfParams() });
  setState('idle', 'Ready');
  updateShare();
}

function clearWrapPlots(): void {
  distancePlot.clear();
  covolumePlot.clear();
  verticesPlot.clear();
  kappaPlot.clear();
}

/** Starts a wrap of `source` with the panel's settings (the kept result stays until it completes). */
function startWrap(source: Source, ds: string | null, name: string): void {
  if (!panel) return;
  setMode('wrap');
  showError(null);
  dataset = ds;
  inputName = name;
  clearWrapPlots();
  draw({ type: 'clear-frames' });
  draw({ type: 'refit' });
  draw({ type: 'field' });
  runStart = performance.now();
  setState('loading', `Loading ${name}…`);
  showPending(health, 'certificate: when the wrap ends');
  $('hash').textContent = kept ? `previous result ${kept.hash.slice(0, 12)}` : '';
  volumePanel.hide();
  volumeIso = linkIso;
  linkIso = null;
  send({ type: 'wrap-load', source, settings: panel.settings(), autoplay: true, run: ++runSeq, iso: volumeIso ?? undefined }, source.kind === 'bytes' ? [source.bytes] : []);
  updateShare();
}

function startDemo(id: string): void {
  if (id === 'mcf') {
    mcfReset();
    return;
  }
  startWrap({ kind: 'demo', id: `demo:${id}` }, `demo:${id}`, id);
}

async function openFile(file: File): Promise<void> {
  const bytes = await file.arrayBuffer();
  startWrap({ kind: 'bytes', bytes, name: file.name }, null, file.name);
}

function openUrl(url: string): void {
  if (!validDataset(url) || url.startsWith('demo:')) {
    showError({ code: 'bad-url', message: `"${url.slice(0, 80)}" is not an http(s) address.`, hint: 'Give a full address such as https://example.org/scan.ply.' });
    return;
  }
  startWrap({ kind: 'url', url }, url, decodeURIComponent(new URL(url).pathname.split('/').pop() || 'download'));
}

/** Shows the kept result again (after a cancel or a failed run). */
function restoreKept(): void {
  if (!kept) return;
  draw({ type: 'geometry', positions: kept.positions.slice(), normals: kept.normals.slice(), indices: kept.indices.slice(), colors: null });
  if (kept.target) draw({ type: 'target', positions: kept.target.positions.slice(), indices: kept.target.indices.slice() });
  $('hash').textContent = `result ${kept.hash.slice(0, 12)}`;
  $('hash').dataset.hash = kept.hash;
  // The badge certifies what is on screen: the kept result again.
  showCertificate(health, kept.certificate, kept.stopReason);
}

// ---- Worker messages --------------------------------------------------------------------------

const LEGEND: Record<ColourMap, string> = {
  none: '', distance: 'distance to target |d|', curvature: 'mean curvature H', kappa: 'κ(J_Δ) (1 = equilateral)', covolume: 'co-volume (stabilised)', features: 'feature vertices (1)',
};

function onFrame(msg: Extract<FromWorker, { type: 'frame' }>): void {
  if (msg.mode !== mode || (mode === 'wrap' && msg.run !== runSeq)) return; // a stale frame still in flight
  const transfer: Transferable[] = [msg.positions.buffer, msg.normals.buffer];
  if (msg.indices) transfer.push(msg.indices.buffer);
  if (msg.colors) transfer.push(msg.colors.buffer);
  const step = msg.mode === 'mcf' ? msg.stats?.step ?? 0 : msg.report?.step ?? 0;
  draw({ type: 'geometry', positions: msg.positions, normals: msg.normals, indices: msg.indices, colors: msg.colors, step, record: msg.mode === 'wrap', final: !!msg.report?.done }, transfer);
  $('legend').hidden = !msg.colors;
  $('legend-title').textContent = LEGEND[msg.colour];
  $('legend-min').textContent = msg.range[0].toPrecision(4);
  $('legend-max').textContent = msg.range[1].toPrecision(4);
  if (msg.mode === 'mcf' && msg.stats) {
    const s = msg.stats;
    plot.push(s.time, s.meanRadius, s.exactRadius);
    const err = s.exactRadius > 0 ? (100 * (s.meanRadius - s.exactRadius)) / s.exactRadius : NaN;
    $('stats').textContent =
      `step ${s.step}   t = ${s.time.toFixed(4)}\n` +
      `mean radius ${s.meanRadius.toFixed(5)}   exact ${s.exactRadius.toFixed(5)}   (${err.toFixed(3)} %)\n` +
      `co-volume min/mean/max ${s.covolumeMin.toExponential(2)} / ${s.covolumeMean.toExponential(2)} / ${s.covolumeMax.toExponential(2)}\n` +
      `solver ${s.solverIterations} it, residual ${s.solverResidual.toExponential(1)}   ${s.msPerStep.toFixed(2)} ms/step\n` +
      `${s.vertices} vertices, ${s.faces} faces`;
    $('stats').dataset.step = String(s.step);
    $('progress').hidden = true;
    $('progress-text').textContent = '';
    if (msg.playing) setState('running', `Running — step ${s.step}`);
    return;
  }
  const r: StepReport | null | undefined = msg.report;
  if (msg.histogram) kappaPlot.set(msg.histogram.lo, msg.histogram.hi, msg.histogram.counts);
  const limit = msg.stepLimit ?? 0;
  const el = ((msg.elapsedMs ?? 0) / 1000).toFixed(1);
  const p = $<HTMLProgressElement>('progress');
  p.hidden = false;
  p.max = Math.max(1, limit);
  p.value = r?.step ?? 0;
  const verts = r?.vertices ?? msg.positions.length / 3;
  $('progress-text').textContent = `step ${r?.step ?? 0}/${limit} · ${verts} vertices · ${el} s`;
  $('stats').dataset.step = String(r?.step ?? 0);
  for (const q of msg.reports ?? []) {
    distancePlot.push(q.step, Math.max(1e-9, q.distance_mean), Math.max(1e-9, q.distance_max));
    covolumePlot.push(q.step, Math.max(1e-12, q.covolume_min), q.covolume_mean, q.covolume_max);
    verticesPlot.push(q.step, q.vertices);
  }
  if (r) {
    $('stats').textContent =
      `step ${r.step}   τ = ${r.tau.toPrecision(3)}${r.retries ? ` (${r.retries} retries)` : ''}\n` +
      `distance mean ${r.distance_mean.toExponential(2)}  max ${r.distance_max.toExponential(2)}\n` +
      `settled ${(100 * r.settled_fraction).toFixed(1)} %   ${r.vertices} vertices, ${r.faces} faces\n` +
      `ms: assembly ${r.times.assembly.toFixed(0)}  solve ${r.times.solve.toFixed(0)}  remesh ${r.times.remesh.toFixed(0)}  total ${r.times.total.toFixed(0)}`;
  }
  if (msg.playing) setState('running', `Wrapping ${inputName} — step ${r?.step ?? 0}`);
}

function onWorkerMessage(ev: MessageEvent<FromWorker>): void {
  const msg = ev.data;
  switch (msg.type) {
    case 'ready':
      if (restarting) {
        restarting = false;
        return;
      }
      onReady(msg.presets, msg.docs, msg.enums);
      break;
    case 'frame':
      onFrame(msg);
      break;
    case 'loading':
      setState('loading', msg.what);
      break;
    case 'target': {
      if (msg.run !== runSeq) break;
      currentTarget = { positions: msg.positions.slice(), indices: msg.indices.slice() };
      draw({ type: 'target', positions: msg.positions, indices: msg.indices.length ? msg.indices : null }, [msg.positions.buffer, msg.indices.buffer]);
      const i: TargetInfo = msg.info;
      $('field-box').hidden = false;
      $('target-info').textContent = `${msg.name}: ${i.format}, ${i.kind === 'points' ? `${i.points} points` : `${i.points} vertices, ${i.triangles} triangles`}, diagonal ${i.diagonal.toPrecision(4)}`;
      break;
    }
    case 'result': {
      if (msg.run !== runSeq) break;
      const valid = msg.certificate.valid && !msg.stopReason;
      kept = { positions: msg.positions, normals: msg.normals, indices: msg.indices, hash: msg.hash, name: msg.name, target: currentTarget, valid, why: explain(msg.certificate, msg.stopReason), certificate: msg.certificate, stopReason: msg.stopReason };
      showCertificate(health, msg.certificate, msg.stopReason);
      wasmBytes = msg.wasmBytes;
      lastDoneMs = performance.now() - runStart;
      $('hash').textContent = `result ${msg.hash.slice(0, 12)}`;
      $('hash').dataset.hash = msg.hash;
      $('hash').dataset.ms = String(Math.round(lastDoneMs));
      draw({ type: 'fit' });
      break;
    }
    case 'stopped':
      if (cancelTimer) {
        clearTimeout(cancelTimer);
        cancelTimer = null;
      }
      if (msg.reason === 'finished' && mode === 'wrap' && kept && !kept.valid) setState('invalid', `Not valid — ${kept.why}`);
      else if (msg.reason === 'finished') setState('done', mode === 'mcf' ? 'Done — the sphere has shrunk to 15 % of its radius' : `Done — ${inputName} wrapped in ${(lastDoneMs / 1000).toFixed(1)} s`);
      else if (msg.reason === 'cancelled') {
        setState('idle', 'Cancelled');
        restoreKept();
      } else setState('idle', 'Paused');
      break;
    case 'exported': {
      // An invalid result is only ever exported under a name that says so.
      const stem = ((kept?.name ?? inputName).replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_') || 'result') + (kept && !kept.valid ? '-NOT-VALID' : '');
      const blob = new Blob([msg.bytes as BlobPart], { type: 'application/octet-stream' });
      const a = document.createElement('a');
      a.href = URL.createObjectURL(blob);
      a.download = `${stem}-wrapped.${msg.format}`;
      document.body.appendChild(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(a.href), 10000);
      break;
    }
    case 'field': {
      if (mode !== 'wrap' || msg.run !== runSeq) break;
      const transfer: Transferable[] = [];
      if (msg.slice) transfer.push(msg.slice.corners.buffer, msg.slice.rgba.buffer);
      if (msg.iso) transfer.push(msg.iso.positions.buffer, msg.iso.indices.buffer);
      fieldShown = { view: msg.view, label: msg.label, width: msg.slice?.width ?? 0, height: msg.slice?.height ?? 0, triangles: (msg.iso?.indices.length ?? 0) / 3 };
      draw({ type: 'field', slice: msg.slice, iso: msg.iso }, transfer);
      $('field-label').textContent = msg.label;
      break;
    }
    case 'volume':
      if (msg.run === runSeq) volumePanel.show(msg.info, msg.histogram, msg.iso);
      break;
    case 'volume-slice':
      volumePanel.slice(msg);
      break;
    case 'curves':
      controlPlot.set([msg.curves.delta, msg.curves.epsilon, msg.curves.eta_facing, msg.curves.eta_side]);
      break;
    case 'error':
      if (cancelTimer) {
        clearTimeout(cancelTimer);
        cancelTimer = null;
      }
      showError(msg.error);
      setState('error', 'Error');
      if (mode === 'wrap') restoreKept();
      // After a panic or an allocation failure the wasm instance may be unusable: start afresh.
      if (msg.error.code === 'internal' || msg.error.code === 'out-of-memory') restartWorker();
      break;
  }
}

function startWorker(): void {
  worker = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
  worker.onmessage = onWorkerMessage;
  worker.onerror = (e: ErrorEvent) => {
    showError({ code: 'worker', message: `The computation worker failed: ${e.message}`, hint: 'The page restarts it; try a smaller grid or another preset.' });
    setState('error', 'Error');
  };
}
startWorker();
renderer.onerror = (e: ErrorEvent) => {
  showError({ code: 'worker', message: `The render worker failed: ${e.message}`, hint: 'Reload the page.' });
  setState('error', 'Error');
};

/** Stops a run: asks the worker, and terminates and restarts it if it does not answer in 120 ms. */
function cancel(): void {
  send({ type: 'cancel' });
  if (cancelTimer) return;
  cancelTimer = setTimeout(() => {
    cancelTimer = null;
    restartWorker();
    setState('idle', 'Cancelled (worker restarted)');
    restoreKept();
  }, 120);
}

/** Replaces the computation worker (the kept result lives on in this thread). */
function restartWorker(): void {
  worker.terminate();
  restarting = true;
  startWorker();
  send({ type: 'colour', map: view.cmap as ColourMap });
  sendField();
}

function onReady(presets: Record<string, Record<string, unknown>>, docs: Record<string, string>, enums: Record<string, string[]>): void {
  presetsFlat = Object.fromEntries(Object.entries(presets).map(([k, v]) => [k, flatten(v)]));
  panel = new SettingsPanel($('gui'), presetsFlat, docs, enums, () => {
    send({ type: 'curves', settings: panel!.settings() });
    updateShare();
  });
  const params = new URLSearchParams(location.search);
  const { state, notices } = decode(location.hash, presetsFlat);
  const src = params.get('src');
  if (src !== null) {
    if (validDataset(src) && !src.startsWith('demo:')) state.dataset = src;
    else notices.push(`Ignored ?src=${src.slice(0, 60)}: not an http(s) address.`);
  }
  showNotice(notices);
  panel.set(state.preset, state.changed);
  $<HTMLSelectElement>('preset').value = panel.preset;
  view = state.view;
  $<HTMLInputElement>('wireframe').checked = view.wire;
  $<HTMLInputElement>('smooth').checked = view.smooth;
  $<HTMLSelectElement>('cmap').value = view.cmap;
  draw({ type: 'wireframe', on: view.wire });
  draw({ type: 'smooth', on: view.smooth });
  draw({ type: 'set-view', yaw: view.yaw, pitch: view.pitch, zoom: view.zoom });
  send({ type: 'colour', map: view.cmap as ColourMap });
  send({ type: 'curves', settings: panel.settings() });
  const d = state.dataset;
  linkIso = state.iso ?? null;
  if (d && d !== 'demo:mcf') {
    if (d.startsWith('demo:')) startDemo(d.slice(5));
    else openUrl(d);
  } else mcfReset();
}

// ---- Controls ---------------------------------------------------------------------------------

$('play').onclick = () => {
  showError(null);
  send({ type: 'play' });
  setState('running', 'Running');
};
$('pause').onclick = () => send({ type: 'pause' });
$('step').onclick = () => send({ type: 'step', n: 1 });
$('cancel').onclick = cancel;
$('reset').onclick = () => {
  if (mode === 'mcf') mcfReset();
  else {
    showError(null);
    clearWrapPlots();
    draw({ type: 'clear-frames' });
    runStart = performance.now();
    send({ type: 'reset', settings: panel!.settings(), run: ++runSeq });
  }
};
$('level').onchange = mcfReset;
$('tau').onchange = mcfReset;
$<HTMLSelectElement>('preset').onchange = (e) => {
  panel?.set((e.target as HTMLSelectElement).value);
  send({ type: 'curves', settings: panel!.settings() });
  updateShare();
};
$<HTMLInputElement>('wireframe').onchange = (e) => {
  view.wire = (e.target as HTMLInputElement).checked;
  draw({ type: 'wireframe', on: view.wire });
  updateShare();
};
$<HTMLInputElement>('smooth').onchange = (e) => {
  view.smooth = (e.target as HTMLInputElement).checked;
  draw({ type: 'smooth', on: view.smooth });
  updateShare();
};
$<HTMLInputElement>('show-target').onchange = (e) => draw({ type: 'show-target', on: (e.target as HTMLInputElement).checked });
$<HTMLSelectElement>('field-view').onchange = () => {
  $('field-t-name').textContent = fieldView() === 'iso' ? 'Level' : 'Position';
  sendField();
};
// Slices are cheap (one node plane): follow the slider; isosurfaces run marching cubes: on release.
$<HTMLInputElement>('field-t').oninput = () => {
  if (fieldView() !== 'iso' && fieldView() !== 'off') sendField();
};
$<HTMLInputElement>('field-t').onchange = () => {
  if (fieldView() === 'iso') sendField();
};
$<HTMLSelectElement>('cmap').onchange = (e) => {
  view.cmap = (e.target as HTMLSelectElement).value;
  send({ type: 'colour', map: view.cmap as ColourMap });
  updateShare();
};
for (const b of document.querySelectorAll<HTMLButtonElement>('[data-demo]')) {
  b.onclick = () => {
    const preset = b.dataset.preset ?? (b.dataset.demo === 'mcf' ? panel?.preset : 'full-wrap') ?? 'full-wrap';
    if (panel && preset !== panel.preset) {
      panel.set(preset);
      $<HTMLSelectElement>('preset').value = preset;
      send({ type: 'curves', settings: panel.settings() });
    }
    startDemo(b.dataset.demo!);
  };
}
for (const b of document.querySelectorAll<HTMLButtonElement>('[data-format]')) {
  b.onclick = () => {
    const k = kept ? { positions: kept.positions.slice(), indices: kept.indices.slice() } : undefined;
    send({ type: 'export', format: b.dataset.format!, kept: k });
  };
}
$<HTMLInputElement>('file').onchange = (e) => {
  const f = (e.target as HTMLInputElement).files?.[0];
  if (f) void openFile(f);
  (e.target as HTMLInputElement).value = '';
};
$('url-form').onsubmit = (e) => {
  e.preventDefault();
  openUrl($<HTMLInputElement>('url').value.trim());
};

// Drag and drop anywhere on the page.
let dragDepth = 0;
window.addEventListener('dragenter', (e) => {
  e.preventDefault();
  dragDepth++;
  $('drop').hidden = false;
});
window.addEventListener('dragleave', () => {
  if (--dragDepth <= 0) {
    dragDepth = 0;
    $('drop').hidden = true;
  }
});
window.addEventListener('dragover', (e) => e.preventDefault());
window.addEventListener('drop', (e) => {
  e.preventDefault();
  dragDepth = 0;
  $('drop').hidden = true;
  const f = e.dataTransfer?.files?.[0];
  if (f) void openFile(f);
});

/** Test and automation hooks: read-only views of what is shown. */
function meshPixelFraction(): Promise<number> {
  return new Promise((resolve) => {
    const onProbe = (ev: MessageEvent<FromRender>) => {
      if (ev.data?.type !== 'probe') return;
      renderer.removeEventListener('message', onProbe);
      resolve(ev.data.meshPixelFraction);
    };
    renderer.addEventListener('message', onProbe);
    draw({ type: 'probe' });
  });
}
(window as unknown as { __lsw: object }).__lsw = {
  radiusSeries: () => plot.series(),
  distanceSeries: () => distancePlot.series(),
  controlSeries: () => controlPlot.series(),
  resultHash: () => kept?.hash ?? null,
  dropToDoneMs: () => lastDoneMs,
  wasmMemoryBytes: () => wasmBytes,
  meshPixelFraction,
  fieldShown: () => fieldShown,
};

// Wiring only: UI events → worker messages; worker frames → render worker, plot and status.
// The UI thread neither computes nor draws: the flow runs in one worker, three.js in another.
import type { FromWorker, McfParams, RenderProbe, ToRender, ToWorker, UiError } from './protocol';
import { RadiusPlot } from './plots';

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;
const status = $('status');
const canvas = $<HTMLCanvasElement>('canvas');
const plot = new RadiusPlot($('plot'));
const worker = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
const renderer = new Worker(new URL('./render-worker.ts', import.meta.url), { type: 'module' });
const send = (m: ToWorker) => worker.postMessage(m);
const draw = (m: ToRender, transfer: Transferable[] = []) => renderer.postMessage(m, transfer);

type State = 'idle' | 'loading' | 'running' | 'done' | 'error';
function setState(state: State, text: string): void {
  status.dataset.state = state;
  status.textContent = text;
  $<HTMLButtonElement>('play').disabled = state === 'running';
  $<HTMLButtonElement>('pause').disabled = state !== 'running';
}

function showError(e: UiError | null): void {
  const el = $('error');
  el.hidden = !e;
  el.textContent = e ? `${e.message}${e.hint ? ' — ' + e.hint : ''}` : '';
}

if (!('transferControlToOffscreen' in canvas)) {
  showError({ code: 'unsupported', message: 'This browser cannot draw from a worker (no OffscreenCanvas).', hint: 'Use a current Chrome, Edge, Firefox or Safari (16.4 or newer).' });
  setState('error', 'Unsupported browser');
} else {
  const offscreen = canvas.transferControlToOffscreen();
  draw({ type: 'init', canvas: offscreen, width: canvas.clientWidth, height: canvas.clientHeight, pixelRatio: Math.min(2, devicePixelRatio) }, [offscreen]);
  new ResizeObserver(() => draw({ type: 'resize', width: canvas.clientWidth, height: canvas.clientHeight })).observe(canvas);
}

// Camera: drag to orbit, wheel to zoom. Only deltas cross to the render worker.
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

function params(): McfParams {
  return { level: Number($<HTMLSelectElement>('level').value), radius: 1, tau: Number($<HTMLInputElement>('tau').value) };
}

function reset(): void {
  showError(null);
  plot.clear();
  draw({ type: 'refit' });
  send({ type: 'mcf-init', params: params() });
  setState('idle', 'Ready');
}

worker.onmessage = (ev: MessageEvent<FromWorker>) => {
  const msg = ev.data;
  switch (msg.type) {
    case 'ready':
      reset();
      break;
    case 'frame': {
      const transfer: Transferable[] = [msg.positions.buffer, msg.normals.buffer];
      if (msg.indices) transfer.push(msg.indices.buffer);
      if (msg.colors) transfer.push(msg.colors.buffer);
      draw({ type: 'geometry', positions: msg.positions, normals: msg.normals, indices: msg.indices, colors: msg.colors }, transfer);
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
      $('legend').hidden = !msg.colors;
      $('legend-title').textContent = 'mean curvature H';
      $('legend-min').textContent = msg.range[0].toPrecision(5);
      $('legend-max').textContent = msg.range[1].toPrecision(5);
      if (msg.playing) setState('running', `Running — step ${s.step}`);
      break;
    }
    case 'stopped':
      setState(msg.reason === 'finished' ? 'done' : 'idle', msg.reason === 'finished' ? 'Done — the sphere has shrunk to 15 % of its radius' : 'Paused');
      break;
    case 'error':
      showError(msg.error);
      setState('error', 'Error');
      break;
  }
};
const workerFailed = (what: string) => (e: ErrorEvent) => {
  showError({ code: 'worker', message: `The ${what} failed: ${e.message}`, hint: 'Reload the page.' });
  setState('error', 'Error');
};
worker.onerror = workerFailed('computation worker');
renderer.onerror = workerFailed('render worker');

$('play').onclick = () => {
  showError(null);
  send({ type: 'play' });
  setState('running', 'Running');
};
$('pause').onclick = () => send({ type: 'pause' });
$('step').onclick = () => send({ type: 'step', n: 1 });
$('reset').onclick = reset;
$('level').onchange = reset;
$('tau').onchange = reset;
$<HTMLInputElement>('wireframe').onchange = (e) => draw({ type: 'wireframe', on: (e.target as HTMLInputElement).checked });
$<HTMLInputElement>('colour').onchange = (e) => send({ type: 'colour', on: (e.target as HTMLInputElement).checked });

/** Test and automation hooks: read-only views of what is shown. */
function meshPixelFraction(): Promise<number> {
  return new Promise((resolve) => {
    const onProbe = (ev: MessageEvent<RenderProbe>) => {
      if (ev.data?.type !== 'probe') return;
      renderer.removeEventListener('message', onProbe);
      resolve(ev.data.meshPixelFraction);
    };
    renderer.addEventListener('message', onProbe);
    draw({ type: 'probe' });
  });
}
(window as unknown as { __lsw: object }).__lsw = { radiusSeries: () => plot.series(), meshPixelFraction };

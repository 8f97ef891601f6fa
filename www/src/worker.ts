// The worker owns the wasm module and the step loop; the UI thread never computes.
import init, { McfSession } from '../pkg/lsw.js';
import type { FromWorker, McfStats, ToWorker } from './protocol';
import { toUiError } from './protocol';
import { batchSize } from './schedule';
import { colorize, robustRange } from './colormap';

const ready = init();
let session: McfSession | null = null;
let playing = false;
let msPerStep = 1;
let sentIndices = false;
let colours = true;

function post(msg: FromWorker, transfer: Transferable[] = []): void {
  (self as unknown as Worker).postMessage(msg, transfer);
}

function sendFrame(): void {
  if (!session) return;
  const positions = session.positions();
  const normals = session.normals();
  const scalar = session.meanCurvature();
  const stats = session.stats() as McfStats;
  const range = robustRange(scalar);
  let colors: Float32Array | null = null;
  const transfer: Transferable[] = [positions.buffer, normals.buffer];
  if (colours) {
    colors = new Float32Array(positions.length);
    colorize(scalar, range[0], range[1], colors);
    transfer.push(colors.buffer);
  }
  let indices: Uint32Array | undefined;
  if (!sentIndices) {
    indices = session.indices();
    transfer.push(indices.buffer);
    sentIndices = true;
  }
  post({ type: 'frame', positions, normals, indices, colors, range, stats, playing }, transfer);
}

function fail(e: unknown): void {
  playing = false;
  post({ type: 'error', error: toUiError(e) });
}

/** Runs one batch, posts a frame, and yields to the event loop so "pause" gets through. */
function loop(): void {
  if (!playing || !session) return;
  try {
    const n = batchSize(msPerStep);
    session.step(n);
    const stats = session.stats() as McfStats;
    msPerStep = stats.msPerStep;
    // Stop before the sphere collapses to a point: below 15 % of the start radius the step τ
    // is no longer small against the co-volumes and the linearised flow loses accuracy.
    if (!(stats.exactRadius > 0.15 * currentR0)) {
      playing = false;
      sendFrame();
      post({ type: 'stopped', reason: 'finished' });
      return;
    }
    sendFrame();
    setTimeout(loop, 0);
  } catch (e) {
    fail(e);
  }
}

let currentR0 = 1;

self.onmessage = async (ev: MessageEvent<ToWorker>) => {
  await ready;
  const msg = ev.data;
  try {
    switch (msg.type) {
      case 'mcf-init': {
        playing = false;
        const next = new McfSession(msg.params.level, msg.params.radius, msg.params.tau);
        session?.free();
        session = next;
        currentR0 = msg.params.radius;
        sentIndices = false;
        sendFrame();
        break;
      }
      case 'play':
        if (!playing) {
          playing = true;
          loop();
        }
        break;
      case 'pause':
        playing = false;
        post({ type: 'stopped', reason: 'paused' });
        break;
      case 'colour':
        colours = msg.on;
        if (!playing) sendFrame();
        break;
      case 'step':
        playing = false;
        session?.step(msg.n);
        sendFrame();
        break;
    }
  } catch (e) {
    fail(e);
  }
};

ready.then(() => post({ type: 'ready' }), (e) => fail(e));

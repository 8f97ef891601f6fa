// The render worker: owns the three.js scene on an OffscreenCanvas. Draws at most once per
// animation frame, always the latest geometry. It also records frames for the time scrubber
// (bounded memory, see frames.ts), so the page never holds mesh buffers.
import type { FromRender, ToRender } from './protocol';
import { Viewer } from './viewer';
import { FrameStore } from './frames';

let viewer: Viewer | null = null;
let dirty = false;
let scheduled = false;
let store = new FrameStore(2, 192 * 1024 * 1024);
/** The kept result's frames while a new run records its own: a failed run shows them again. */
let aside: FrameStore | null = null;
/** Index of the recorded frame shown, or -1 for the live one. */
let showing = -1;

const nextFrame: (cb: () => void) => void =
  typeof requestAnimationFrame === 'function' ? (cb) => requestAnimationFrame(cb) : (cb) => setTimeout(cb, 16);
const post = (m: FromRender) => (self as unknown as Worker).postMessage(m);

function requestDraw(): void {
  dirty = true;
  if (scheduled) return;
  scheduled = true;
  nextFrame(() => {
    scheduled = false;
    if (dirty && viewer) {
      dirty = false;
      viewer.render();
    }
  });
}

let lastIndices: Uint32Array | null = null;
let viewTimer: ReturnType<typeof setTimeout> | null = null;
function reportView(): void {
  if (viewTimer) return;
  viewTimer = setTimeout(() => {
    viewTimer = null;
    if (viewer) post({ type: 'view', ...viewer.getView() });
  }, 150);
}
const reportFrames = () => post({ type: 'frames', count: store.frames.length, steps: store.frames.map((f) => f.step), bytes: store.bytes, showing });
/** Reports the recorded frames at most every 250 ms: a report per frame kept the page's slider
 * (and with it the page's painting) so busy that a level-6 lesson answered Pause in 0.8 s, not 0.1 s. */
let framesTimer: ReturnType<typeof setTimeout> | null = null;
function reportFramesSoon(): void {
  if (framesTimer) return;
  framesTimer = setTimeout(() => {
    framesTimer = null;
    reportFrames();
  }, 250);
}

self.onmessage = (ev: MessageEvent<ToRender>) => {
  const m = ev.data;
  if (m.type === 'init') {
    viewer = new Viewer(m.canvas, m.pixelRatio);
    viewer.resize(m.width, m.height);
    return;
  }
  if (!viewer) return;
  switch (m.type) {
    case 'resize':
      viewer.resize(m.width, m.height);
      break;
    case 'geometry': {
      if (m.indices) lastIndices = m.indices;
      if (m.record && lastIndices) {
        // Copies: the viewer may reuse these arrays as GPU staging for later frames.
        const kept = store.offer(
          { step: m.step ?? 0, positions: m.positions.slice(), normals: m.normals.slice(), indices: lastIndices, colors: m.colors ? m.colors.slice() : null },
          !!m.final,
        );
        if (kept && m.final) reportFrames();
        else if (kept) reportFramesSoon();
      }
      if (showing >= 0) return; // scrubbing: keep showing the chosen frame
      viewer.update(m.positions, m.normals, m.indices, m.colors);
      break;
    }
    case 'target':
      viewer.setTarget(m.positions, m.indices);
      break;
    case 'clear-frames':
      if (m.aside === 'set') [aside, store] = [store, new FrameStore(store.every, store.budget)];
      else store.clear();
      if (!m.aside) aside = null;
      showing = -1;
      lastIndices = null;
      reportFrames();
      return;
    case 'restore-frames':
      if (aside) [store, aside] = [aside, null];
      showing = -1;
      lastIndices = store.frames[store.frames.length - 1]?.indices ?? null;
      reportFrames();
      return;
    case 'show-frame': {
      const f = store.frames[m.index];
      if (m.index < 0 || !f) {
        showing = -1;
        const last = store.frames[store.frames.length - 1];
        if (last) viewer.update(last.positions.slice(), last.normals.slice(), last.indices, last.colors ? last.colors.slice() : null);
      } else {
        showing = m.index;
        viewer.update(f.positions.slice(), f.normals.slice(), f.indices, f.colors ? f.colors.slice() : null);
      }
      break;
    }
    case 'refit':
      viewer.refit();
      break;
    case 'fit':
      viewer.fitKeepingAngles();
      reportView();
      break;
    case 'look':
      viewer.setView(m.yaw, m.pitch, 1);
      viewer.fitKeepingAngles();
      reportView();
      break;
    case 'rotate':
      viewer.rotate(m.dx, m.dy);
      reportView();
      break;
    case 'zoom':
      viewer.zoom(m.factor);
      reportView();
      break;
    case 'set-view':
      viewer.pendingView = { yaw: m.yaw, pitch: m.pitch, zoom: m.zoom };
      viewer.setView(m.yaw, m.pitch, m.zoom);
      break;
    case 'wireframe':
      viewer.setWireframe(m.on);
      break;
    case 'smooth':
      viewer.setSmooth(m.on);
      break;
    case 'show-target':
      viewer.showTarget(m.on);
      break;
    case 'field':
      viewer.setField(m.slice, m.iso);
      break;
    case 'probe':
      viewer.render();
      post({ type: 'probe', meshPixelFraction: viewer.meshPixelFraction() });
      return;
  }
  requestDraw();
};

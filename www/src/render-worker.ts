// The render worker: owns the three.js scene on an OffscreenCanvas. Draws at most once per
// animation frame, always the latest geometry.
import type { ToRender } from './protocol';
import { Viewer } from './viewer';

let viewer: Viewer | null = null;
let dirty = false;
let scheduled = false;

const nextFrame: (cb: () => void) => void =
  typeof requestAnimationFrame === 'function' ? (cb) => requestAnimationFrame(cb) : (cb) => setTimeout(cb, 16);

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
    case 'geometry':
      viewer.update(m.positions, m.normals, m.indices, m.colors);
      break;
    case 'refit':
      viewer.refit();
      break;
    case 'rotate':
      viewer.rotate(m.dx, m.dy);
      break;
    case 'zoom':
      viewer.zoom(m.factor);
      break;
    case 'wireframe':
      viewer.setWireframe(m.on);
      break;
    case 'probe':
      viewer.render();
      (self as unknown as Worker).postMessage({ type: 'probe', meshPixelFraction: viewer.meshPixelFraction() });
      return;
  }
  requestDraw();
};

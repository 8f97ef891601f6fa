// The render worker seen from the page: draw messages go out (geometry buffers transferred);
// camera moves, recorded-frame counts and probe answers come back. three.js lives in the worker.
import type { FromRender, ToRender } from './protocol';

export class Renderer {
  private readonly worker = new Worker(new URL('./render-worker.ts', import.meta.url), { type: 'module' });

  /** Posts a message; a bound arrow so that modules can take it as their `Draw`. */
  readonly draw = (m: ToRender, transfer: Transferable[] = []): void => this.worker.postMessage(m, transfer);

  /** Hands the canvas to the worker and keeps its size in step; false where the browser cannot draw from a worker. */
  attach(canvas: HTMLCanvasElement): boolean {
    if (!('transferControlToOffscreen' in canvas)) return false;
    const offscreen = canvas.transferControlToOffscreen();
    this.draw({ type: 'init', canvas: offscreen, width: canvas.clientWidth, height: canvas.clientHeight, pixelRatio: Math.min(2, devicePixelRatio) }, [offscreen]);
    new ResizeObserver(() => this.draw({ type: 'resize', width: canvas.clientWidth, height: canvas.clientHeight })).observe(canvas);
    return true;
  }

  listen(handler: (m: FromRender) => void): void {
    this.worker.addEventListener('message', (ev: MessageEvent<FromRender>) => handler(ev.data));
  }

  onError(handler: (e: ErrorEvent) => void): void {
    this.worker.onerror = handler;
  }

  /** Fraction of canvas pixels that show something other than the background (for tests and automation). */
  meshPixelFraction(): Promise<number> {
    return new Promise((resolve) => {
      const onProbe = (ev: MessageEvent<FromRender>) => {
        if (ev.data?.type !== 'probe') return;
        this.worker.removeEventListener('message', onProbe);
        resolve(ev.data.meshPixelFraction);
      };
      this.worker.addEventListener('message', onProbe);
      this.draw({ type: 'probe' });
    });
  }
}

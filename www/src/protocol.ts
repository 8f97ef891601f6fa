// Messages between the UI thread and the worker: the one source of truth for both sides.
// Meshes travel as flat typed arrays (Transferables), never as JSON.

/** An error as produced by the Rust facade: stable code, message naming the problem, and a hint. */
export interface UiError {
  code: string;
  message: string;
  hint: string;
}

/** Statistics of the MCF demo (mirrors `McfStats` in src/wasm.rs, camelCase via serde). */
export interface McfStats {
  step: number;
  time: number;
  meanRadius: number;
  exactRadius: number;
  covolumeMin: number;
  covolumeMean: number;
  covolumeMax: number;
  solverIterations: number;
  solverResidual: number;
  msPerStep: number;
  vertices: number;
  faces: number;
}

export interface McfParams {
  level: number;
  radius: number;
  tau: number;
}

/** UI → worker. */
export type ToWorker =
  | { type: 'mcf-init'; params: McfParams }
  | { type: 'play' }
  | { type: 'pause' }
  | { type: 'step'; n: number }
  | { type: 'colour'; on: boolean };

/**
 * A frame of the evolving surface, ready to upload: the worker computes normals and colours so
 * the UI thread only copies buffers. `indices` is present when connectivity changed.
 */
export interface Frame {
  type: 'frame';
  positions: Float32Array;
  normals: Float32Array;
  indices?: Uint32Array;
  /** RGB per vertex from the colour map, or null for plain shading. */
  colors: Float32Array | null;
  /** Range of the coloured scalar, for the legend. */
  range: [number, number];
  stats: McfStats;
  playing: boolean;
}

/** Worker → UI. */
export type FromWorker =
  | { type: 'ready' }
  | Frame
  | { type: 'stopped'; reason: 'paused' | 'finished' }
  | { type: 'error'; error: UiError };

/** Turns anything thrown (a facade error object, an Error, a string) into a UiError. */
export function toUiError(e: unknown): UiError {
  if (e && typeof e === 'object' && 'code' in e && 'message' in e) {
    const o = e as { code: unknown; message: unknown; hint?: unknown };
    return { code: String(o.code), message: String(o.message), hint: o.hint ? String(o.hint) : '' };
  }
  if (e instanceof Error) return { code: 'internal', message: e.message, hint: 'Reload the page; if it persists, report a bug.' };
  return { code: 'internal', message: String(e), hint: 'Reload the page; if it persists, report a bug.' };
}

/** UI → render worker. Geometry buffers are transferred, not copied. */
export type ToRender =
  | { type: 'init'; canvas: OffscreenCanvas; width: number; height: number; pixelRatio: number }
  | { type: 'resize'; width: number; height: number }
  | { type: 'geometry'; positions: Float32Array; normals: Float32Array; indices?: Uint32Array; colors: Float32Array | null }
  | { type: 'refit' }
  | { type: 'rotate'; dx: number; dy: number }
  | { type: 'zoom'; factor: number }
  | { type: 'wireframe'; on: boolean }
  | { type: 'probe' };

/** Render worker → UI: the answer to a probe. */
export interface RenderProbe {
  type: 'probe';
  meshPixelFraction: number;
}

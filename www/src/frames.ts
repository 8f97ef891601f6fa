// Recorded frames for the time scrubber, with bounded memory: every k-th frame is kept, and the
// oldest are dropped once the total passes a byte budget. Lives in the render worker.

export interface RecordedFrame {
  step: number;
  positions: Float32Array;
  normals: Float32Array;
  indices: Uint32Array;
  colors: Float32Array | null;
}

/** Bytes held by a frame's arrays. */
export function frameBytes(f: RecordedFrame): number {
  return f.positions.byteLength + f.normals.byteLength + f.indices.byteLength + (f.colors?.byteLength ?? 0);
}

export class FrameStore {
  readonly frames: RecordedFrame[] = [];
  private seen = 0;
  private total = 0;

  /** `every`: keep one frame in `every`; `budget`: bytes kept at most (the newest frame always stays). */
  constructor(readonly every = 2, readonly budget = 192 * 1024 * 1024) {}

  get bytes(): number {
    return this.total;
  }

  clear(): void {
    this.frames.length = 0;
    this.seen = 0;
    this.total = 0;
  }

  /** Offers a frame; `force` keeps it regardless of the stride (e.g. the final frame). Returns whether it was kept. */
  offer(f: RecordedFrame, force = false): boolean {
    const keep = force || this.seen % this.every === 0;
    this.seen++;
    if (!keep) return false;
    const last = this.frames[this.frames.length - 1];
    if (last && last.step === f.step) {
      this.total -= frameBytes(last);
      this.frames.pop();
    }
    this.frames.push(f);
    this.total += frameBytes(f);
    while (this.total > this.budget && this.frames.length > 1) this.total -= frameBytes(this.frames.shift()!);
    return true;
  }
}

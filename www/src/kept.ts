// The last completed wrap, kept in this thread: a cancelled or failed run shows it again, export
// writes it, and #hash / the health badge describe what is on screen.
import { byId } from './dom';
import { showVerdict } from './health';
import type { Certificate, Draw, FromWorker, Verdict } from './protocol';

/** A target as drawn: positions and triangle indices (none for a point cloud). */
export interface TargetMesh {
  positions: Float32Array;
  indices: Uint32Array;
}

export interface Kept {
  positions: Float32Array;
  normals: Float32Array;
  indices: Uint32Array;
  hash: string;
  name: string;
  target: TargetMesh | null;
  /** Certified and not stopped early: only then is it exported under its plain name. */
  valid: boolean;
  /** What is wrong (or right) with it, in one sentence. */
  why: string;
  certificate: Certificate;
  /** The core's verdict on it, shown as it is. */
  verdict: Verdict;
  stopReason: string | null;
}

export class KeptResult {
  private kept: Kept | null = null;
  private readonly hashEl = byId('hash');

  constructor(private readonly draw: Draw, private readonly health: HTMLElement) {}

  get result(): Kept | null {
    return this.kept;
  }

  /** Keeps a completed wrap (with the target it was wrapped around) and shows its certificate and hash. */
  keep(msg: Extract<FromWorker, { type: 'result' }>, target: TargetMesh | null): void {
    const v = msg.verdict;
    this.kept = { positions: msg.positions, normals: msg.normals, indices: msg.indices, hash: msg.hash, name: msg.name, target, valid: v.certified, why: v.explanation, certificate: msg.certificate, verdict: v, stopReason: msg.stopReason };
    showVerdict(this.health, v, msg.certificate);
    this.hashEl.textContent = `result ${msg.hash.slice(0, 12)}`;
    this.hashEl.dataset.hash = msg.hash;
  }

  /** A new run started: #hash names the kept result as the previous one. */
  showPrevious(): void {
    this.hashEl.textContent = this.kept ? `previous result ${this.kept.hash.slice(0, 12)}` : '';
  }

  /** Shows the kept result again (after a cancel or a failed run); copies, as drawing transfers the buffers. */
  restore(): void {
    const k = this.kept;
    if (!k) return;
    this.draw({ type: 'geometry', positions: k.positions.slice(), normals: k.normals.slice(), indices: k.indices.slice(), colors: null });
    if (k.target) this.draw({ type: 'target', positions: k.target.positions.slice(), indices: k.target.indices.slice() });
    this.hashEl.textContent = `result ${k.hash.slice(0, 12)}`;
    this.hashEl.dataset.hash = k.hash;
    // The badge certifies what is on screen: the kept result again.
    showVerdict(this.health, k.verdict, k.certificate);
  }
}

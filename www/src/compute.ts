// The computation worker's lifecycle. One worker owns the wasm module; the page replaces it when
// it may be unusable (a panic, an allocation failure) or when it does not answer a cancel in
// time (one long wasm call, e.g. the distance field, cannot be interrupted from inside).
import { RESTART_CODES, type FromWorker, type ToWorker } from './protocol';

/** How long a cancel may go unanswered before the worker is terminated. */
const CANCEL_MS = 120;

export interface ComputeHooks {
  /** Every message of the current worker except a replacement's 'ready'. */
  message: (m: FromWorker) => void;
  /** The worker threw outside the protocol. */
  failed: (e: ErrorEvent) => void;
  /** A fresh worker was started: re-send what it must know (colour map, field view). */
  restarted: () => void;
  /** A cancel went unanswered and the worker was replaced. */
  unanswered: () => void;
}

export class Compute {
  private worker!: Worker;
  /** A replacement's 'ready' repeats what the page already has: it is dropped. */
  private restarting = false;
  private cancelTimer: ReturnType<typeof setTimeout> | null = null;
  /** Callers of `cancel` waiting for its answer (or the replacement). */
  private waiting: (() => void)[] = [];

  constructor(private readonly hooks: ComputeHooks) {
    this.start();
  }

  /** Posts to the current worker; a bound arrow so that modules can take it as their `Send`. */
  readonly send = (m: ToWorker, transfer: Transferable[] = []): void => this.worker.postMessage(m, transfer);

  private start(): void {
    this.worker = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
    this.worker.onmessage = (ev: MessageEvent<FromWorker>) => this.receive(ev.data);
    this.worker.onerror = this.hooks.failed;
  }

  private receive(msg: FromWorker): void {
    if (msg.type === 'ready' && this.restarting) {
      this.restarting = false;
      return;
    }
    const answered = msg.type === 'stopped' || msg.type === 'error';
    if (answered && this.cancelTimer) {
      clearTimeout(this.cancelTimer);
      this.cancelTimer = null;
    }
    this.hooks.message(msg);
    if (answered) this.release();
    // After a panic or an allocation failure the wasm instance may be unusable: start afresh.
    if (msg.type === 'error' && RESTART_CODES.includes(msg.error.code)) this.restart();
  }

  /** Replaces the worker (what the page keeps, e.g. the kept result, lives on in this thread). */
  restart(): void {
    this.worker.terminate();
    this.restarting = true;
    this.start();
    this.hooks.restarted();
  }

  /**
   * Stops a run: asks the worker, and replaces it if it does not answer in time. Resolves once
   * the worker has answered or been replaced, so that a new job sent then is not lost with it.
   */
  cancel(): Promise<void> {
    const done = new Promise<void>((resolve) => this.waiting.push(resolve));
    this.send({ type: 'cancel' });
    if (!this.cancelTimer) {
      this.cancelTimer = setTimeout(() => {
        this.cancelTimer = null;
        this.restart();
        this.hooks.unanswered();
        this.release();
      }, CANCEL_MS);
    }
    return done;
  }

  private release(): void {
    for (const resolve of this.waiting.splice(0)) resolve();
  }
}

// Elapsed time of a run that counts only while it works: loading and stepping count, pauses do
// not. The worker owns one per wrap and reports it with every frame and the result.

export class Stopwatch {
  private total = 0;
  private since: number | null = null;

  constructor(private readonly now: () => number = () => performance.now()) {}

  /** Starts afresh (running). */
  restart(): void {
    this.total = 0;
    this.since = this.now();
  }

  /** Counts again (after a pause); no-op while running. */
  resume(): void {
    if (this.since === null) this.since = this.now();
  }

  /** Stops counting (a pause, the end); no-op while stopped. */
  pause(): void {
    if (this.since === null) return;
    this.total += this.now() - this.since;
    this.since = null;
  }

  /** Milliseconds counted so far. */
  get ms(): number {
    return this.total + (this.since === null ? 0 : this.now() - this.since);
  }
}

// Elapsed time of a run that counts only while it works: loading and stepping count, pauses do
// not. The worker owns one per wrap and reports it with every frame and the result, split by
// phase (the core's long phases, the steps, the frames, the certificate): where a wrap's time
// went in the browser, which natively the CLI's JSON says.

export class Stopwatch {
  private total = 0;
  private since: number | null = null;
  private current = '';
  /** Milliseconds per phase, in the order the phases first ran. */
  private readonly shares = new Map<string, number>();

  constructor(private readonly now: () => number = () => performance.now()) {}

  /** Starts afresh (running), in phase `phase`. */
  restart(phase = 'other'): void {
    this.total = 0;
    this.shares.clear();
    this.current = phase;
    this.since = this.now();
  }

  /** Counts again (after a pause); no-op while running. */
  resume(): void {
    if (this.since === null) this.since = this.now();
  }

  /** Stops counting (a pause, the end); no-op while stopped. */
  pause(): void {
    if (this.since === null) return;
    this.book();
    this.since = null;
  }

  /** The time from now on counts as `phase` (the time so far stays with the phase before). */
  phase(phase: string): void {
    if (phase === this.current) return;
    if (this.since !== null) {
      this.book();
      this.since = this.now();
    }
    this.current = phase;
  }

  /** The phase the time counts as now. */
  get currentPhase(): string {
    return this.current;
  }

  /** Milliseconds counted so far. */
  get ms(): number {
    return this.total + (this.since === null ? 0 : this.now() - this.since);
  }

  /** Milliseconds per phase so far, in the order the phases first ran; they add up to `ms`. */
  phases(): [string, number][] {
    const out = [...this.shares];
    if (this.since !== null) {
      const open = this.now() - this.since;
      const at = out.findIndex(([p]) => p === this.current);
      if (at >= 0) out[at] = [this.current, out[at][1] + open];
      else out.push([this.current, open]);
    }
    return out;
  }

  private book(): void {
    const dt = this.now() - (this.since ?? this.now());
    this.total += dt;
    this.shares.set(this.current, (this.shares.get(this.current) ?? 0) + dt);
  }
}

/** "steps 1.7 s · final fit 1.3 s · …": the phases that took at least `minShare` of the time,
 * longest first, and the rest as one "rest". */
export function describePhases(phases: [string, number][], minShare = 0.05): string {
  const total = phases.reduce((s, [, ms]) => s + ms, 0);
  if (!(total > 0)) return '';
  const shown = phases.filter(([, ms]) => ms >= minShare * total).sort((a, b) => b[1] - a[1]);
  const rest = total - shown.reduce((s, [, ms]) => s + ms, 0);
  const parts = shown.map(([p, ms]) => `${p} ${(ms / 1000).toFixed(1)} s`);
  if (rest > 0.0005 * total) parts.push(`rest ${(rest / 1000).toFixed(1)} s`);
  return parts.join(' · ');
}

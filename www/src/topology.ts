// The surface's topology over time: genus per step and the surgery events (a handle opened, a neck cut) that
// changed it, as marks on the time scrubber and a line under it. Scrubbing back shows the genus
// of the frame on screen in the health badge; the end of the timeline shows the certificate again.
import { byId } from './dom';
import { showVerdict } from './health';
import type { Certificate, StartedOver, StepReport, SurgeryEvent, Verdict } from './protocol';

/** One line per event, in words; `n` events alike in one step (two handles opened at once) as one. */
function describe(e: SurgeryEvent, n = 1): string {
  const parts = `components ${e.components_before} → ${e.components_after}`;
  const times = n > 1 ? ` (${n}×)` : '';
  switch (e.kind) {
    case 'handle':
      return `step ${e.step} opened ${n > 1 ? `${n} handles` : 'a handle'} (genus ${e.genus_before} → ${e.genus_after})`;
    case 'merge':
      return `step ${e.step} joined two parts (${parts})${times}`;
    case 'pinch':
      return `step ${e.step} cut a neck in empty space (${parts})${times}`;
    case 'drop':
      return `step ${e.step} dropped a part around nothing (${parts})${times}`;
  }
}

/** The events in words, those alike in one step together. */
export function describeAll(events: SurgeryEvent[]): string[] {
  const lines: { first: SurgeryEvent; n: number }[] = [];
  for (const e of events) {
    const last = lines.at(-1);
    if (last && describe(last.first) === describe(e)) last.n++;
    else lines.push({ first: e, n: 1 });
  }
  return lines.map((l) => describe(l.first, l.n));
}

/** The later pass whose result is shown ('second' or 'third'), or null for the first. A later
 * pass runs inside the first pass's last step, so its events reach the UI in that step's report
 * only, and the first pass's earlier events are not the result's. */
export function laterPassShown(s: StartedOver | null): 'second' | 'third' | null {
  if (s?.third?.kept) return 'third';
  return s?.kept ? 'second' : null;
}

/** The surgery line: the result's events in words, and which pass made them when not the first. */
export function surgeryLine(events: SurgeryEvent[], pass: 'second' | 'third' | null): string {
  if (!events.length) return '';
  const which = pass ? ` (in the ${pass} pass, whose result is shown)` : '';
  return `Surgery${which}: ${describeAll(events).join('; ')}`;
}

/** A timeline's contents (see `TopologyTimeline.snapshot`). */
export interface TimelineState {
  genusAt: [number, number][];
  events: SurgeryEvent[];
  lastEvents: SurgeryEvent[];
  pass: 'second' | 'third' | null;
}

export class TopologyTimeline {
  private readonly genusAt = new Map<number, number>();
  private events: SurgeryEvent[] = [];
  /** The events of the latest step report (a later pass's, when one ran). */
  private lastEvents: SurgeryEvent[] = [];
  private pass: 'second' | 'third' | null = null;
  private readonly list = byId('surgery');
  private readonly marks = byId<HTMLDataListElement>('scrub-marks');

  /** A new run: no steps, no events. */
  clear(): void {
    this.genusAt.clear();
    this.events = [];
    this.lastEvents = [];
    this.pass = null;
    this.render();
    this.marks.replaceChildren();
  }

  /** What the timeline holds, to put back with `put` (a failed run shows the kept result's). */
  snapshot(): TimelineState {
    return { genusAt: [...this.genusAt], events: [...this.events], lastEvents: [...this.lastEvents], pass: this.pass };
  }

  put(s: TimelineState): void {
    this.clear();
    for (const [step, g] of s.genusAt) this.genusAt.set(step, g);
    [this.events, this.lastEvents, this.pass] = [[...s.events], [...s.lastEvents], s.pass];
    this.render();
  }

  /** The reports of the steps since the last frame. */
  add(reports: StepReport[]): void {
    for (const r of reports) {
      this.genusAt.set(r.step, r.genus);
      this.events.push(...(r.surgery ?? []));
      this.lastEvents = r.surgery ?? [];
    }
    this.render();
  }

  /** The result arrived: where a later pass is shown, its events replace the first pass's, and
   * the scrubber (the first pass's frames) gets no marks. */
  result(startedOver: StartedOver | null): void {
    this.pass = laterPassShown(startedOver);
    if (!this.pass) return;
    this.events = [...this.lastEvents];
    this.render();
    this.marks.replaceChildren();
  }

  private render(): void {
    this.list.dataset.events = String(this.events.length);
    this.list.textContent = surgeryLine(this.events, this.pass);
  }

  /** Genus of the surface after `step` (the latest step at or before it). */
  genus(step: number): number | undefined {
    for (let s = step; s >= 0; s--) {
      const g = this.genusAt.get(s);
      if (g !== undefined) return g;
    }
    return undefined;
  }

  /** The scrubber's frames (their steps) changed: one tick at the first frame after each event. */
  place(steps: number[]): void {
    if (this.pass) return;
    const ticks = this.events.map((e) => steps.findIndex((s) => s >= e.step)).filter((i) => i >= 0);
    this.marks.replaceChildren(...[...new Set(ticks)].map((i) => Object.assign(document.createElement('option'), { value: String(i) })));
  }

  /** A frame of `step` is on screen (null: the live end): its genus, or the result's verdict. */
  show(health: HTMLElement, step: number | null, result: { verdict: Verdict; certificate: Certificate } | null): void {
    if (step === null) {
      if (result) showVerdict(health, result.verdict, result.certificate);
      return;
    }
    const g = this.genus(step);
    health.dataset.state = 'frame';
    health.dataset.valid = '';
    health.dataset.si = '';
    health.dataset.genus = g === undefined ? '' : String(g);
    health.textContent = `step ${step} · genus ${g ?? '?'} (earlier frame)`;
    health.title = 'An earlier frame, not certified: the certificate is that of the result at the end of the timeline.';
  }
}

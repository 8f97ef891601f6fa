// The time scrubber: the render worker records frames (FrameStore in frames.ts) and reports how
// many it holds; the slider picks one to show, and its end follows the live surface.
import { byId } from './dom';
import type { Draw, FromRender } from './protocol';

/** What the page does when the scrubber moves or its frames change. */
export interface ScrubberHooks {
  /** The frame of solver step `step` is on screen (null: the live end). */
  shown(step: number | null): void;
  /** The recorded frames (their steps) changed. */
  frames(steps: number[]): void;
}

export class Scrubber {
  private readonly slider = byId<HTMLInputElement>('scrub');
  private readonly label = byId('scrub-label');
  /** Solver step of each recorded frame. */
  private steps: number[] = [];

  constructor(draw: Draw, private readonly hooks: ScrubberHooks) {
    this.slider.oninput = () => {
      const i = Number(this.slider.value);
      const end = i >= Number(this.slider.max);
      draw({ type: 'show-frame', index: end ? -1 : i });
      this.label.textContent = `step ${this.steps[i] ?? '–'}`;
      hooks.shown(end ? null : this.steps[i] ?? null);
    };
  }

  /** The render worker's recorded frames changed; a slider at its end stays there. */
  frames(m: Extract<FromRender, { type: 'frames' }>): void {
    const s = this.slider;
    const atEnd = Number(s.value) >= Number(s.max);
    this.steps = m.steps;
    s.max = String(Math.max(0, m.count - 1));
    s.disabled = m.count < 2;
    if (atEnd || m.showing < 0) s.value = s.max;
    this.hooks.frames(m.steps);
    this.label.textContent = m.count ? `step ${this.steps[Number(s.value)] ?? '–'} · ${m.count} frames, ${(m.bytes / 1048576).toFixed(1)} MB` : '';
  }
}

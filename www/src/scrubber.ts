// The time scrubber: the render worker records frames (FrameStore in frames.ts) and reports how
// many it holds; the slider picks one to show, and its end follows the live surface.
import { byId } from './dom';
import type { Draw, FromRender } from './protocol';

export class Scrubber {
  private readonly slider = byId<HTMLInputElement>('scrub');
  private readonly label = byId('scrub-label');
  /** Solver step of each recorded frame. */
  private steps: number[] = [];

  constructor(draw: Draw) {
    this.slider.oninput = () => {
      const i = Number(this.slider.value);
      draw({ type: 'show-frame', index: i >= Number(this.slider.max) ? -1 : i });
      this.label.textContent = `step ${this.steps[i] ?? '–'}`;
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
    this.label.textContent = m.count ? `step ${this.steps[Number(s.value)] ?? '–'} · ${m.count} frames, ${(m.bytes / 1048576).toFixed(1)} MB` : '';
  }
}

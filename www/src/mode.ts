// What the page is showing: the MCF lesson or a wrap. The two differ in their controls, plots and
// which worker messages still count, so several modules read the mode; only this one switches it.
import { byId } from './dom';

export type Mode = 'mcf' | 'wrap';

export class ModeSwitch {
  private mode: Mode = 'mcf';
  /** Runs after every switch (the colour menu follows the mode). */
  onSwitch: (m: Mode) => void = () => {};

  get current(): Mode {
    return this.mode;
  }

  /** Switches and shows the matching controls and plots (the page starts in the lesson's layout). */
  set(m: Mode): void {
    this.mode = m;
    // A lesson's frames carry no certificate: the badge and the hash describe wraps only.
    byId('hash').hidden = m === 'mcf';
    byId('health').hidden = m === 'mcf';
    byId('mcf-box').hidden = m !== 'mcf';
    byId('mcf-plots').hidden = m !== 'mcf';
    byId('wrap-plots').hidden = m !== 'wrap';
    byId('plot-controls').hidden = m !== 'wrap'; // ε(δ), η(δ) steer a wrap, not the lesson
    this.onSwitch(m);
  }
}

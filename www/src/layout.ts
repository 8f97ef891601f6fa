// The page's layout controls: the side panel can be hidden to give the view the whole width
// (the plots and every panel section fold with their own <details> summaries); on a phone, where
// the panel lies below the view, a new input brings the view back on screen.
import { byId } from './dom';

export function bindLayout(): void {
  const toggle = byId('toggle-side');
  toggle.onclick = () => {
    const hidden = document.body.dataset.side !== 'hidden';
    document.body.dataset.side = hidden ? 'hidden' : '';
    toggle.setAttribute('aria-expanded', String(!hidden));
  };
  // A finished wrap's phase times: a line of their own below the header, closed by default.
  const phases = byId('phases-toggle');
  phases.onclick = () => {
    const line = byId('phase-times');
    line.hidden = !line.hidden;
    phases.setAttribute('aria-expanded', String(!line.hidden));
    phases.textContent = line.hidden ? 'phases ▸' : 'phases ▾';
  };
}

/** Scrolls the 3-D view into sight when most of it is off screen or under the sticky header (one
 * column: a demo or file was chosen in the panel below it). */
export function revealView(): void {
  // At the next frame, whose layout it then shares: read now, it forced a layout of the whole
  // page inside the click (50–70 ms of a demo's first click on a 2-core machine).
  requestAnimationFrame(reveal);
}

function reveal(): void {
  const r = byId('stage').getBoundingClientRect();
  // The sticky header covers the top of the window.
  const header = byId('header').offsetHeight;
  const visible = Math.min(r.bottom, window.innerHeight) - Math.max(r.top, header);
  if (visible < r.height / 2) window.scrollTo({ top: window.scrollY + r.top - header, behavior: 'instant' });
}

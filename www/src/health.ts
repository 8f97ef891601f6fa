// The health badge: the core's verdict on the current result at a glance (green only when the
// verdict is valid), with its sentence on what is wrong and what to try. It shows; it decides nothing.
import type { Certificate, Verdict } from './protocol';

/** The badge's state before any result exists or while a run is under way. */
export function showPending(el: HTMLElement, text: string): void {
  el.dataset.valid = '';
  el.dataset.genus = '';
  el.dataset.si = '';
  el.dataset.state = 'pending';
  el.textContent = text;
  el.title = 'The certificate is computed when the wrap ends.';
}

/** Shows a verdict: data-state / data-valid / data-genus / data-si for scripts, words for people. */
export function showVerdict(el: HTMLElement, v: Verdict, c: Certificate): void {
  el.dataset.valid = String(v.certified);
  el.dataset.genus = c.genus === undefined ? '' : String(c.genus);
  el.dataset.si = String(c.self_intersections);
  el.dataset.state = v.state;
  el.textContent = v.badge.join(' · ');
  // The badge may be cut to fit the header: its tooltip repeats it whole.
  el.title = [el.textContent, v.explanation, ...v.warnings, ...v.notes].join('\n');
}

// The health badge: the certificate of the current result at a glance (green only when valid),
// with one line saying what is wrong and what to try. It shows; it computes nothing.
import type { Certificate, StartedOver } from './protocol';

/** The badge's state before any result exists or while a run is under way. */
export function showPending(el: HTMLElement, text: string): void {
  el.dataset.valid = '';
  el.dataset.genus = '';
  el.dataset.si = '';
  el.dataset.state = 'pending';
  el.textContent = text;
  el.title = 'The certificate is computed when the wrap ends.';
}

/** Whether the wrap's genus or component count differs from a closed mesh target's. */
export function topologyDiffers(c: Certificate): boolean {
  return c.target_genus != null && (c.target_genus !== c.genus || c.target_components !== c.components);
}

/** Whether a part of the target lies outside the wrap (more than 0.5 % of its points checked). */
export function partLeftOut(c: Certificate): boolean {
  return c.target_part_outside === true;
}

/** Whether the first pass is shown although a later one left fewer points outside: the later
 * ones ended far off the data, or with fewer handles (see the core's `flow::StartedOver`). */
export function firstKeptOverFewerOutside(s: StartedOver): boolean {
  return !s.kept && !s.third?.kept && s.outside_after < s.outside_before;
}

/** The genus of each later pass that ended as a closed manifold. */
function laterGenera(s: StartedOver): number[] {
  return [s.genus_after, s.third?.genus].filter((g): g is number => typeof g === 'number');
}

/** A length for a sentence: two significant digits. */
function num(x: number | undefined | null): string {
  return x === undefined || x === null ? '?' : x.toPrecision(2);
}

/** One sentence on what is wrong with an invalid result, and what to try (`again`: the second
 * pass the core ran because the first left part of the target outside, if it did). */
export function explain(c: Certificate, stopReason: string | null, again: StartedOver | null = null): string {
  if (stopReason) return `Stopped early (${stopReason}). Try a smaller time step τ.`;
  if (c.valid && topologyDiffers(c)) {
    return `Closed, manifold, no intersecting faces, but the target has genus ${c.target_genus} in ${c.target_components} part(s) and this wrap genus ${c.genus} in ${c.components}. Try the other start surface or a finer grid.`;
  }
  if (c.valid && partLeftOut(c) && again && firstKeptOverFewerOutside(again)) {
    const far = Math.min(again.far_after ?? Infinity, again.third?.far ?? Infinity);
    const later = laterGenera(again);
    const why = later.some((g) => g < (again.genus_before ?? -1))
      ? `closed a hole the first had opened (genus ${again.genus_before}, theirs ${later.join(' and ')})`
      : `ended farther off the data (${num(far)} against ${num(again.far_before)})`;
    return `Closed, manifold, no intersecting faces, but ${c.target_points_outside} of ${c.target_points_checked} target points checked lie outside the wrap, up to ${num(again.miss_before)} out (an open rim's edge or a thin part cut off); ${again.third ? 'the later passes' : 'a second pass'} that kept them ${why}, so the first is shown. Try a finer grid (Detail) or the other start surface.`;
  }
  if (c.valid && partLeftOut(c) && again) {
    return `Closed, manifold, no intersecting faces, but ${c.target_points_outside} of ${c.target_points_checked} target points checked lie outside the wrap, also after a second pass without full-wrap's push (${again.outside_before} → ${again.outside_after}): a thin part or an open rim was cut off. Try a finer grid (Detail) or the other start surface.`;
  }
  if (c.valid && partLeftOut(c)) {
    return `Closed, manifold, no intersecting faces, but ${c.target_points_outside} of ${c.target_points_checked} target points checked lie outside the wrap: a thin part was cut off. Try the other start surface or a finer grid; for an open sheet (a single-layer scan), the obstacle preset.`;
  }
  if (c.valid) return 'Closed, manifold, oriented, no intersecting faces.';
  if (!c.finite) return 'Has non-finite coordinates. Try a smaller time step τ.';
  if (!c.closed) return 'Not closed. Report the share link: this is a bug.';
  if (!c.manifold || !c.oriented) return 'Not manifold or not oriented. Report the share link: this is a bug.';
  return `${c.self_intersections} pairs of faces intersect. Try the other start surface or a finer grid.`;
}

/** Shows a certificate: data-valid / data-genus / data-si for scripts, words for people. */
export function showCertificate(el: HTMLElement, c: Certificate, stopReason: string | null): void {
  const ok = c.valid && !stopReason;
  el.dataset.valid = String(ok);
  el.dataset.genus = c.genus === null ? '' : String(c.genus);
  el.dataset.si = String(c.self_intersections);
  el.dataset.state = ok ? 'valid' : 'invalid';
  el.dataset.topology = topologyDiffers(c) ? 'differs' : '';
  el.dataset.outside = partLeftOut(c) ? String(c.target_points_outside) : '';
  const parts = [
    ok ? '✓ valid' : '✗ not valid',
    c.closed ? 'closed' : 'open',
    c.manifold ? 'manifold' : 'non-manifold',
    c.genus === null ? 'genus ?' : `genus ${c.genus}`,
    `${c.self_intersections} SI`,
  ];
  if (topologyDiffers(c)) parts.push(`⚠ target: genus ${c.target_genus}, ${c.target_components} part(s)`);
  if (partLeftOut(c)) parts.push(`⚠ ${c.target_points_outside} target points outside`);
  if (c.distance_max !== null) parts.push(`max dist ${c.distance_max.toPrecision(3)}`);
  el.textContent = parts.join(' · ');
  el.title = explain(c, stopReason);
}

// Axis tick labels for the plots, apart from uPlot so that they can be tested without a canvas.

/** A tick's label: three significant digits, and powers of ten below 10⁻⁴ and from 10⁵, where a
 * fixed-point number would lose them (uPlot's default reads ticks below 0.001 as "0"). */
export function tickLabel(t: number | null): string {
  // (uPlot asks about ticks it has no value for, e.g. a log axis before its first data.)
  if (t === null || !Number.isFinite(t)) return '';
  const a = Math.abs(t);
  if (t === 0 || (a >= 1e-4 && a < 1e5)) return String(Number(t.toPrecision(3)));
  const e = t.toExponential(1);
  return e.replace('.0e', 'e');
}

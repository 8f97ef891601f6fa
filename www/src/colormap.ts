// Colour maps for per-vertex scalars (display only; values come from the Rust core).

// Turbo colour map (Google), 7 control points, linearly interpolated.
const TURBO: [number, number, number][] = [
  [0.19, 0.07, 0.23], [0.27, 0.53, 0.98], [0.11, 0.9, 0.71], [0.64, 0.99, 0.24],
  [0.98, 0.73, 0.22], [0.89, 0.27, 0.04], [0.48, 0.02, 0.01],
];

/** RGB in [0,1] for t in [0,1] (clamped; NaN maps to grey). */
export function turbo(t: number): [number, number, number] {
  if (Number.isNaN(t)) return [0.5, 0.5, 0.5];
  const x = Math.min(1, Math.max(0, t)) * (TURBO.length - 1);
  const i = Math.min(TURBO.length - 2, Math.floor(x));
  const f = x - i;
  const a = TURBO[i], b = TURBO[i + 1];
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}

/** Robust range: the 2nd and 98th percentiles, widened by ±5 % when they agree to 1e-4 (a uniform
 * field such as the curvature of a sphere: its rounding noise is not coloured as if it meant something). */
export function robustRange(values: ArrayLike<number>): [number, number] {
  const finite = Float64Array.from(values).filter(Number.isFinite).sort();
  if (finite.length === 0) return [0, 1];
  let lo = finite[Math.floor(0.02 * (finite.length - 1))];
  let hi = finite[Math.ceil(0.98 * (finite.length - 1))];
  if (hi - lo <= 1e-4 * Math.max(Math.abs(lo), Math.abs(hi))) {
    const pad = Math.max(1e-6, Math.abs(hi) * 0.05);
    lo -= pad;
    hi += pad;
  }
  return [lo, hi];
}

/** Fills `out` (RGB per vertex) from `values` mapped through [lo, hi]. */
export function colorize(values: ArrayLike<number>, lo: number, hi: number, out: Float32Array): void {
  const span = hi - lo || 1;
  for (let i = 0; i < values.length; i++) {
    const [r, g, b] = turbo((values[i] - lo) / span);
    out[3 * i] = r;
    out[3 * i + 1] = g;
    out[3 * i + 2] = b;
  }
}

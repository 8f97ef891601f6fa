// Colour maps for per-vertex scalars (display only; the values and their range come from the Rust
// core).

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

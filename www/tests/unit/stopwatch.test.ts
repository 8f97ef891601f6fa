import { describe, expect, it } from 'vitest';
import { Stopwatch } from '../../src/stopwatch';

describe('stopwatch', () => {
  it('counts running time only', () => {
    let t = 0;
    const w = new Stopwatch(() => t);
    w.restart();
    t = 100;
    expect(w.ms).toBe(100);
    w.pause();
    t = 5000; // a long pause
    expect(w.ms).toBe(100);
    w.pause();
    w.resume();
    w.resume();
    t = 5050;
    expect(w.ms).toBe(150);
    w.restart();
    expect(w.ms).toBe(0);
  });
});

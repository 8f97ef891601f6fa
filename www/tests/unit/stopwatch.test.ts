import { describe, expect, it } from 'vitest';
import { describePhases, Stopwatch } from '../../src/stopwatch';

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

describe('stopwatch phases', () => {
  it('splits the counted time by phase, pauses excluded, in the order the phases first ran', () => {
    let t = 0;
    const w = new Stopwatch(() => t);
    w.restart('reading');
    t = 10;
    w.phase('distance field');
    t = 50;
    w.phase('steps');
    t = 80;
    w.phase('frames');
    t = 85;
    w.phase('steps');
    t = 100;
    w.pause();
    t = 1000; // paused: counts nowhere
    w.phase('final fit'); // switched while paused: counts from the resume
    w.resume();
    t = 1030;
    expect(w.phases()).toEqual([['reading', 10], ['distance field', 40], ['steps', 45], ['frames', 5], ['final fit', 30]]);
    expect(w.phases().reduce((s, [, ms]) => s + ms, 0)).toBe(w.ms);
    expect(w.currentPhase).toBe('final fit');
    w.restart();
    expect(w.phases()).toEqual([['other', 0]]);
  });

  it('describes the long phases, longest first, and the rest together', () => {
    expect(describePhases([['reading', 10], ['steps', 1700], ['frames', 40], ['final fit', 1300], ['certificate', 400]]))
      .toBe('steps 1.7 s · final fit 1.3 s · certificate 0.4 s · rest 0.1 s');
    expect(describePhases([['steps', 1000]])).toBe('steps 1.0 s');
    expect(describePhases([])).toBe('');
  });
});

import { describe, expect, it } from 'vitest';
import { colorize, turbo } from '../../src/colormap';
import { repairsNote, toUiError } from '../../src/protocol';
import { batchSize, lessonBatch, LESSON_FRAMES } from '../../src/schedule';
import { tickLabel } from '../../src/ticks';

describe('colour map', () => {
  it('maps the ends and clamps outside [0, 1]', () => {
    expect(turbo(0)).toEqual(turbo(-5));
    expect(turbo(1)).toEqual(turbo(7));
    expect(turbo(0)).not.toEqual(turbo(1));
    expect(turbo(NaN)).toEqual([0.5, 0.5, 0.5]);
  });
  it('colorize writes RGB per value', () => {
    const out = new Float32Array(6);
    colorize([0, 1], 0, 1, out);
    expect(Array.from(out.slice(0, 3))).toEqual(turbo(0).map(Math.fround));
    expect(Array.from(out.slice(3))).toEqual(turbo(1).map(Math.fround));
  });
});

describe('worker batch size', () => {
  it('fills the frame budget and stays within bounds', () => {
    expect(batchSize(1, 30)).toBe(30);
    expect(batchSize(100, 30)).toBe(1);
    expect(batchSize(0.01, 30, 50)).toBe(50);
    expect(batchSize(NaN)).toBe(1);
    expect(batchSize(0)).toBe(1);
  });
  it('gives a lesson its frames whatever a step costs', () => {
    for (const ms of [0.001, 0.1, 1, 10]) {
      const batch = lessonBatch(ms, 800);
      expect(Math.ceil(800 / batch)).toBeGreaterThanOrEqual(LESSON_FRAMES);
    }
    expect(lessonBatch(0.001, 10)).toBe(1);
    expect(lessonBatch(100, 800)).toBe(1);
  });
});

describe('error mapping', () => {
  it('keeps facade errors and wraps anything else', () => {
    expect(toUiError({ code: 'bad-parameter', message: 'τ < 0', hint: 'positive' })).toEqual({ code: 'bad-parameter', message: 'τ < 0', hint: 'positive' });
    expect(toUiError(new Error('boom')).code).toBe('internal');
    expect(toUiError('text').message).toBe('text');
  });
});

describe('repairs note', () => {
  it('names only what changed, and nothing for an untouched mesh', () => {
    expect(repairsNote(undefined)).toBe('');
    expect(repairsNote({ merged_vertices: 0, dropped_faces: 0, flipped_faces: 0, split_vertices: 0, filled_holes: 0 })).toBe('');
    expect(repairsNote({ merged_vertices: 12, dropped_faces: 0, flipped_faces: 3, split_vertices: 0, filled_holes: 2 })).toBe(
      ' (mended: 12 coincident vertices merged, 3 faces turned to agree, 2 small holes closed)',
    );
  });
});

describe('axis ticks', () => {
  it('keep three significant digits, in powers of ten below 0.0001', () => {
    expect([0, 0.0005, 0.001, 0.25, 12.5].map(tickLabel)).toEqual(['0', '0.0005', '0.001', '0.25', '12.5']);
    expect([1e-4, 2.5e-5, 3e-7, 2e5].map(tickLabel)).toEqual(['0.0001', '2.5e-5', '3e-7', '2e+5']);
    expect([null, NaN].map(tickLabel)).toEqual(['', '']);
  });
});

import { describe, expect, it } from 'vitest';
import { leftOut, secondPass } from '../../src/wrap-run';

describe('what the wrap left out, in words', () => {
  it('says nothing when nothing was left out', () => {
    expect(leftOut(0, 0)).toBe('');
  });

  it('names stray points and specks, singular and plural', () => {
    expect(leftOut(1, 0)).toBe(' (1 stray point left out)');
    expect(leftOut(42, 0)).toBe(' (42 stray points left out)');
    expect(leftOut(0, 1)).toBe(' (1 small loose part left out)');
    expect(leftOut(3, 282)).toBe(' (3 stray points and 282 small loose parts left out)');
  });
});

describe('a second pass over a cloud left partly outside, in words', () => {
  const pass = { outside_before: 254, outside_after: 0, checked: 9999, iso_level_before: 0.0163, iso_level_after: 0.0244, kept: true };

  it('says nothing when the wrap ran once', () => {
    expect(secondPass(null)).toBe('');
  });

  it('gives both passes\' counts when the second is shown, and says so when it is not', () => {
    expect(secondPass(pass)).toBe('; wrapped twice: the first pass left 254 of 9999 checked points outside (an open rim or gaps in the sampling), the second 0');
    expect(secondPass({ ...pass, outside_after: 300, kept: false })).toBe('; a second pass left more points outside, so the first is shown');
  });
});

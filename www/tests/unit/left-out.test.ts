import { describe, expect, it } from 'vitest';
import { leftOut } from '../../src/wrap-run';

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

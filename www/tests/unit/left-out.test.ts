import { describe, expect, it } from 'vitest';
import { explain } from '../../src/health';
import type { Certificate } from '../../src/protocol';
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

  it('names a third pass when one ran', () => {
    const third = { d2: 0.5, outside: 1, far: 0.03, kept: true };
    expect(secondPass({ ...pass, kept: false, third })).toBe('; wrapped three times: the first pass left 254 of 9999 checked points outside (an open rim or gaps in the sampling), the second 0 but ended far off the data, the third 1');
    expect(secondPass({ ...pass, third: { ...third, kept: false } })).toBe('; wrapped twice: the first pass left 254 of 9999 checked points outside (an open rim or gaps in the sampling), the second 0 (a third pass did no better)');
  });
});

describe('a part left outside, explained', () => {
  const c: Certificate = {
    valid: true, closed: true, manifold: true, oriented: true, finite: true, genus: 0, components: 1, euler_characteristic: 2,
    self_intersections: 0, degenerate_faces: 0, distance_min: 0, distance_max: 0.01, problem: null, target_genus: null, target_components: null,
    target_points_outside: 390, target_points_checked: 20000, target_part_outside: true,
  };

  it('names the obstacle preset when the wrap ran once, and the second pass when there was one', () => {
    expect(explain(c, null)).toContain('for an open sheet (a single-layer scan), the obstacle preset');
    const again = { outside_before: 4379, outside_after: 390, checked: 20000, iso_level_before: 0.0069, iso_level_after: 0.0078, kept: true };
    const text = explain(c, null, again);
    expect(text).toContain('also after a second pass without full-wrap\'s push (4379 → 390)');
    expect(text).not.toContain('obstacle preset');
  });

  it('says why the first pass is shown when the later ones ended far off the data', () => {
    const again = {
      outside_before: 188, outside_after: 7, checked: 16748, iso_level_before: 0.0113, iso_level_after: 0.0169, kept: false,
      far_before: 0.0292, far_after: 0.279, miss_before: 0.0494, miss_after: 0, third: { d2: 0.5, outside: 0, miss: 0, far: 0.113, kept: false },
    };
    expect(explain(c, null, again)).toContain('up to 0.049 out (an open rim\'s edge or a thin part cut off); the later passes that kept them ended farther off the data (0.11 against 0.029), so the first is shown');
    expect(secondPass(again)).toBe('; a second pass left fewer points outside but ended far off the data, so the first is shown (a third pass did no better)');
  });

  it('says so when the later passes closed a hole the first had opened', () => {
    const again = {
      outside_before: 358, outside_after: 4, checked: 16657, iso_level_before: 0.0037, iso_level_after: 0.0051, kept: false,
      far_before: 0.018, far_after: 0.046, miss_before: 0.027, miss_after: 0, genus_before: 3, genus_after: 1,
      third: { d2: 0.5, outside: 2, miss: 0, far: 0.028, genus: 2, kept: false },
    };
    expect(explain(c, null, again)).toContain('the later passes that kept them closed a hole the first had opened (genus 3, theirs 1 and 2), so the first is shown');
  });
});

import { describe, expect, it } from 'vitest';
import type { StartedOver, SurgeryEvent } from '../../src/protocol';
import { describeAll, laterPassShown, surgeryLine } from '../../src/topology';

const event = (step: number, kind: SurgeryEvent['kind'], genus: [number, number], parts: [number, number] = [1, 1]): SurgeryEvent => ({
  step, kind, position: [0, 0, 0], radius: 0.1, genus_before: genus[0], genus_after: genus[1], components_before: parts[0], components_after: parts[1],
});

describe('surgery events in words', () => {
  it('says events alike in one step once, with their number', () => {
    const events = [event(64, 'handle', [0, 2]), event(64, 'handle', [0, 2]), event(84, 'handle', [2, 4]), event(84, 'handle', [2, 4]), event(90, 'merge', [4, 4], [2, 1])];
    expect(describeAll(events)).toEqual([
      'step 64 opened 2 handles (genus 0 → 2)',
      'step 84 opened 2 handles (genus 2 → 4)',
      'step 90 joined two parts (components 2 → 1)',
    ]);
  });

  it('keeps events of different steps or kinds apart', () => {
    const events = [event(10, 'pinch', [0, 0], [1, 2]), event(11, 'pinch', [0, 0], [1, 2]), event(11, 'drop', [0, 0], [2, 1]), event(11, 'drop', [0, 0], [2, 1])];
    expect(describeAll(events)).toEqual([
      'step 10 cut a neck in empty space (components 1 → 2)',
      'step 11 cut a neck in empty space (components 1 → 2)',
      'step 11 dropped a part around nothing (components 2 → 1) (2×)',
    ]);
  });
});

describe('the surgery of the pass whose result is shown', () => {
  const over = (kept: boolean, third: boolean | null): StartedOver => ({
    outside_before: 174, outside_after: 0, checked: 10000, iso_level_before: 0.01, iso_level_after: 0.02, kept,
    far_before: 0.01, far_after: 0.01, miss_before: 0.02, miss_after: 0, genus_before: 0, genus_after: 0,
    third: third === null ? undefined : { d2: 0.5, outside: 0, miss: 0, far: 0.01, genus: 0, kept: third },
  });

  it('is the first pass unless a later one is kept', () => {
    expect(laterPassShown(null)).toBeNull();
    expect(laterPassShown(over(false, null))).toBeNull();
    expect(laterPassShown(over(false, false))).toBeNull();
    expect(laterPassShown(over(true, null))).toBe('second');
    expect(laterPassShown(over(true, false))).toBe('second');
    expect(laterPassShown(over(false, true))).toBe('third');
  });

  it('names the later pass, and says nothing without events', () => {
    const events = [event(40, 'handle', [0, 1])];
    expect(surgeryLine(events, null)).toBe('Surgery: step 40 opened a handle (genus 0 → 1)');
    expect(surgeryLine(events, 'third')).toBe('Surgery (in the third pass, whose result is shown): step 40 opened a handle (genus 0 → 1)');
    expect(surgeryLine([], 'second')).toBe('');
  });
});

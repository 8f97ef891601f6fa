import { describe, expect, it } from 'vitest';
import type { SurgeryEvent } from '../../src/protocol';
import { describeAll } from '../../src/topology';

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

import { describe, expect, it } from 'vitest';
import { decode, DEFAULT_VIEW, encode, type ShareState } from '../../src/share';

const presets = { 'full-wrap': { tau: 0.001 } };

describe('share links carry the volume iso-value', () => {
  it('round-trips iso and leaves it out when absent', () => {
    const state: ShareState = { dataset: 'demo:phantom', preset: 'full-wrap', changed: {}, view: { ...DEFAULT_VIEW }, iso: 127.5 };
    const hash = encode(state);
    expect(hash).toContain('iso=127.5');
    expect(decode(hash, presets).state).toEqual(state);
    const plain: ShareState = { dataset: 'demo:bunny', preset: 'full-wrap', changed: {}, view: { ...DEFAULT_VIEW } };
    expect(encode(plain)).not.toContain('iso');
    expect(decode(encode(plain), presets).state).toEqual(plain);
  });

  it('ignores a malformed iso with a notice', () => {
    for (const bad of ['abc', '', 'Infinity', '1e999']) {
      const { state, notices } = decode(`v=1&d=demo%3Aphantom&p=full-wrap&iso=${encodeURIComponent(bad)}`, presets);
      expect(state.iso).toBeUndefined();
      expect(notices.join(' ')).toMatch(/iso/);
    }
  });
});

import { describe, expect, it } from 'vitest';
import { decode, DEFAULT_VIEW, describeFile, diff, encode, flatten, formatBytes, sameFile, unflatten, type Flat, type ShareState } from '../../src/share';

const base = { tau: 0.07, steps: 146, schedule: [3, 10], start: 'icosphere', remesh: true, field: { cells_per_min_dimension: 40, truncation: null } };
const presets: Record<string, Flat> = { 'full-wrap': flatten(base), obstacle: flatten({ ...base, tau: 0.05 }) };

describe('URL state codec', () => {
  it('round-trips dataset, preset, changed settings and view', () => {
    const state: ShareState = {
      dataset: 'demo:bunny-points',
      preset: 'obstacle',
      changed: { steps: 20, schedule: [1, 2, 3], start: 'isosurface', 'field.cells_per_min_dimension': 64, 'field.truncation': 3.5, remesh: false },
      view: { ...DEFAULT_VIEW, wire: false, cmap: 'kappa', yaw: 1.25 },
    };
    const hash = encode(state);
    expect(hash.startsWith('v=4')).toBe(true);
    const { state: back, notices } = decode('#' + hash, presets, { colourMaps: ['distance', 'kappa', 'none'] });
    expect(notices).toEqual([]);
    expect(back).toEqual(state);
  });

  it('writes every setting, so a link keeps its result when a later version changes a default', () => {
    const settings = { ...presets.obstacle, steps: 20 };
    const state: ShareState = { dataset: 'demo:bunny-points', preset: 'obstacle', changed: { steps: 20 }, settings, view: { ...DEFAULT_VIEW } };
    const hash = encode(state);
    for (const k of Object.keys(settings)) expect(hash).toContain(`s.${k}=`);
    // Read by this version: only the change is a change.
    const back = decode(hash, presets);
    expect(back.notices).toEqual([]);
    expect(back.state.changed).toEqual({ steps: 20 });
    // Read by a version whose obstacle τ default moved to 0.06: the link's 0.05 still applies.
    const later = { ...presets, obstacle: { ...presets.obstacle, tau: 0.06 } };
    expect(decode(hash, later).state.changed).toEqual({ steps: 20, tau: 0.05 });
  });

  it('carries a dropped file as name, size and fingerprint; version 1 links read as before', () => {
    const file = { name: 'scan & co=1.ply', size: 1234567, sha: '3fa2c9e1d07b4a55' };
    const state: ShareState = { dataset: null, preset: 'full-wrap', changed: { steps: 20 }, view: { ...DEFAULT_VIEW }, file };
    const hash = encode(state);
    expect(hash).toContain('f.size=1234567');
    const back = decode(hash, presets);
    expect(back.notices).toEqual([]);
    expect(back.state).toEqual(state);
    expect(describeFile(file)).toBe('scan & co=1.ply (1.2 MB, fingerprint 3fa2c9e1d07b4a55)');
    // A link of version 1 (before files): its settings are read, nothing is missing.
    const v1 = decode('v=1&p=obstacle&s.steps=20&s.start="isosurface"', presets);
    expect(v1.notices).toEqual([]);
    expect(v1.state.changed).toEqual({ steps: 20, start: 'isosurface' });
    expect(v1.state.file).toBeUndefined();
  });

  it('refuses malformed file keys with a notice and compares files by size and fingerprint', () => {
    for (const bad of ['f.name=x.ply&f.size=-1', 'f.name=x.ply&f.size=1.5', 'f.name=&f.size=3', 'f.name=x.ply&f.size=3&f.sha=XYZ', 'f.name=a%00b&f.size=3', 'f.sha=abcdef12']) {
      const { state, notices } = decode(`v=2&${bad}`, presets);
      expect(state.file).toBeUndefined();
      expect(notices.join(' ')).toMatch(/file/);
    }
    const a = { name: 'a.ply', size: 10, sha: 'aaaaaaaa' };
    expect(sameFile(a, { ...a, name: 'renamed.ply' })).toBe(true);
    expect(sameFile(a, { ...a, sha: 'bbbbbbbb' })).toBe(false);
    expect(sameFile(a, { ...a, size: 11 })).toBe(false);
    expect(sameFile({ ...a, sha: '' }, { ...a, sha: 'bbbbbbbb' })).toBe(true);
    expect(sameFile({ ...a, sha: '' }, { ...a, name: 'b.ply' })).toBe(false);
    expect([formatBytes(812), formatBytes(2048), formatBytes(5e9)]).toEqual(['812 B', '2.0 kB', '4.7 GB']);
  });

  it('carries the sphere lesson\'s level and time step; a non-number is refused with a notice', () => {
    const state: ShareState = { dataset: 'demo:mcf', preset: 'full-wrap', changed: {}, view: { ...DEFAULT_VIEW }, lesson: { level: 3, tau: 0.001 } };
    const back = decode(encode(state), presets);
    expect(back.notices).toEqual([]);
    expect(back.state.lesson).toEqual({ level: 3, tau: 0.001 });
    const bad = decode('v=4&d=demo:mcf&mcf.level=3&mcf.tau=fast', presets);
    expect(bad.state.lesson).toEqual({ level: 3, tau: NaN });
    expect(bad.notices.join(' ')).toMatch(/mcf\.tau/);
  });

  it('round-trips source URLs with their own query strings', () => {
    const state: ShareState = { dataset: 'https://example.org/scan.ply?x=1&y=2#frag', preset: 'full-wrap', changed: {}, view: { ...DEFAULT_VIEW } };
    expect(decode(encode(state), presets).state).toEqual(state);
  });

  it('flatten / unflatten / diff are inverse and minimal', () => {
    expect(unflatten(flatten(base))).toEqual(base);
    expect(diff(flatten({ ...base, tau: 0.1 }), flatten(base))).toEqual({ tau: 0.1 });
    expect(unflatten({ '__proto__.x': 1, 'a.b': 2 } as Flat)).toEqual({ a: { b: 2 } });
  });

  it('old versions keep dataset and preset, drop settings, and say so', () => {
    const { state, notices } = decode('v=0&d=demo:teapot&p=obstacle&s.tau=0.5', presets);
    expect(state.dataset).toBe('demo:teapot');
    expect(state.preset).toBe('obstacle');
    expect(state.changed).toEqual({});
    expect(notices.join(' ')).toMatch(/version 0/);
    const legacy = decode('dataset=demo:teapot&preset=obstacle', presets);
    expect(legacy.state.dataset).toBe('demo:teapot');
    expect(legacy.notices.join(' ')).toMatch(/no version/);
  });

  it('links made before the settings were nested decode through the core\'s aliases', () => {
    const nested: Record<string, Flat> = { 'full-wrap': flatten({ start: { surface: 'auto' }, flow: { tau: 0.07 }, stop: { steps: 146 }, remesh: { features: { detector: 'off' } } }) };
    const aliases = { start: 'start.surface', tau: 'flow.tau', steps: 'stop.steps', 'features.detector': 'remesh.features.detector' };
    const { state, notices } = decode('v=1&p=full-wrap&s.tau=0.05&s.start=isosurface&s.steps=20&s.features.detector="both"', nested, { aliases });
    expect(notices).toEqual([]);
    expect(state.changed).toEqual({ 'flow.tau': 0.05, 'start.surface': 'isosurface', 'stop.steps': 20, 'remesh.features.detector': 'both' });
    // The current keys decode as they are.
    expect(decode('v=1&s.flow.tau=0.04', nested, { aliases }).state.changed).toEqual({ 'flow.tau': 0.04 });
  });

  it('a link decodes against the tuning version it was made with', () => {
    const nested: Record<string, Flat> = { 'full-wrap': flatten({ flow: { tau: 0.07 }, tuning: { version: 2, flow: { regrow_depth: 1.5, max_retries: 4 } } }) };
    const tuningRows = { '1': { version: 1, flow: { regrow_depth: 0, max_retries: 4 } }, '2': { version: 2, flow: { regrow_depth: 1.5, max_retries: 4 } } };
    const aliases = { 'flow.regrow_depth': 'tuning.flow.regrow_depth' };
    const opts = { aliases, tuningRows };
    // A version-3 link made before the regrowth lacks the key: the tuning of then (row 1).
    expect(decode('v=3&p=full-wrap&s.flow.tau=0.07', nested, opts).state.changed).toEqual({ 'tuning.version': 1, 'tuning.flow.regrow_depth': 0 });
    // Made after it, the link carries the key under its stage's earlier name: its value counts.
    expect(decode('v=3&p=full-wrap&s.flow.tau=0.07&s.flow.regrow_depth=1.5', nested, opts).state.changed).toEqual({ 'tuning.version': 1 });
    expect(decode('v=3&s.flow.regrow_depth=2', nested, opts).state.changed).toEqual({ 'tuning.version': 1, 'tuning.flow.regrow_depth': 2 });
    // A version-4 link names its tuning version; the current one is no change.
    expect(decode('v=4&s.tuning.version=2&s.flow.tau=0.05', nested, opts).state.changed).toEqual({ 'flow.tau': 0.05 });
    expect(decode('v=4&s.tuning.version=1', nested, opts).state.changed).toEqual({ 'tuning.version': 1, 'tuning.flow.regrow_depth': 0 });
    // An unknown tuning version is said and dropped.
    const future = decode('v=4&s.tuning.version=9', nested, opts);
    expect(future.state.changed).toEqual({});
    expect(future.notices.join(' ')).toMatch(/tuning version 9/);
    // A link without a version uses no settings at all.
    expect(decode('p=full-wrap', nested, opts).state.changed).toEqual({});
  });

  it('unknown keys, wrong types and bad values fall back to defaults with notices', () => {
    const { state, notices } = decode('v=1&p=nope&s.bogus=1&s.tau="fast"&s.steps=1e999&view.cmap=<img>&view.zoom=abc&zzz=1', presets);
    expect(state.preset).toBe('full-wrap');
    expect(state.changed).toEqual({});
    expect(state.view).toEqual(DEFAULT_VIEW);
    const text = notices.join(' ');
    expect(text).toMatch(/Unknown preset/);
    expect(text).toMatch(/s\.bogus/);
    expect(text).toMatch(/tau/);
    expect(text).toMatch(/zzz/);
  });

  it('garbage never throws and never yields a script dataset', () => {
    for (const g of ['%%%', '#&&&=', 'v=1&d=javascript:alert(1)', 'v=1&d=<script>', '\u0000\uffff', 'v=999999999', 'v=1&s.__proto__.x=1', 'd=data:text/html,hi']) {
      const { state } = decode(g, presets);
      expect(state.dataset === null || /^demo:|^https?:/.test(state.dataset)).toBe(true);
      expect(({} as Record<string, unknown>).x).toBeUndefined();
    }
  });
});

import { FrameStore, frameBytes } from '../../src/frames';
describe('frame recorder', () => {
  const frame = (step: number, nv = 100) => ({ step, positions: new Float32Array(3 * nv), normals: new Float32Array(3 * nv), indices: new Uint32Array(6 * nv), colors: null });
  it('keeps every k-th frame and the forced last one', () => {
    const s = new FrameStore(3, 1e9);
    for (let i = 0; i < 10; i++) s.offer(frame(i));
    expect(s.frames.map((f) => f.step)).toEqual([0, 3, 6, 9]);
    s.offer(frame(10), true);
    expect(s.frames.map((f) => f.step)).toEqual([0, 3, 6, 9, 10]);
  });
  it('drops the oldest past the budget', () => {
    const one = frameBytes(frame(0));
    const s = new FrameStore(1, 3.5 * one);
    for (let i = 0; i < 20; i++) s.offer(frame(i));
    expect(s.frames.map((f) => f.step)).toEqual([17, 18, 19]);
    expect(s.bytes).toBeLessThanOrEqual(3.5 * one);
  });
});

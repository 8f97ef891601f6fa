import { describe, expect, it } from 'vitest';
import { failureError, WASM_MEMORY_LIMIT } from '../../src/protocol';

describe('what the worker says when the core fails', () => {
  it('takes a trap with most of the memory in use for a failed allocation', () => {
    const e = failureError(new WebAssembly.RuntimeError('unreachable'), 2.8e9);
    expect(e.code).toBe('out-of-memory');
    expect(e.message).toContain('2.6 GiB in use of at most 4 GiB');
    expect(e.hint).toContain('lsw wrap');
  });

  it('calls a trap with little memory in use an internal error, not a lack of memory', () => {
    const e = failureError(new WebAssembly.RuntimeError('unreachable'), 0.1 * WASM_MEMORY_LIMIT);
    expect(e.code).toBe('internal');
    expect(e.message).toBe('The computation stopped on an internal error (wasm: unreachable).');
    expect(e.hint).toContain('report a bug');
  });

  it('calls a trap while reading a file a damaged file, not a bug', () => {
    const e = failureError(new WebAssembly.RuntimeError('unreachable'), 0.1 * WASM_MEMORY_LIMIT, 'reading');
    expect(e.code).toBe('corrupt-data');
    expect(e.message).toContain('probably corrupt');
    expect(e.hint).toContain('the last result shown is kept');
  });

  it('takes a RangeError for a failed allocation whatever the memory in use', () => {
    expect(failureError(new RangeError('Array buffer allocation failed'), 0).code).toBe('out-of-memory');
  });

  it('passes core errors through as they are', () => {
    const core = { code: 'bad-file', message: 'PLY: truncated', hint: 'Check the file.' };
    expect(failureError(core, 3.9e9)).toEqual(core);
  });
});

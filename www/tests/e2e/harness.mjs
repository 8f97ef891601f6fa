// What both end-to-end suites share: the test list, drop and fixtures, and the loop that serves
// the built app, runs the tests in headless Chromium and prints "N passed, N failed".
import { execFileSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
/** The built app, and where tests write screenshots and files. */
const repoRoot = join(here, '..', '..', '..');
export const dist = join(here, '..', '..', 'dist');
export const out = join(here, '..', '..', 'test-results');

/** A closed octahedron as OBJ text. */
export const octahedron = 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\nf 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n';

/** A test list: `test(name, fn)` adds, `assert(cond, msg)` fails the current test. */
export function suite() {
  const tests = [];
  return {
    tests,
    test: (name, fn) => tests.push({ name, fn }),
    assert: (cond, msg) => {
      if (!cond) throw new Error(msg);
    },
  };
}

/** Drops a file of `bytes` named `name` on the page, as a user's drag and drop does. */
export async function dropFile(page, name, bytes) {
  const dt = await page.evaluateHandle(({ name, b64 }) => {
    const bin = atob(b64);
    const u8 = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) u8[i] = bin.charCodeAt(i);
    const dt = new DataTransfer();
    dt.items.add(new File([u8], name));
    return dt;
  }, { name, b64: Buffer.from(bytes).toString('base64') });
  await page.dispatchEvent('body', 'dragenter', { dataTransfer: dt });
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
}

/** Serves the app (with `fixtures`: URL path → bytes), runs `tests` (those whose name contains
 * the first command-line argument, if any) and exits non-zero when one failed. */
export async function runSuite(tests, fixtures = {}) {
  const server = await serve(dist, fixtures);
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: ['--disable-quic', '--disable-gpu', '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--no-first-run'],
  });
  let passed = 0, failed = 0;
  const only = process.argv[2];
  for (const t of tests) {
    if (only && !t.name.includes(only)) continue;
    const t0 = Date.now();
    try {
      await t.fn(browser, server.url);
      passed++;
      console.log(`ok   ${t.name} (${Date.now() - t0} ms)`);
    } catch (e) {
      failed++;
      console.log(`FAIL ${t.name}: ${e.message}`);
    }
  }
  await browser.close();
  await server.close();
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}

/** Runs the native CLI (the debug build `cargo test` leaves, else `cargo run`); parses its JSON. */
export function lswCli(args) {
  const bin = ['debug', 'release'].map((p) => join(repoRoot, 'target', p, 'lsw')).find((b) => existsSync(b));
  const outText = bin
    ? execFileSync(bin, args, { encoding: 'utf8' })
    : execFileSync('cargo', ['run', '--quiet', '--bin', 'lsw', '--', ...args], { cwd: repoRoot, encoding: 'utf8' });
  return JSON.parse(outText);
}


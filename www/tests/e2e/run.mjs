// End-to-end tests: the built app in headless Debian Chromium, driven by playwright-core.
// Screenshots go to www/test-results/. Prints "N passed, N failed" and exits non-zero on failure.
import { chromium } from 'playwright-core';
import { mkdir } from 'node:fs/promises';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const dist = join(here, '..', '..', 'dist');
const out = join(here, '..', '..', 'test-results');
await mkdir(out, { recursive: true });

const tests = [];
const test = (name, fn) => tests.push({ name, fn });
const assert = (cond, msg) => {
  if (!cond) throw new Error(msg);
};

/** Opens the app in a fresh page, collecting console errors and long main-thread tasks. */
async function openApp(browser, url) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.addInitScript(() => {
    window.__longTasks = [];
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.__longTasks.push(e.duration);
    }).observe({ type: 'longtask', buffered: true });
  });
  await page.goto(url);
  await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 30000 });
  return { page, errors };
}

/** Fraction of canvas pixels that differ from the background colour (read in the render worker). */
const meshPixelFraction = (page) => page.evaluate(() => window.__lsw.meshPixelFraction());

test('app loads without console errors and shows the sphere', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const frac = await meshPixelFraction(page);
  assert(frac > 0.02, `canvas shows almost no mesh pixels (${(100 * frac).toFixed(2)} %)`);
  assert(errors.length === 0, `console errors: ${errors.join(' | ')}`);
  await page.close();
});

test('MCF runs in the worker, follows r(t) = sqrt(r0² − 4t), main thread stays responsive', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  await page.selectOption('#level', '4');
  await page.fill('#tau', '0.0005');
  await page.dispatchEvent('#tau', 'change');
  await page.waitForSelector('[data-testid=status][data-state=idle]');
  await page.evaluate(() => (window.__longTasks.length = 0));
  await page.click('[data-testid=play]');
  await page.waitForSelector('[data-testid=status][data-state=running]', { timeout: 10000 });
  // The worker stops by itself when the sphere has nearly vanished (r < 15 % of r0).
  await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 60000 });
  const series = await page.evaluate(() => window.__lsw.radiusSeries());
  // Compare over t ≤ 0.2 (r ≥ 0.45), where τ = 5e-4 resolves the law; near extinction τ/r² grows.
  const idx = series.t.map((t, i) => (t <= 0.2 ? i : -1)).filter((i) => i >= 0);
  assert(idx.length >= 10, `only ${idx.length} plotted points up to t = 0.2`);
  let worst = 0;
  for (const i of idx) worst = Math.max(worst, Math.abs(series.mesh[i] - series.exact[i]) / series.exact[i]);
  assert(worst < 0.01, `plotted radius deviates from the exact law by ${(100 * worst).toFixed(3)} %`);
  const last = series.mesh[series.mesh.length - 1];
  assert(last < 0.2, `sphere did not shrink to near extinction (mean radius ${last})`);
  const longTasks = await page.evaluate(() => window.__longTasks);
  const maxTask = Math.max(0, ...longTasks);
  assert(maxTask <= 100, `main thread had a ${maxTask.toFixed(0)} ms task during the flow`);
  assert(errors.length === 0, `console errors: ${errors.join(' | ')}`);
  await page.screenshot({ path: join(out, 'mcf.png') });
  console.log(`   ${series.t.length} plotted points, worst radius error (t ≤ 0.2) ${(100 * worst).toFixed(3)} %, longest main-thread task ${maxTask.toFixed(0)} ms`);
  await page.close();
});

test('pause stops the flow within a frame (level 6, 40 962 vertices)', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  await page.selectOption('#level', '6');
  await page.dispatchEvent('#level', 'change');
  await page.waitForFunction(() => (document.querySelector('#stats').textContent || '').includes('40962 vertices'), null, { timeout: 20000 });
  await page.waitForTimeout(500); // let the first upload of the new mesh happen
  await page.evaluate(() => (window.__longTasks.length = 0));
  await page.click('[data-testid=play]');
  await page.waitForFunction(() => Number(document.querySelector('#stats').dataset.step) >= 5, null, { timeout: 30000 });
  const t0 = Date.now();
  await page.click('[data-testid=pause]');
  await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 5000 });
  const pauseMs = Date.now() - t0;
  const step = await page.evaluate(() => Number(document.querySelector('#stats').dataset.step));
  await page.waitForTimeout(500);
  const later = await page.evaluate(() => Number(document.querySelector('#stats').dataset.step));
  assert(later === step, `flow kept running after pause (${step} → ${later})`);
  const ms = await page.evaluate(() => /([0-9.]+) ms\/step/.exec(document.querySelector('#stats').textContent)[1]);
  const maxTask = Math.max(0, ...(await page.evaluate(() => window.__longTasks)));
  assert(maxTask <= 100, `main thread had a ${maxTask.toFixed(0)} ms task at level 6`);
  assert(errors.length === 0, `console errors: ${errors.join(' | ')}`);
  const frac = await meshPixelFraction(page);
  assert(frac > 0.02, `canvas shows almost no mesh pixels (${(100 * frac).toFixed(2)} %)`);
  await page.screenshot({ path: join(out, 'mcf-level6.png') });
  console.log(`   paused in ${pauseMs} ms at step ${step}; ${ms} ms per MCF step at level 6 in the browser; longest main-thread task ${maxTask.toFixed(0)} ms`);
  await page.close();
});

test('bad parameters give a readable error and the page survives', async (browser, url) => {
  const { page } = await openApp(browser, url);
  await page.fill('#tau', '-1');
  await page.dispatchEvent('#tau', 'change');
  await page.waitForSelector('[data-testid=status][data-state=error]', { timeout: 10000 });
  const text = await page.textContent('#error');
  assert(/time step/i.test(text), `error text does not name the problem: "${text}"`);
  await page.fill('#tau', '0.0005');
  await page.dispatchEvent('#tau', 'change');
  await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 10000 });
  await page.close();
});

const server = await serve(dist);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--disable-quic', '--disable-gpu', '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update', '--no-first-run'],
});
let passed = 0, failed = 0;
for (const t of tests) {
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

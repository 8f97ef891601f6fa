// The volume flow in headless Chromium: the procedural head phantom from the gallery is read as a
// NIfTI volume, the panel shows its histogram (Otsu marker) and three slices, the wrap finishes;
// then a drag of the iso marker re-wraps at the new value. Asserts each stage and writes
// screenshots/volume.png and screenshots/volume-iso.png.
// Usage: node tests/e2e/volume-shot.mjs  (after `npm run build`).
import { chromium } from 'playwright-core';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const shots = join(here, '..', '..', 'screenshots');
const server = await serve(join(here, '..', '..', 'dist'));
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true, args: ['--disable-gpu', '--enable-unsafe-swiftshader'] });
try {
  const page = await browser.newPage({ viewport: { width: 1720, height: 980 } });
  await page.addInitScript(() => window.localStorage.setItem('lsw.help.seen', '1')); // no help overlay in the picture
  page.on('pageerror', (e) => console.log('pageerror:', e.message));
  const t0 = Date.now();
  await page.goto(server.url + '#v=1&d=demo%3Aphantom&p=full-wrap&view.yaw=0.6&view.pitch=0.3');
  await page.waitForSelector('[data-testid=volume]:not([hidden])', { timeout: 120000 });
  const label = await page.textContent('.volume-label');
  console.log('volume:', label);
  assert.match(label, /96×96×72 voxels/);
  const iso0 = Number(await page.getAttribute('.volume-hist', 'data-iso'));
  assert.ok(iso0 > 0 && iso0 < 255, `Otsu iso ${iso0}`);
  await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
  console.log(`phantom wrapped at iso ${iso0.toFixed(2)} in ${((Date.now() - t0) / 1000).toFixed(1)} s:`, await page.textContent('[data-testid=status]'));
  // The slices were drawn (non-zero size).
  const sizes = await page.$$eval('.volume-slice canvas', (cs) => cs.map((c) => [c.width, c.height]));
  assert.deepEqual(sizes, [[96, 72], [96, 72], [96, 96]]);
  await page.screenshot({ path: join(shots, 'volume.png') });
  // Drag the marker to 3/4 of the histogram: a new wrap at a higher iso-value.
  const box = await page.locator('.volume-hist').boundingBox();
  await page.mouse.move(box.x + box.width * 0.3, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.75, box.y + box.height / 2, { steps: 5 });
  await page.mouse.up();
  const iso1 = Number(await page.getAttribute('.volume-hist', 'data-iso'));
  assert.ok(iso1 > iso0, `dragged iso ${iso1} > ${iso0}`);
  await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
  console.log(`re-wrapped at iso ${iso1.toFixed(2)}:`, await page.textContent('[data-testid=status]'));
  await page.screenshot({ path: join(shots, 'volume-iso.png') });
  // The share link carries the iso-value, and opening it wraps at that value.
  const hash = await page.evaluate(() => location.hash);
  assert.match(hash, /[#&]iso=18\d/);
  const page2 = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  await page2.goto(server.url + '#v=1&d=demo%3Aphantom&p=full-wrap&iso=150');
  await page2.waitForSelector('[data-testid=volume]:not([hidden])', { timeout: 120000 });
  assert.equal(Number(await page2.getAttribute('.volume-hist', 'data-iso')), 150);
  await page2.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
  console.log('link with iso=150:', await page2.textContent('[data-testid=status]'), await page2.evaluate(() => location.hash));
  await page2.close();
  // With the shared data: the brain files wrapped at iso 128 in the browser (timing, hash).
  const data = process.env.LSW_SHARED_DATA;
  if (!data) console.log('skipped the brain files: LSW_SHARED_DATA unset');
  for (const name of data ? ['gm_half.nrrd', 'mni_icbm152_gm_tal_nlin_sym_09a_converted.nii.gz'] : []) {
    await page.setInputFiles('[data-testid=file]', join(data, name));
    await page.waitForSelector('[data-testid=volume]:not([hidden])', { timeout: 300000 });
    const t1 = Date.now();
    await page.fill('#volume-iso', '128');
    await page.dispatchEvent('#volume-iso', 'change');
    await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 600000 });
    const hash = await page.getAttribute('[data-testid=result-hash]', 'data-hash').catch(() => null);
    const heap = await page.evaluate(() => (performance.memory ? performance.memory.usedJSHeapSize : 0));
    console.log(`${name} at iso 128: ${((Date.now() - t1) / 1000).toFixed(1)} s from the iso change to done; status "${await page.textContent('[data-testid=status]')}"; hash ${hash}; JS heap ${(heap / 1e6).toFixed(0)} MB`);
  }
  // A 4-D file: the panel offers the volume; choosing the second re-reads and re-wraps it.
  if (data) {
    await page.setInputFiles('[data-testid=file]', join(data, 'example4d.nii.gz'));
    await page.waitForSelector('[data-testid=volume]:not([hidden])', { timeout: 300000 });
    assert.match(await page.textContent('.volume-label'), /128×96×24 voxels.*volume 1 of 2/);
    await page.fill('#volume-frame', '2');
    await page.dispatchEvent('#volume-frame', 'change');
    await page.waitForFunction(() => /volume 2 of 2/.test(document.querySelector('.volume-label')?.textContent ?? ''), null, { timeout: 300000 });
    await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
    console.log('example4d.nii.gz, second volume:', await page.textContent('[data-testid=status]'));
  }
} finally {
  await browser.close();
  await server.close();
}

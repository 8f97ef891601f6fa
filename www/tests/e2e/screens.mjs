// Screenshots of the main screens at a phone (400×800) and a desktop (1920×1080) size, for
// looking at the layout by eye. Usage (after `npm run build`):
//   node tests/e2e/screens.mjs screenshots/after
// Writes <dir>/<width>x<height>-<screen>.png: the first visit (help overlay, if the app shows
// one), the MCF lesson before and after a run, a wrap of the bunny demo when done, an error, and
// the advanced settings opened.
import { chromium } from 'playwright-core';
import { mkdir } from 'node:fs/promises';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const dir = resolve(process.argv[2] ?? join(here, '..', '..', 'screenshots', 'after'));
await mkdir(dir, { recursive: true });
const server = await serve(join(here, '..', '..', 'dist'));
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true, args: ['--disable-gpu', '--enable-unsafe-swiftshader'] });

for (const [width, height] of [[400, 800], [1920, 1080]]) {
  const page = await browser.newPage({ viewport: { width, height } });
  const shot = (name) => page.screenshot({ path: join(dir, `${width}x${height}-${name}.png`) });
  await page.goto(server.url);
  await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 30000 });
  await page.waitForTimeout(500);
  const help = page.locator('[data-testid=help]');
  if ((await help.count()) && (await help.isVisible())) {
    await shot('help');
    await page.click('[data-testid=help-close]');
  }
  await shot('start');
  await page.click('[data-testid=play]');
  await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 120000 });
  await page.waitForTimeout(300);
  await shot('mcf-done');
  await page.click('[data-demo=bunny-points]');
  await page.waitForSelector('[data-testid=status][data-state=done], [data-testid=status][data-state=invalid]', { timeout: 300000 });
  await page.waitForTimeout(500);
  await shot('wrap-done');
  await page.setInputFiles('#file', { name: 'three.xyz', mimeType: 'text/plain', buffer: Buffer.from('0 0 0\n1 0 0\n0 1 0\n') });
  await page.waitForSelector('[data-testid=status][data-state=error]', { timeout: 60000 });
  await shot('error');
  const advanced = page.locator('#gui .lil-root > .lil-title');
  await advanced.scrollIntoViewIfNeeded();
  await advanced.click();
  await page.waitForTimeout(200);
  await shot('advanced');
  console.log(`${width}×${height}: screenshots in ${dir}`);
  await page.close();
}
await browser.close();
await server.close();

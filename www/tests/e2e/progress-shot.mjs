// Watches the status line while a dropped file is read and wrapped (not a test): prints each
// distinct status text seen (polled every 50 ms) until done, and saves a screenshot of the
// first one that shows reading progress. Usage: bash .ci/build && node tests/e2e/progress-shot.mjs FILE OUT.png
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import { chromium } from 'playwright-core';
import { dist, dropFile } from './harness.mjs';
import { serve } from './server.mjs';

const [file, shot] = process.argv.slice(2);
const server = await serve(dist, {});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--disable-gpu', '--enable-unsafe-swiftshader', '--no-first-run'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
await page.goto(server.url);
await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 30000 });
await dropFile(page, basename(file), readFileSync(file));
const seen = [];
let shotTaken = false;
const t0 = Date.now();
while (Date.now() - t0 < 300000) {
  const text = await page.textContent('[data-testid=status]');
  const state = await page.getAttribute('[data-testid=status]', 'data-state');
  if (text && seen[seen.length - 1] !== text) {
    seen.push(text);
    console.log(`${Date.now() - t0} ms  ${text.slice(0, 110)}`);
    if (!shotTaken && /reading/i.test(text) && /\d+ ?%/.test(text)) {
      await page.screenshot({ path: shot });
      shotTaken = true;
    }
  }
  if (state === 'done' || state === 'error' || state === 'invalid') break;
  await new Promise((r) => setTimeout(r, 50));
}
await browser.close();
await server.close();

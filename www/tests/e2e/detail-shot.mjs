// Takes issue 15's app screenshots: the sculpted bust and fish demos wrapped to done, coloured
// by each vertex's distance to the target (the default colour map), target hidden, seen from
// below the app's frame (the bust's face, the fish's belly).
// Usage: node tests/e2e/detail-shot.mjs OUT_DIR  (after `npm run build`).
import { chromium } from 'playwright-core';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const out = process.argv[2] ?? join(here, '..', '..', 'screenshots');
const server = await serve(join(here, '..', '..', 'dist'));
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true, args: ['--disable-gpu', '--enable-unsafe-swiftshader'] });
for (const demo of ['bust', 'fish']) {
  const page = await browser.newPage({ viewport: { width: 1500, height: 900 } });
  await page.addInitScript(() => window.localStorage.setItem('lsw.help.seen', '1'));
  await page.goto(`${server.url}#v=1&d=demo%3A${demo}&p=full-wrap&view.wire=false&view.yaw=3.1416&view.pitch=-1.45`);
  await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
  await page.uncheck('#show-target');
  await page.waitForTimeout(800);
  await page.screenshot({ path: join(out, `detail-${demo}.png`) });
  console.log(demo, await page.textContent('[data-testid=status]'));
  await page.close();
}
await browser.close();
await server.close();

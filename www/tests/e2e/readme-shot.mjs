// Takes the README screenshot: the bunny demo (points sampled by the core) wrapped to done, with
// its plots. Usage: node tests/e2e/readme-shot.mjs  (after `npm run build`); writes screenshots/wrap.png.
import { chromium } from 'playwright-core';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from './server.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const server = await serve(join(here, '..', '..', 'dist'));
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true, args: ['--disable-gpu', '--enable-unsafe-swiftshader'] });
const page = await browser.newPage({ viewport: { width: 1720, height: 980 } });
await page.addInitScript(() => window.localStorage.setItem('lsw.help.seen', '1')); // no help overlay in the picture
await page.goto(server.url + '#v=1&d=demo%3Abunny-points&p=full-wrap&view.wire=false&view.yaw=0.2&view.pitch=0.25');
await page.waitForSelector('[data-testid=status][data-state=done]', { timeout: 300000 });
await page.uncheck('#show-target');
await page.waitForTimeout(800);
await page.screenshot({ path: join(here, '..', '..', 'screenshots', 'wrap.png') });
await browser.close();
await server.close();

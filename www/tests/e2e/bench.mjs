// A timed run in headless Chromium (issue 16's browser figures; not a test): drops FILE on the
// built app with the default settings, waits for done, and prints one JSON line with drop → done
// (the app's own clock), the result's hash (to compare with `lsw wrap`'s), the worker's time by
// phase (reading, the core's long phases, steps, frames, certificate), the certificate and the
// peak resident memory of the page's renderer process (the tab: page, computation worker and
// render worker), sampled every 100 ms from /proc.
// Usage: bash .ci/build && node tests/e2e/bench.mjs FILE [RUNS=1]
// BENCH_SHOT=OUT.png also saves a screenshot of the page at done, or where a run ended otherwise
// (the last run's).
import { readFileSync, readdirSync } from 'node:fs';
import { basename } from 'node:path';
import { setInterval, clearInterval } from 'node:timers';
import { chromium } from 'playwright-core';
import { dist, dropFile } from './harness.mjs';
import { serve } from './server.mjs';

const file = process.argv[2];
const runs = Number(process.argv[3] ?? 1);
if (!file) {
  console.error('usage: node tests/e2e/bench.mjs FILE [RUNS]');
  process.exit(2);
}

/** Resident memory (bytes) of every Chromium renderer process, by pid. */
function rendererRss() {
  const out = new Map();
  for (const pid of readdirSync('/proc').filter((d) => /^\d+$/.test(d))) {
    try {
      const cmd = readFileSync(`/proc/${pid}/cmdline`, 'utf8');
      if (!cmd.includes('chromium') || !cmd.includes('--type=renderer')) continue;
      const rss = /VmRSS:\s+(\d+) kB/.exec(readFileSync(`/proc/${pid}/status`, 'utf8'));
      if (rss) out.set(pid, Number(rss[1]) * 1024);
    } catch {
      // The process ended between the listing and the read.
    }
  }
  return out;
}

// BENCH_V8_PROF=DIR: V8's sampling profiler, one log per isolate (the computation worker's is
// the largest); read one with `node --prof-process DIR/isolate-…-v8.log`.
const v8Prof = process.env.BENCH_V8_PROF
  ? [`--js-flags=--prof --logfile=${process.env.BENCH_V8_PROF}/v8.log`, '--no-sandbox']
  : [];
const bytes = readFileSync(file);
const server = await serve(dist, {});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--disable-gpu', '--enable-unsafe-swiftshader', '--no-first-run', ...v8Prof],
});
for (let run = 1; run <= runs; run++) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  // A broken build (e.g. a post-processed module that fails in the worker) ends the run at once
  // instead of waiting ten minutes for a done that never comes.
  const broken = (what) => {
    console.error(`bench: ${what}`);
    process.exit(1);
  };
  page.on('pageerror', (e) => broken(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 30000 });
  let peak = 0;
  const sampler = setInterval(() => {
    for (const rss of rendererRss().values()) peak = Math.max(peak, rss);
  }, 100);
  await dropFile(page, basename(file), bytes);
  const end = await page.waitForSelector('[data-testid=status]:is([data-state=done], [data-state=invalid], [data-state=error])', { timeout: 600000 });
  if ((await end.getAttribute('data-state')) !== 'done') {
    if (process.env.BENCH_SHOT) await page.screenshot({ path: process.env.BENCH_SHOT });
    broken(`the run ended as: ${(await end.textContent()).trim()}`);
  }
  clearInterval(sampler);
  const ms = await page.evaluate(() => window.__lsw.dropToDoneMs());
  const phases = await page.evaluate(() => window.__lsw.phaseTimes());
  const status = await page.textContent('[data-testid=status]');
  const hash = await page.evaluate(() => window.__lsw.resultHash());
  console.log(JSON.stringify({
    file: basename(file), run, dropToDoneMs: Math.round(ms), peakRendererMB: Math.round(peak / 2 ** 20), resultHash: hash,
    status: status.trim().slice(0, 400), date: new Date().toISOString(),
    phasesMs: Object.fromEntries(phases.map(([p, t]) => [p, Math.round(t)])),
  }));
  if (process.env.BENCH_SHOT) await page.screenshot({ path: process.env.BENCH_SHOT });
  await page.close();
}
await browser.close();
await server.close();

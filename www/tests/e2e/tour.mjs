// A newcomer's tour of the built app in headless Chromium (playwright-core), issue 18: the
// layout on a phone and a desktop, no dead ends (cancel in every phase, a new drop during a run,
// Reset, readouts cleared at once, pauses not counted), the MCF lesson, readable plots and
// legends, the help overlay, links for dropped files and the simple controls.
// Usage (after `npm run build`): node tests/e2e/tour.mjs [name filter]. Screenshots go to
// www/test-results/tour-*.png. Prints "N passed, N failed" and exits non-zero on failure.
import { mkdir, readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { dropFile, lswCli, octahedron, out, runSuite, suite } from './harness.mjs';
const shared = process.env.LSW_SHARED_DATA;
await mkdir(out, { recursive: true });

const { tests, test, assert } = suite();

/** Opens the app (help overlay already seen unless `firstVisit`), collecting page errors. */
async function openApp(browser, url, { width = 1280, height = 800, firstVisit = false, hash = '' } = {}) {
  const page = await browser.newPage({ viewport: { width, height } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  if (!firstVisit) await page.addInitScript(() => window.localStorage.setItem('lsw.help.seen', '1'));
  await page.goto(url + hash);
  if (!hash) await page.waitForSelector('[data-testid=status][data-state=idle]', { timeout: 30000 });
  return { page, errors };
}

const state = (page) => page.getAttribute('[data-testid=status]', 'data-state');
const statusText = (page) => page.textContent('[data-testid=status]');
const waitState = (page, states, timeout = 120000) =>
  page.waitForSelector(states.map((s) => `[data-testid=status][data-state=${s}]`).join(', '), { timeout });
const noErrors = (errors) => assert(errors.length === 0, `page errors: ${errors.join(' | ')}`);

/** Clicks Cancel; resolves with the milliseconds until the status leaves loading / running. */
const cancelLatency = (page) =>
  page.evaluate(
    () =>
      new Promise((resolve) => {
        const el = document.querySelector('[data-testid=status]');
        const t0 = performance.now();
        const obs = new MutationObserver(() => {
          if (el.dataset.state !== 'running' && el.dataset.state !== 'loading') {
            obs.disconnect();
            resolve(performance.now() - t0);
          }
        });
        obs.observe(el, { attributes: true });
        document.querySelector('[data-testid=cancel]').click();
      }),
  );

/** A binary little-endian PLY of `n` points scattered on a unit sphere with 1 % noise. */
function cloudPly(n) {
  const header = Buffer.from(`ply\nformat binary_little_endian 1.0\nelement vertex ${n}\nproperty float x\nproperty float y\nproperty float z\nend_header\n`);
  const body = Buffer.alloc(12 * n);
  let seed = 12345;
  const rand = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  for (let i = 0; i < n; i++) {
    const z = 2 * rand() - 1, a = 2 * Math.PI * rand(), r = 1 + 0.01 * (rand() - 0.5), s = Math.sqrt(1 - z * z);
    body.writeFloatLE(r * s * Math.cos(a), 12 * i);
    body.writeFloatLE(r * s * Math.sin(a), 12 * i + 4);
    body.writeFloatLE(r * z, 12 * i + 8);
  }
  return Buffer.concat([header, body]);
}

test('no dead ends: a 1 M-point cloud cancelled after 2.5 s, then the bunny dropped ends done and valid; three coplanar points end in error', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  await dropFile(page, 'three.xyz', Buffer.from('0 0 0\n1 0 0\n0 1 0\n'));
  await waitState(page, ['error'], 60000);
  assert(/distinct point/.test(await page.textContent('[data-testid=error]')), 'three points: no named error');
  await dropFile(page, 'million.ply', cloudPly(1_000_000));
  await waitState(page, ['loading', 'running'], 20000);
  await page.waitForTimeout(2500);
  const phase = await statusText(page);
  const ms = await cancelLatency(page);
  const after = { state: await state(page), text: await statusText(page) };
  assert(ms <= 300, `cancel (${phase}) took ${ms.toFixed(0)} ms`);
  assert(after.state === 'idle' && /Cancelled/.test(after.text), `after cancel: ${JSON.stringify(after)}`);
  assert(!(await page.isDisabled('[data-testid=play]')), 'Play is disabled after the cancel');
  await page.waitForTimeout(500);
  assert((await state(page)) === 'idle', `the status left idle after the cancel: ${await statusText(page)}`);
  if (!shared) console.log('   SKIPPED the bunny: LSW_SHARED_DATA is not set (the scan lives in ../shared/data)');
  else {
    await dropFile(page, 'bunnyPts_3.ply', await readFile(join(shared, 'bunnyPts_3.ply')));
    await waitState(page, ['done', 'invalid', 'error'], 180000);
    const h = await page.evaluate(() => ({ ...document.querySelector('[data-testid=health]').dataset }));
    assert((await state(page)) === 'done' && h.valid === 'true', `bunny after the cancel: ${await statusText(page)} ${JSON.stringify(h)}`);
  }
  noErrors(errors);
  console.log(`   cancel during "${phase.slice(0, 60)}": ${ms.toFixed(0)} ms → "${after.text}"`);
  await page.close();
});

test('a genus-4 point cloud ends done with the badge valid, genus 4, 0 SI (surgery opened four handles)', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const file = join(out, 'torus-g4-cloud.ply');
  lswCli(['demo', 'torus-g4-cloud', '-o', file]);
  await dropFile(page, 'torus-g4-cloud.ply', await readFile(file));
  await waitState(page, ['done', 'invalid', 'error'], 300000);
  const h = await page.evaluate(() => ({ ...document.querySelector('[data-testid=health]').dataset }));
  const events = await page.getAttribute('[data-testid=surgery]', 'data-events');
  assert((await state(page)) === 'done' && h.valid === 'true' && h.genus === '4' && h.si === '0', `genus-4 cloud: ${await statusText(page)} ${JSON.stringify(h)}`);
  assert(events === '4', `surgery events: ${events}`);
  await page.screenshot({ path: join(out, 'tour-genus4-cloud.png') });
  noErrors(errors);
  console.log(`   ${await statusText(page)} · ${await page.textContent('[data-testid=surgery]')}`);
  await page.close();
});

test('Close gaps up to: "all" keeps the torus handle closed (genus 0, no surgery) and the link carries it; "auto" opens it again', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const choices = await page.evaluate(() => [...document.querySelector('[data-testid=close-gaps]').options].filter((o) => !o.disabled).map((o) => o.textContent));
  assert(choices[0] === 'auto' && choices.at(-1) === 'all', `choices: ${choices}`);
  assert((await page.inputValue('[data-testid=close-gaps]')) === '0', 'the default is not auto');
  const badge = () => page.evaluate(() => ({ ...document.querySelector('[data-testid=health]').dataset }));
  await page.selectOption('[data-testid=close-gaps]', { label: 'all' });
  // The link follows within the task after the change (updates are coalesced).
  await page.waitForFunction(() => /s\.surgery\.close_gaps=1/.test(document.querySelector('[data-testid=share-url]').value), null, { timeout: 5000 }).catch(() => {});
  const link = await page.inputValue('[data-testid=share-url]');
  assert(/s\.surgery\.close_gaps=1/.test(link), `link: ${link}`);
  await page.click('[data-testid=demo-sphere-torus]');
  await waitState(page, ['done', 'invalid', 'error'], 300000);
  const closed = await badge();
  const events = await page.getAttribute('[data-testid=surgery]', 'data-events');
  assert(closed.valid === 'true' && closed.genus === '0' && events === '0', `all: ${JSON.stringify(closed)}, ${events} events`);
  // Kept closed, the hole is spanned by a membrane far from the data: valid, not faithful (amber).
  assert(closed.state === 'unfaithful', `all: badge state ${closed.state}`);
  // The view shows where: the core's verdict points at the flagged map, and the page switches to it.
  const cmapClosed = await page.inputValue('#cmap');
  assert(cmapClosed === 'flagged', `all: colour map ${cmapClosed}`);
  await page.screenshot({ path: join(out, 'tour-unfaithful.png') });
  await page.selectOption('[data-testid=close-gaps]', { label: 'auto' });
  await page.click('[data-testid=reset]');
  await waitState(page, ['idle'], 60000);
  await page.click('[data-testid=play]');
  await waitState(page, ['done', 'invalid', 'error'], 300000);
  const open = await badge();
  assert(open.valid === 'true' && open.genus === '1' && open.state === 'valid', `auto: ${JSON.stringify(open)}`);
  const cmapOpen = await page.inputValue('#cmap');
  assert(cmapOpen === 'distance', `auto: the colour map chosen before comes back, not ${cmapOpen}`);
  await page.screenshot({ path: join(out, 'tour-close-gaps.png') });
  noErrors(errors);
  console.log(`   close gaps "all": genus ${closed.genus}; "auto": genus ${open.genus}`);
  await page.close();
});

test('a new drop during a run replaces it; Reset returns to the loaded state and starts nothing; readouts clear at once', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  await page.click('[data-demo=bunny-points]');
  await page.waitForFunction(() => Number(document.querySelector('#stats').dataset.step) >= 3, null, { timeout: 60000 });
  await dropFile(page, 'octahedron.obj', Buffer.from(octahedron));
  // The moment new data arrives: no step statistics, no progress of the old run.
  const cleared = await page.evaluate(() => ({ stats: document.querySelector('#stats').textContent, step: document.querySelector('#stats').dataset.step ?? null, progress: document.querySelector('#progress-text').textContent }));
  assert(cleared.stats === '' && cleared.step === null && cleared.progress === '', `readouts not cleared: ${JSON.stringify(cleared)}`);
  await waitState(page, ['done'], 60000);
  const text = await statusText(page);
  assert(/octahedron/.test(text), `status after the replacing drop: ${text}`);
  await page.click('[data-testid=reset]');
  await waitState(page, ['idle'], 30000);
  await page.waitForFunction(() => /Ready/.test(document.querySelector('[data-testid=status]').textContent), null, { timeout: 30000 });
  const step0 = await page.evaluate(() => document.querySelector('#stats').dataset.step);
  await page.waitForTimeout(700);
  const step1 = await page.evaluate(() => document.querySelector('#stats').dataset.step);
  assert(step0 === '0' && step1 === '0' && (await state(page)) === 'idle', `Reset ran steps (${step0} → ${step1}, ${await statusText(page)})`);
  await page.click('[data-testid=play]');
  await waitState(page, ['done'], 60000);
  noErrors(errors);
  await page.close();
});

test('pauses do not count in the elapsed time; cancel in the MCF lesson returns to Ready', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const t0 = Date.now();
  await page.click('[data-demo=noisy-sphere]');
  await page.waitForFunction(() => Number(document.querySelector('#stats').dataset.step) >= 2, null, { timeout: 60000 });
  await page.click('[data-testid=pause]');
  await waitState(page, ['paused'], 10000);
  assert(!(await page.isDisabled('[data-testid=cancel]')), 'Cancel is disabled while the wrap is paused');
  await page.waitForTimeout(2500);
  await page.click('[data-testid=play]');
  await waitState(page, ['done'], 120000);
  const text = await statusText(page);
  const secs = Number(/in ([0-9.]+) s/.exec(text)?.[1]);
  const wall = (Date.now() - t0) / 1000;
  assert(secs <= wall - 2, `elapsed ${secs} s counts the 2.5 s pause (${wall.toFixed(1)} s from the click to done): "${text}"`);
  // The lesson: run, cancel → back to the start, ready.
  await page.click('[data-demo=mcf]');
  await page.click('[data-testid=play]');
  await page.waitForFunction(() => Number(document.querySelector('#stats').dataset.step) >= 5, null, { timeout: 30000 });
  const ms = await cancelLatency(page);
  await page.waitForFunction(() => document.querySelector('#stats').dataset.step === '0', null, { timeout: 10000 });
  assert((await state(page)) === 'idle' && /Ready/.test(await statusText(page)), `lesson after cancel: ${await statusText(page)}`);
  noErrors(errors);
  console.log(`   wrap "${text}" with a 2.5 s pause; lesson cancelled in ${ms.toFixed(0)} ms`);
  await page.close();
});

/** The colour legend as shown: hidden, or its title and range. */
const legend = (page) =>
  page.evaluate(() => {
    const el = document.querySelector('#legend');
    const text = (id) => document.querySelector(id).textContent;
    return el.hidden ? null : { title: text('#legend-title'), min: text('#legend-min'), max: text('#legend-max') };
  });

test('MCF lesson: its own colour maps with matching legends; τ judged before running; the scrubber after a run', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const options = await page.evaluate(() => [...document.querySelector('[data-testid=cmap]').options].map((o) => o.value));
  assert(options.join() === 'curvature,kappa,none', `lesson colour menu: ${options}`);
  await page.waitForFunction(() => !document.querySelector('#legend').hidden, null, { timeout: 10000 });
  const first = await legend(page);
  assert(/curvature/.test(first.title) && first.min !== first.max, `legend on first load: ${JSON.stringify(first)}`);
  await page.selectOption('[data-testid=cmap]', 'kappa');
  await page.waitForFunction(() => /κ/.test(document.querySelector('#legend-title').textContent), null, { timeout: 10000 });
  await page.selectOption('[data-testid=cmap]', 'none');
  await page.waitForFunction(() => document.querySelector('#legend').hidden, null, { timeout: 10000 });
  await page.selectOption('[data-testid=cmap]', 'curvature');
  // τ = 0.01: the sphere vanishes at t = 0.25, after 25 steps: a warning before running, and a
  // run that ends before the collapse, saying where, not "shrunk to 15 %" past a NaN.
  await page.fill('#tau', '0.01');
  await page.dispatchEvent('#tau', 'change');
  await page.waitForSelector('[data-testid=tau-warning]:not([hidden])', { timeout: 10000 });
  const warning = await page.textContent('[data-testid=tau-warning]');
  assert(/r0²\/4 = 0\.25/.test(warning) && /24 steps/.test(warning), `τ warning: ${warning}`);
  await page.click('[data-testid=play]');
  await waitState(page, ['done', 'error'], 30000);
  const end = await statusText(page);
  assert((await state(page)) === 'done' && /t = 0\.240/.test(end) && !/NaN|15 %/.test(end), `τ = 0.01 ends: ${end}`);
  await page.fill('#tau', '0.0005');
  await page.selectOption('#level', '3');
  await page.dispatchEvent('#tau', 'change');
  await page.waitForSelector('[data-testid=tau-warning][hidden]', { state: 'attached', timeout: 10000 });
  await page.click('[data-testid=play]');
  await waitState(page, ['done'], 60000);
  const scrub = await page.evaluate(() => ({ disabled: document.querySelector('[data-testid=scrubber]').disabled, max: Number(document.querySelector('[data-testid=scrubber]').max) }));
  assert(!scrub.disabled && scrub.max >= 2, `scrubber after the lesson: ${JSON.stringify(scrub)}`);
  await page.fill('[data-testid=scrubber]', '0');
  await page.waitForFunction(() => /step 0/.test(document.querySelector('#scrub-label').textContent), null, { timeout: 5000 });
  noErrors(errors);
  console.log(`   legend on load ${first.title} ${first.min}–${first.max}; τ = 0.01: "${end}"; ${scrub.max + 1} recorded lesson frames`);
  await page.close();
});

/** Plot titles, legends and axes that overflow their plot (or the page), by plot id. */
const clippedPlotText = (page) =>
  page.evaluate(() =>
    [...document.querySelectorAll('#plots .u-title, #plots .u-legend, #plots .u-axis')]
      .filter((e) => e.offsetParent)
      .map((e) => {
        const host = e.closest('.plot').getBoundingClientRect();
        const r = e.getBoundingClientRect();
        const over = Math.max(r.right - host.right, host.left - r.left, r.bottom - host.bottom, e.scrollWidth - e.clientWidth, r.right - window.innerWidth);
        return `${e.closest('.plot').id} ${e.className.split(' ')[0]} "${e.textContent.slice(0, 24)}" by ${Math.round(over)} px`;
      })
      .filter((s) => !/by (0|-\d+) px$/.test(s)),
  );

test('readable at 400×800, 1280×800 and 1920×1080: canvas ≥ 350×300, no sideways scroll, no clipped plot text; help on the first visit only, never in the way', async (browser, url) => {
  const { page, errors } = await openApp(browser, url, { firstVisit: true, hash: '#v=2&d=demo%3Anoisy-sphere&p=full-wrap' });
  await waitState(page, ['done'], 60000);
  // The help shows on a first visit; the wrap ran while it was open.
  assert(await page.isVisible('[data-testid=help]'), 'no help on the first visit');
  const sizes = [];
  for (const [width, height] of [[400, 800], [1280, 800], [1920, 1080]]) {
    await page.setViewportSize({ width, height });
    await page.waitForTimeout(400); // the plots follow their hosts' new widths
    const m = await page.evaluate(() => {
      const r = document.querySelector('#canvas').getBoundingClientRect();
      return { w: r.width, h: r.height, scroll: document.documentElement.scrollWidth, inner: window.innerWidth };
    });
    assert(m.w >= 350 && m.h >= 300, `${width}×${height}: canvas ${m.w}×${m.h}`);
    assert(m.scroll <= m.inner, `${width}×${height}: the page scrolls sideways (${m.scroll} > ${m.inner})`);
    // On a loaded machine the plots can take longer than the wait above to follow: poll (up to
    // 3 s more) rather than judge a layout still in motion; text that stays clipped still fails.
    let clipped = await clippedPlotText(page);
    for (let i = 0; clipped.length > 0 && i < 10; i++) {
      await page.waitForTimeout(300);
      clipped = await clippedPlotText(page);
    }
    assert(clipped.length === 0, `${width}×${height}: clipped plot text: ${clipped.join('; ')}`);
    await page.screenshot({ path: join(out, `tour-${width}x${height}.png`), fullPage: width < 800 });
    sizes.push(`${width}×${height}: canvas ${Math.round(m.w)}×${Math.round(m.h)}`);
  }
  // View buttons (usable with the help open): the camera turns, the link follows.
  await page.click('[data-view=top]');
  await page.waitForFunction(() => /view\.pitch=1\.5/.test(document.querySelector('[data-testid=share-url]').value), null, { timeout: 5000 });
  await page.click('[data-view=front]');
  await page.waitForFunction(() => /view\.pitch=0(&|$)/.test(document.querySelector('[data-testid=share-url]').value), null, { timeout: 5000 });
  // Panels fold; ☰ gives the view the whole width.
  await page.click('#run-box > summary');
  assert(await page.isHidden('[data-testid=play]'), 'the Run panel does not fold');
  await page.click('#run-box > summary');
  const narrow = (await page.locator('#canvas').boundingBox()).width;
  await page.click('[data-testid=toggle-side]');
  await page.waitForFunction((w) => document.querySelector('#canvas').getBoundingClientRect().width > w + 200, narrow, { timeout: 5000 });
  await page.click('[data-testid=toggle-side]');
  await page.click('[data-testid=help-close]');
  assert(await page.isHidden('[data-testid=help]'), 'the help does not close');
  await page.reload();
  await page.waitForSelector('[data-testid=status][data-state=running], [data-testid=status][data-state=done]', { timeout: 60000 });
  assert(await page.isHidden('[data-testid=help]'), 'the help shows again after it was dismissed');
  await page.click('[data-testid=help-open]');
  assert(await page.isVisible('[data-testid=help]'), '"?" does not show the help');
  noErrors(errors);
  console.log(`   ${sizes.join('; ')}`);
  await page.close();
});

test('a link for a dropped file names it (name, size, fingerprint); the receiver is told to drop it, a different file is flagged, the same one reproduces the result', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  await dropFile(page, 'octahedron.obj', Buffer.from(octahedron));
  await waitState(page, ['done'], 60000);
  await page.waitForFunction(() => /f\.sha=/.test(document.querySelector('[data-testid=share-url]').value), null, { timeout: 10000 });
  const link = await page.inputValue('[data-testid=share-url]');
  const hash1 = await page.evaluate(() => window.__lsw.resultHash());
  assert(/#v=4&/.test(link) && /f\.name=octahedron\.obj/.test(link) && new RegExp(`f\\.size=${octahedron.length}`).test(link) && /f\.sha=[0-9a-f]{16}/.test(link), `link: ${link}`);
  await page.click('[data-testid=copy-link]');
  assert(/cannot carry the file/.test(await page.textContent('[data-testid=notice]')), 'no notice on copying a link of a dropped file');
  const fresh = await openApp(browser, link);
  await fresh.page.waitForSelector('[data-testid=notice]:not([hidden])', { timeout: 30000 });
  const invite = await fresh.page.textContent('[data-testid=notice]');
  assert(/This link was made with octahedron\.obj \(\d+ B, fingerprint [0-9a-f]{16}\): drop it here/.test(invite), `receiver's notice: ${invite}`);
  await dropFile(fresh.page, 'octahedron.obj', Buffer.from(octahedron + '# another file\n'));
  await fresh.page.waitForFunction(() => /Not the file the link was made with/.test(document.querySelector('[data-testid=notice]').textContent), null, { timeout: 30000 });
  await waitState(fresh.page, ['done'], 60000);
  await dropFile(fresh.page, 'octahedron.obj', Buffer.from(octahedron));
  await fresh.page.waitForFunction(() => /This is the file the link was made with/.test(document.querySelector('[data-testid=notice]').textContent), null, { timeout: 30000 });
  await waitState(fresh.page, ['done'], 60000);
  await fresh.page.waitForFunction((h) => window.__lsw.resultHash() === h, hash1, { timeout: 30000 }).catch(() => {});
  const hash2 = await fresh.page.evaluate(() => window.__lsw.resultHash());
  assert(hash1 === hash2, `the same file under the link gives ${hash2}, not ${hash1}`);
  noErrors(errors);
  noErrors(fresh.errors);
  console.log(`   ${link.replace(url, '/')} → "${invite.slice(0, 110)}…"; result hash ${hash1} reproduced`);
  await fresh.page.close();
  await page.close();
});

test('simple controls in front: Detail drives the grid and the smallest edge together, Start surface keeps the level; the advanced panel shows ranges and refuses values outside them', async (browser, url) => {
  const { page, errors } = await openApp(browser, url);
  const levels = await page.evaluate(() => [...document.querySelector('[data-testid=detail]').options].filter((o) => !o.disabled).map((o) => o.value));
  const starts = await page.evaluate(() => [...document.querySelector('[data-testid=start-surface]').options].map((o) => o.value));
  assert(levels.join() === 'coarse,low,normal,high,fine' && starts.join() === 'auto,icosphere,isosurface', `menus: ${levels} / ${starts}`);
  assert((await page.inputValue('[data-testid=detail]')) === 'normal', 'the default is not "normal"');
  const shown = (key) => page.inputValue(`[data-setting="${key}"] input`);
  await page.click('#gui .lil-root > .lil-title');
  await page.locator('#gui .lil-title', { hasText: /^field$/ }).click();
  await page.locator('#gui .lil-title', { hasText: /^remesh$/ }).click();
  // Normal detail: the noisy sphere's vertex count, then coarse.
  const vertices = async () => {
    await waitState(page, ['done'], 120000);
    return Number(/(\d+) vertices/.exec(await page.textContent('#stats'))[1]);
  };
  await page.click('[data-demo=noisy-sphere]');
  const normal = await vertices();
  await page.selectOption('[data-testid=detail]', 'coarse');
  const cells = await shown('field.cells_per_min_dimension'), edge = await shown('remesh.min_edge_multiplier');
  assert(cells === '24' && edge === '0.233', `coarse sets cells ${cells}, λ_min ${edge}`);
  const link = await page.inputValue('[data-testid=share-url]');
  assert(/s\.field\.cells_per_min_dimension=24/.test(link) && /s\.remesh\.min_edge_multiplier=0\.233/.test(link), `link: ${link}`);
  await page.click('[data-testid=reset]');
  await waitState(page, ['idle'], 60000);
  await page.click('[data-testid=play]');
  const coarse = await vertices();
  assert(coarse < normal, `coarse gives ${coarse} vertices, normal ${normal}`);
  // The isosurface start's λ_min is relative to the grid cell: coarse keeps it, the level stays.
  await page.selectOption('[data-testid=start-surface]', 'isosurface');
  assert((await shown('remesh.min_edge_multiplier')) === '0.14' && (await page.inputValue('[data-testid=detail]')) === 'coarse', 'isosurface start: λ_min or level wrong');
  await page.selectOption('[data-testid=start-surface]', 'auto');
  // A value of one's own makes the level "custom"; one outside its range is refused and said so.
  const cellsInput = page.locator('[data-setting="field.cells_per_min_dimension"] input');
  await cellsInput.fill('33');
  await cellsInput.press('Enter');
  assert((await page.inputValue('[data-testid=detail]')) === 'custom', 'an own grid size does not show as custom');
  await page.locator('#gui .lil-title', { hasText: /^flow$/ }).click();
  const tau = page.locator('[data-setting="flow.tau"] input');
  assert(/\(0, 10\]/.test(await page.getAttribute('[data-setting="flow.tau"]', 'title')), 'no range in the tooltip of flow.tau');
  await tau.fill('20');
  await tau.press('Enter');
  await page.waitForSelector('[data-testid=settings-warning]:not([hidden])', { timeout: 5000 });
  assert((await tau.inputValue()) === '0.07' && /outside its range \(0, 10\]/.test(await page.textContent('[data-testid=settings-warning]')), 'τ = 20 was not refused');
  noErrors(errors);
  console.log(`   noisy sphere: ${normal} vertices at normal detail, ${coarse} at coarse (24 cells, λ_min 0.233)`);
  await page.close();
});

await runSuite(tests);

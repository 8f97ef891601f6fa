// Wiring only: UI events → worker messages; worker frames → render worker, plots and status.
// The UI thread neither computes nor draws: the flow runs in one worker, three.js in another.
// Each concern lives in its own module; this file builds them, hands each its dependencies and
// routes the workers' messages. tests/unit/layout.test.ts keeps it at most 200 lines.
import { applyCatalog, colourMenu } from './catalog-ui';
import { Compute } from './compute';
import { byId } from './dom';
import { Exporter } from './export';
import { FieldControls } from './field-view';
import { drawFrame } from './frame-view';
import { bindDrop } from './drop';
import { bindInputs } from './inputs';
import { bindHelp } from './help';
import { KeptResult } from './kept';
import { bindLayout } from './layout';
import { Lesson } from './lesson';
import { ModeSwitch } from './mode';
import { RunSettings } from './panel';
import type { Frame, FromWorker } from './protocol';
import { Renderer } from './renderer';
import { Scrubber } from './scrubber';
import { describeFile } from './share';
import { readLink, ShareLink } from './share-link';
import { StatusLine } from './status';
import { bindOrbit, ViewControls } from './view-controls';
import { WrapReadout } from './wrap-readout';
import { WrapRun } from './wrap-run';

const canvas = byId<HTMLCanvasElement>('canvas');
const health = byId('health');
const mode = new ModeSwitch();
const status = new StatusLine();
const renderer = new Renderer();
const draw = renderer.draw;

if (!renderer.attach(canvas)) {
  status.error({ code: 'unsupported', message: 'This browser cannot draw from a worker (no OffscreenCanvas).', hint: 'Use a current Chrome, Edge, Firefox or Safari (16.4 or newer).' });
  status.set('error', 'Unsupported browser');
}
bindOrbit(canvas, draw);
bindLayout();
bindHelp();

// The computation worker; its hooks reach modules built below, and run only once they exist.
const compute = new Compute({
  message: onWorkerMessage,
  failed: (e) => status.fail({ code: 'worker', message: `The computation worker failed: ${e.message}`, hint: 'The page restarts it; try a smaller grid or another preset.' }),
  // A fresh worker knows nothing of the page: tell it the colour map and field view again, and
  // start the lesson afresh, or note that the wrap's session is gone (Play loads it again).
  restarted: () => {
    view.sendColour();
    field.request();
    if (mode.current === 'mcf') lesson.reset();
    else run.lost();
  },
  unanswered: () => mode.current === 'wrap' && run.cancelledByRestart(),
});
const send = compute.send;
renderer.onError((e) => status.fail({ code: 'worker', message: `The render worker failed: ${e.message}`, hint: 'Reload the page.' }));

const updateShare = () => share.update();
const view = new ViewControls(draw, send, updateShare);
mode.onSwitch = (m) => view.offer(colourMenu(m));
const scrubber = new Scrubber(draw, { shown: (step) => (mode.current === 'mcf' ? lesson.scrubbed(step) : run.scrubbed(step)), frames: (steps) => readout.topology.place(steps) });
const field = new FieldControls(draw, send);
const settings = new RunSettings(byId('preset'), byId('gui'), send, updateShare);
const readout = new WrapReadout();
const kept = new KeptResult(draw, health);
const lesson = new Lesson({ mode, status, field, draw, send, share: updateShare });
const run = new WrapRun({ mode, status, settings, kept, readout, field, health, draw, send, cancel: () => compute.cancel(), share: updateShare, view });
const exporter = new Exporter(send, kept, () => run.name);
const sphereLesson = () => mode.current === 'mcf' && lesson.kind === 'sphere'; // its link names the lesson and its parameters
const share = new ShareLink(
  () =>
    settings.panel && {
      dataset: sphereLesson() ? 'demo:mcf' : run.dataset,
      lesson: sphereLesson() ? lesson.params() : undefined,
      preset: settings.panel.preset,
      changed: settings.panel.changed(),
      settings: settings.panel.forLink(),
      view: view.view,
      iso: mode.current === 'wrap' && run.volumeIso !== null ? run.volumeIso : undefined,
      file: (mode.current === 'wrap' && run.stamp) || undefined,
    },
  status,
);

renderer.listen((m) => {
  if (m.type === 'view') view.camera(m.yaw, m.pitch, m.zoom);
  else if (m.type === 'frames') scrubber.frames(m);
});

/** A gallery demo: MCF is the lesson; any other is a wrap of a shape the core generates. */
function startDemo(id: string): void {
  if (id === 'mcf') lesson.start('sphere');
  else run.demo(id);
}

// ---- Worker messages --------------------------------------------------------------------------

function onFrame(msg: Frame): void {
  if (msg.mode !== mode.current || (msg.mode === 'wrap' && !run.isCurrent(msg.run))) return; // a stale frame still in flight
  drawFrame(draw, msg);
  if (msg.mode === 'mcf' && msg.stats) lesson.frame({ ...msg, stats: msg.stats });
  else run.frame(msg);
}

function onWorkerMessage(msg: FromWorker): void {
  switch (msg.type) {
    case 'ready':
      return onReady(msg);
    case 'frame':
      return onFrame(msg);
    // A wrap's phases (reading, field, certificate): a wrap that ends just as a lesson starts
    // still reports its certificate, which must not cover the lesson's status.
    case 'loading':
      return void (mode.current === 'wrap' && status.set('loading', msg.what));
    case 'progress':
      return void (mode.current === 'wrap' && status.progress(msg.phase, msg.fraction));
    case 'mcf-advice':
      return lesson.advice(msg.advice);
    case 'target':
      lesson.target(msg.name, msg.lessonMesh);
      return run.loaded(msg);
    case 'result':
      return run.result(msg);
    case 'stopped':
      return mode.current === 'mcf' ? lesson.stopped(msg.reason) : run.stopped(msg.reason);
    case 'exported':
      return exporter.save(msg);
    case 'field':
      if (mode.current === 'wrap' && run.isCurrent(msg.run)) field.show(msg);
      return;
    case 'volume':
      return run.volumeLoaded(msg);
    case 'volume-slice':
      return run.volumeSlice(msg);
    case 'curves':
      return readout.curves(msg.curves);
    case 'error':
      // (Compute replaces the worker afterwards if the error may have left it unusable.)
      status.fail(msg.error);
      if (mode.current === 'wrap') run.failed();
      return;
  }
}

/** The worker's presets are in: build the settings, then open what the link asks for (else the lesson). */
function onReady(msg: Extract<FromWorker, { type: 'ready' }>): void {
  const presets = settings.build(msg.presets, msg.docs, msg.enums, msg.catalog);
  applyCatalog(msg.catalog);
  lesson.menu(msg.catalog.lessons);
  const { state, notices } = readLink(presets, { aliases: msg.aliases, tuningRows: msg.catalog.tuning.rows, colourMaps: [...msg.catalog.colourMaps.map((m) => m.name), 'none'] });
  status.notice(notices);
  settings.apply(state.preset, state.changed);
  view.apply(state.view);
  view.offer(colourMenu(mode.current)); // (after the link is read: offering rewrites the link)
  settings.sendCurves();
  const d = state.dataset;
  run.linkIso = state.iso ?? null;
  run.linkFile = state.file ?? null;
  if (state.lesson) lesson.setParams(state.lesson);
  if (state.file) status.notice([...notices, `This link was made with ${describeFile(state.file)}: drop it here to reproduce the result.`]);
  if (d && d !== 'demo:mcf') {
    if (d.startsWith('demo:')) startDemo(d.slice(5));
    else run.openUrl(d);
  } else lesson.reset();
}

// ---- Controls ---------------------------------------------------------------------------------

byId('play').onclick = () => (mode.current === 'mcf' ? lesson.play() : run.play());
byId('pause').onclick = () => send({ type: 'pause' });
byId('step').onclick = () => (mode.current === 'mcf' ? lesson.step() : run.step());
byId('cancel').onclick = () => void compute.cancel();
byId('reset').onclick = () => (mode.current === 'mcf' ? lesson.reset() : run.reset());
bindInputs({
  file: (f) => run.openFile(f),
  url: (u) => run.openUrl(u),
  demo: (id, preset) => {
    settings.forDemo(id, preset);
    startDemo(id);
  },
});
bindDrop(byId('drop'), (f) => run.openFile(f));

/** Test and automation hooks: read-only views of what is shown. */
(window as unknown as { __lsw: object }).__lsw = {
  radiusSeries: () => lesson.series(),
  areaSeries: () => lesson.areaSeries(),
  distanceSeries: () => readout.distanceSeries(),
  controlSeries: () => readout.controlSeries(),
  resultHash: () => kept.result?.hash ?? null,
  dropToDoneMs: () => run.lastDoneMs,
  phaseTimes: () => run.phases,
  wasmMemoryBytes: () => run.wasmBytes,
  meshPixelFraction: () => renderer.meshPixelFraction(),
  fieldShown: () => field.shown,
};

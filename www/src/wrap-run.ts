// A wrap from start to result: where its input comes from (demo, file, URL, a volume's
// iso-value), its run number (frames of older runs still in flight are dropped), its timing, and
// the worker's answers that belong to it (target, frames, volume, result, stop).
import { byId } from './dom';
import type { FieldControls } from './field-view';
import { showPending } from './health';
import { revealView } from './layout';
import type { KeptResult, TargetMesh } from './kept';
import type { ModeSwitch } from './mode';
import type { RunSettings, SettingsState } from './panel';
import type { Draw, Frame, FromWorker, Send, Source, StopReason, TargetInfo } from './protocol';
import { leftOutNote, repairsNote } from './protocol';
import { describeFile, sameFile, validDataset, type FileStamp } from './share';
import { stampFile } from './share-link';
import type { StatusLine } from './status';
import type { ViewControls } from './view-controls';
import { VolumePanel } from './volume';
import type { WrapReadout } from './wrap-readout';

/** What a wrap reads: a dropped or picked file (kept, so that the page can send it again), or a
 * gallery shape or address the worker generates or downloads itself. */
type Input = { kind: 'file'; file: File } | Extract<Source, { kind: 'demo' | 'url' }>;

/** The input of the kept result, with its name, dataset, file stamp and iso-value. */
interface Committed {
  input: Input;
  dataset: string | null;
  name: string;
  stamp: FileStamp | null;
  volumeIso: number | null;
}

export interface WrapRunDeps {
  mode: ModeSwitch;
  status: StatusLine;
  settings: RunSettings;
  kept: KeptResult;
  readout: WrapReadout;
  field: FieldControls;
  health: HTMLElement;
  draw: Draw;
  send: Send;
  /** Cancels the worker's job; resolves once it answered or was replaced. */
  cancel: () => Promise<void>;
  /** Rewrites the share link. */
  share: () => void;
  /** The view's target overlay and colour map, as a run and its verdict want them. */
  view: Pick<ViewControls, 'targetOverlay' | 'highlight'>;
}

export class WrapRun {
  /** Dataset of the current wrap for share links: a gallery id or URL; null for a dropped file. */
  dataset: string | null = null;
  /** The input's name, for the status line and export file names. */
  name = 'result';
  /** The stamp (name, size, fingerprint) of the current wrap's dropped or picked file, for share
   * links; null for gallery shapes and addresses, and until the fingerprint is computed. */
  stamp: FileStamp | null = null;
  /** The file a link was made with, until the same file is dropped. */
  linkFile: FileStamp | null = null;
  /** Milliseconds from the start of the last completed wrap to its result. */
  lastDoneMs = 0;
  /** Size of the core's wasm memory at the last result (bytes). */
  wasmBytes = 0;
  /** Volumes: the iso-value chosen in the panel (for share links), and one asked for by a link. */
  volumeIso: number | null = null;
  linkIso: number | null = null;
  /** Number of the current wrap run. */
  private seq = 0;
  private startedAt = 0;
  /** Working time of the last completed wrap (pauses excluded), as the worker measured it. */
  private workMs = 0;
  /** The last completed run's working time by phase (see Stopwatch). */
  phases: [string, number][] = [];
  private input: Input | null = null;
  /** Whether the worker holds a session of the current input: false after a cancel, an error or
   * a worker restart, when Play, Step and Reset first load the input again. */
  private live = false;
  /** Set while a job under way is cancelled to make way for a new input: its answer is no news. */
  private replacing = false;
  /** The current run's target, kept with its result. */
  private target: TargetMesh | null = null;
  private readonly volume: VolumePanel;
  /** The kept result's input and what described it: a run that fails gives way to it again. */
  private committed: Committed | null = null;
  /** Whether the frames, plots and readout on screen are the kept result's (since its result). */
  private keptShown = false;
  /** The settings before this run's input gave the user's own back from a demo (null: untouched):
   * a run that fails puts them back with the kept result. */
  private settingsBefore: SettingsState | null = null;

  constructor(private readonly d: WrapRunDeps) {
    this.volume = new VolumePanel(byId('volume'), {
      onIso: (iso, frame) => this.wrapAtIso(iso, frame),
      onSlice: (axis, index) => d.send({ type: 'volume-slice', axis, index }),
    });
  }

  /** Whether a message of run `run` belongs to the current run. */
  isCurrent(run: number): boolean {
    return run === this.seq;
  }

  /**
   * Wraps a new input with the current settings. What described the previous run is cleared at
   * once; a job under way is cancelled first; the kept result stays until the new one completes.
   */
  private async start(input: Input, dataset: string | null, name: string): Promise<void> {
    const { mode, status, settings, kept, health } = this.d;
    if (!settings.panel) return;
    const busy = status.busy;
    const aside = this.keptShown && mode.current === 'wrap';
    mode.set('wrap');
    const before = settings.snapshot();
    const demoPreset = input.kind === 'demo' ? null : settings.restoreOwn();
    if (demoPreset) this.settingsBefore = before; // (kept until a result or a failure)
    this.input = input;
    this.stamp = null;
    if (input.kind === 'file') void this.stampInput(input.file);
    this.dataset = dataset;
    this.name = name;
    this.clear(aside);
    showPending(health, 'certificate: when the wrap ends');
    kept.showPrevious();
    this.volume.hide();
    this.volumeIso = this.linkIso;
    this.linkIso = null;
    status.set('loading', `Loading ${name}${settings.inForce()}…`);
    if (demoPreset) status.notice([`The demo's preset (${demoPreset}) was the demo's own: ${name} is wrapped with your settings${settings.inForce() || ' (the default preset)'}.`]);
    revealView();
    this.d.share();
    if (busy) {
      this.replacing = true;
      await this.d.cancel();
      this.replacing = false;
    }
    await this.load(true);
  }

  /** Fingerprints a dropped file for share links and checks it against the file a link named. */
  private async stampInput(file: File): Promise<void> {
    const stamp = await stampFile(file);
    if (this.input?.kind !== 'file' || this.input.file !== file) return;
    this.stamp = stamp;
    if (this.committed?.input === this.input) this.committed.stamp = stamp;
    this.d.share();
    const expected = this.linkFile;
    if (!expected) return;
    const same = sameFile(expected, stamp);
    if (same) this.linkFile = null;
    this.d.status.notice(
      same
        ? [`✓ This is the file the link was made with: ${describeFile(stamp)}.`]
        : [`⚠ Not the file the link was made with: it names ${describeFile(expected)}, this is ${describeFile(stamp)}. The result may differ from the link's.`],
    );
  }

  /** Sends the input to the worker (a file is read again: the bytes sent before were transferred). */
  private async load(autoplay: boolean): Promise<void> {
    const input = this.input;
    if (!input || !this.d.settings.panel) return;
    const run = ++this.seq;
    this.live = false;
    this.startedAt = performance.now();
    const source: Source = input.kind === 'file' ? { kind: 'bytes', bytes: await input.file.arrayBuffer(), name: input.file.name } : input;
    if (run !== this.seq) return; // a newer input or reset came while the file was read
    const msg = { type: 'wrap-load', source, settings: this.d.settings.values(), autoplay, run, iso: this.volumeIso ?? undefined } as const;
    this.d.send(msg, source.kind === 'bytes' ? [source.bytes] : []);
  }

  /** Clears the previous run's readout, plots, frames, field view and input description; its
   * messages still in flight are stale from now on. `aside`: they are the kept result's, kept
   * for a run that fails. */
  private clear(aside = false): void {
    const { status, readout, draw } = this.d;
    if (aside) readout.setAside();
    draw({ type: 'clear-frames', aside: aside ? 'set' : 'keep' });
    this.keptShown = false;
    this.seq++;
    status.error(null);
    status.clearReadout();
    readout.clear();
    draw({ type: 'refit' });
    draw({ type: 'field' });
    byId('target-info').textContent = '';
  }

  /** A gallery shape, generated by the core. */
  demo(id: string): void {
    void this.start({ kind: 'demo', id: `demo:${id}` }, `demo:${id}`, id);
  }

  openFile(file: File): void {
    void this.start({ kind: 'file', file }, null, file.name);
  }

  openUrl(url: string): void {
    if (!validDataset(url) || url.startsWith('demo:')) {
      this.d.status.error({ code: 'bad-url', message: `"${url.slice(0, 80)}" is not an http(s) address.`, hint: 'Give a full address such as https://example.org/scan.ply.' });
      return;
    }
    void this.start({ kind: 'url', url }, url, decodeURIComponent(new URL(url).pathname.split('/').pop() || 'download'));
  }

  /** Play: steps on, or (no session since a cancel or a restart) loads the input again and plays. */
  play(): void {
    const { status, send } = this.d;
    if (!this.input) return void status.set(status.state, 'Nothing to wrap yet — drop a file, pick one or choose a demo');
    if (this.live) {
      status.error(null);
      send({ type: 'play' });
      status.set('running', `Wrapping ${this.name}${this.d.settings.inForce()}`);
    } else this.again(true);
  }

  /** Step: one step, or (no session) the input loaded again, ready to step. */
  step(): void {
    if (this.live) this.d.send({ type: 'step', n: 1 });
    else this.again(false);
  }

  /** Reset: the state right after loading the input, with the current settings; starts nothing. */
  reset(): void {
    this.again(false);
  }

  private again(autoplay: boolean): void {
    if (!this.input) return;
    this.clear(this.keptShown);
    showPending(this.d.health, 'certificate: when the wrap ends');
    this.d.status.set('loading', `Loading ${this.name}${this.d.settings.inForce()}…`);
    void this.load(autoplay);
  }

  /** The worker reported an error. A run without a result gives way to the kept one: its input,
   * link, frames, plots and readout come back with it, and Play wraps it again. */
  failed(): void {
    const { status, kept, readout, draw } = this.d;
    this.live = false;
    kept.restore();
    if (this.keptShown) return; // the error came after this run's own result
    const failed = this.name, c = this.committed;
    this.seq++; // frames of the failed run still in flight are stale
    this.keptShown = readout.restore();
    if (this.keptShown) draw({ type: 'restore-frames' });
    if (this.settingsBefore) this.d.settings.put(this.settingsBefore);
    this.settingsBefore = null;
    this.input = c?.input ?? null;
    [this.dataset, this.name, this.stamp, this.volumeIso] = c ? [c.dataset, c.name, c.stamp, c.volumeIso] : [null, 'result', null, null];
    this.d.share();
    status.set('error', c ? `${failed} could not be wrapped — the result of ${c.name} is kept; Play wraps ${c.name} again` : `${failed} could not be wrapped — drop another file, pick one or choose a demo`);
  }

  /** The worker lost its session (replaced after a crash or an unanswered cancel). */
  lost(): void {
    this.live = false;
  }

  /** A cancel went unanswered and the worker was replaced: back to a ready state. */
  cancelledByRestart(): void {
    if (this.replacing) return;
    this.live = false;
    this.d.status.set('idle', `Cancelled (worker restarted) — Play wraps ${this.name} again`);
    this.d.kept.restore();
  }

  /** Volumes: the panel chose an iso-value (or a volume of a 4-D file): wrap the input again there. */
  private wrapAtIso(iso: number, frame: number): void {
    const { status, settings, send } = this.d;
    if (!settings.panel) return;
    this.volumeIso = Number(iso.toPrecision(6));
    this.d.share();
    status.set('loading', `Wrapping at iso-value ${iso.toPrecision(4)}…`);
    if (!this.live) return void this.load(true); // the worker no longer holds the volume
    this.live = false;
    send({ type: 'volume-iso', iso, frame, settings: settings.values(), run: ++this.seq });
  }

  /** The input is loaded: draw it, offer its distance field, describe it. */
  loaded(msg: Extract<FromWorker, { type: 'target' }>): void {
    if (!this.isCurrent(msg.run)) return;
    this.live = true;
    this.target = { positions: msg.positions.slice(), indices: msg.indices.slice() };
    this.d.draw({ type: 'target', positions: msg.positions, indices: msg.indices.length ? msg.indices : null }, [msg.positions.buffer, msg.indices.buffer]);
    this.d.view.targetOverlay(true);
    this.d.view.highlight(null);
    const i: TargetInfo = msg.info;
    this.d.field.reveal();
    byId('target-info').textContent = `${msg.name}: ${i.format}, ${i.kind === 'points' ? `${i.points} points` : `${i.points} vertices, ${i.triangles} triangles`}, diagonal ${i.diagonal.toPrecision(4)}${repairsNote(i.repairs)}${leftOutNote(i.leftOut)}`;
  }

  /** A frame of the current run (already drawn): progress, plots, status. */
  frame(msg: Frame): void {
    this.d.readout.frame(msg);
    if (msg.playing) this.d.status.set('running', `Wrapping ${this.name}${this.d.settings.inForce()} — step ${msg.report?.step ?? 0}`);
  }

  /** The scrubber shows the frame of `step` (null: the live end): the badge follows it. */
  scrubbed(step: number | null): void {
    if (this.d.mode.current !== 'wrap') return; // the lesson's frames have no certificate
    const k = this.d.kept.result;
    this.d.readout.topology.show(this.d.health, step, k ?? null);
  }

  /** The input is a voxel volume: show its panel (histogram, slices, iso-value). */
  volumeLoaded(msg: Extract<FromWorker, { type: 'volume' }>): void {
    if (this.isCurrent(msg.run)) this.volume.show(msg.info, msg.histogram, msg.iso);
  }

  volumeSlice(msg: Extract<FromWorker, { type: 'volume-slice' }>): void {
    this.volume.slice(msg);
  }

  /** The run completed: keep its result and time it. */
  result(msg: Extract<FromWorker, { type: 'result' }>): void {
    if (!this.isCurrent(msg.run)) return;
    this.d.kept.keep(msg, this.target);
    this.d.view.targetOverlay(false);
    this.d.view.highlight(msg.verdict.highlight ?? null);
    this.keptShown = true;
    this.settingsBefore = null;
    if (this.input) this.committed = { input: this.input, dataset: this.dataset, name: this.name, stamp: this.stamp, volumeIso: this.volumeIso };
    this.wasmBytes = msg.wasmBytes;
    this.workMs = msg.elapsedMs;
    this.phases = msg.phases;
    this.d.readout.timed(msg.elapsedMs, msg.phases);
    this.d.readout.exact(msg.certificate);
    this.d.readout.topology.result(msg.startedOver);
    this.lastDoneMs = performance.now() - this.startedAt;
    byId('hash').dataset.ms = String(Math.round(this.lastDoneMs));
    this.d.draw({ type: 'fit' });
  }

  /** The worker stopped stepping; a finished wrap is done only if its result is certified. */
  stopped(reason: StopReason): void {
    const { status, kept } = this.d;
    if (this.replacing) return;
    const k = kept.result;
    if (reason === 'finished' && k && k.verdict.state !== 'valid') status.set('invalid', `${k.verdict.headline} — ${k.why}`);
    else if (reason === 'finished') {
      const notes = k && k.verdict.notes.length > 0 ? `; ${k.verdict.notes.join('; ')}` : '';
      status.set('done', `Done — ${this.name} wrapped in ${(this.workMs / 1000).toFixed(1)} s${this.d.settings.inForce()}${notes}`);
    }
    else if (reason === 'cancelled') {
      this.live = false;
      status.set('idle', `Cancelled — Play wraps ${this.name} again`);
      kept.restore();
    } else if (reason === 'ready') status.set('idle', `Ready — ${this.name} is loaded: Play wraps it`);
    else status.set('paused', `Paused — Play goes on, Cancel ends the wrap of ${this.name}`);
  }
}

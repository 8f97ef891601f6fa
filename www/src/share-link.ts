// The share link: the page's state (dataset, preset, changed settings, view, volume iso-value)
// written into the URL hash with share.ts's versioned codec, and read back when the page opens.
import { byId } from './dom';
import { decode, encode, validDataset, type Decoded, type DecodeOptions, type Flat, type ShareState } from './share';
import type { StatusLine } from './status';

export class ShareLink {
  private readonly field = byId<HTMLInputElement>('share-url');
  private readonly button = byId('copy-link');

  /**
   * `state`: the state to share, or null while there are no settings yet (before the worker's presets);
   * `droppedFile`: whether the input is a dropped file, which a link cannot carry.
   */
  constructor(private readonly state: () => ShareState | null, droppedFile: () => boolean, status: StatusLine) {
    this.button.onclick = async () => {
      this.update();
      const url = this.field.value;
      if (droppedFile()) status.notice(['A dropped file cannot travel in a link: the link keeps the settings and view; the receiver drops the same file.']);
      try {
        await navigator.clipboard.writeText(url);
        this.button.textContent = 'Copied ✓';
      } catch {
        this.field.select();
        this.button.textContent = 'Select and copy the link below';
      }
      setTimeout(() => (this.button.textContent = 'Copy link'), 2000);
    };
  }

  /** Rewrites the address (without a history entry) and the link field. */
  update(): void {
    const s = this.state();
    if (!s) return;
    history.replaceState(null, '', `${location.pathname}#${encode(s)}`);
    this.field.value = location.href;
  }
}

/** The state the page was opened with: the hash, and ?src= (a file's address) over its dataset. */
export function readLink(presets: Record<string, Flat>, opts: DecodeOptions): Decoded {
  const { state, notices } = decode(location.hash, presets, opts);
  const src = new URLSearchParams(location.search).get('src');
  if (src !== null) {
    if (validDataset(src) && !src.startsWith('demo:')) state.dataset = src;
    else notices.push(`Ignored ?src=${src.slice(0, 60)}: not an http(s) address.`);
  }
  return { state, notices };
}

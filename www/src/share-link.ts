// The share link: the page's state (dataset, preset, changed settings, view, volume iso-value,
// the dropped file's stamp) written into the URL hash with share.ts's versioned codec, and read
// back when the page opens.
import { byId } from './dom';
import { decode, describeFile, encode, validDataset, type Decoded, type DecodeOptions, type FileStamp, type Flat, type ShareState } from './share';
import type { StatusLine } from './status';

/** A dropped file's stamp for links: name, size and the first 8 bytes of its SHA-256 in hex (the
 * browser's digest; '' where there is none, e.g. a page not served from a secure origin). */
export async function stampFile(file: File): Promise<FileStamp> {
  let sha = '';
  try {
    const digest = await crypto.subtle.digest('SHA-256', await file.arrayBuffer());
    sha = [...new Uint8Array(digest, 0, 8)].map((b) => b.toString(16).padStart(2, '0')).join('');
  } catch {
    // No SubtleCrypto here: the link names the file by name and size only.
  }
  return { name: file.name, size: file.size, sha };
}

export class ShareLink {
  private readonly field = byId<HTMLInputElement>('share-url');
  private readonly button = byId('copy-link');

  /** `state`: the state to share, or null while there are no settings yet (before the worker's presets). */
  constructor(private readonly state: () => ShareState | null, status: StatusLine) {
    this.button.onclick = async () => {
      this.flush();
      const url = this.field.value;
      const file = this.state()?.file;
      if (file) status.notice([`The link names ${describeFile(file)} but cannot carry the file itself: whoever opens it drops the same file to reproduce the result.`]);
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

  private pending = false;

  /** Rewrites the address and the link field soon, once for all the changes of this task: a
   * history update costs 10–30 ms on a loaded machine, and a demo's click made two. */
  update(): void {
    if (this.pending) return;
    this.pending = true;
    setTimeout(() => this.flush(), 0);
  }

  /** Rewrites the address (without a history entry) and the link field now. */
  flush(): void {
    this.pending = false;
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

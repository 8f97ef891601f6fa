// Export: the worker writes the file (from its live session, else from the kept mesh sent with
// the request); the page only saves the bytes under a name that says whether the mesh is valid.
import type { KeptResult } from './kept';
import type { FromWorker, Send } from './protocol';

export class Exporter {
  /** `inputName`: the current input's name, for the file name when nothing is kept yet. */
  constructor(send: Send, private readonly kept: KeptResult, private readonly inputName: () => string) {
    // One listener for the buttons the catalog puts there (catalog-ui.ts).
    document.getElementById('exports')!.addEventListener('click', (e) => {
      const format = (e.target as HTMLElement).closest<HTMLButtonElement>('[data-format]')?.dataset.format;
      if (!format) return;
      const k = kept.result;
      send({ type: 'export', format, kept: k ? { positions: k.positions.slice(), indices: k.indices.slice() } : undefined });
    });
  }

  /** Saves the worker's file as a download. */
  save(msg: Extract<FromWorker, { type: 'exported' }>): void {
    const k = this.kept.result;
    // An invalid result is only ever exported under a name that says so.
    const stem = ((k?.name ?? this.inputName()).replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_') || 'result') + (k && !k.valid ? '-NOT-VALID' : '');
    const blob = new Blob([msg.bytes as BlobPart], { type: 'application/octet-stream' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${stem}-wrapped.${msg.format}`;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  }
}

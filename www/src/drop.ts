// Drag and drop anywhere on the page: an overlay while a drag is over the page, and the dropped
// file is opened. dragenter / dragleave fire for every child crossed, hence the depth count.

export function bindDrop(overlay: HTMLElement, open: (file: File) => void): void {
  let depth = 0;
  window.addEventListener('dragenter', (e) => {
    e.preventDefault();
    depth++;
    overlay.hidden = false;
  });
  window.addEventListener('dragleave', () => {
    if (--depth <= 0) {
      depth = 0;
      overlay.hidden = true;
    }
  });
  window.addEventListener('dragover', (e) => e.preventDefault());
  window.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    overlay.hidden = true;
    const f = e.dataTransfer?.files?.[0];
    if (f) open(f);
  });
}

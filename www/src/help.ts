// The help overlay: three steps for a newcomer, shown on the first visit only (remembered in
// localStorage), dismissable, and again from the header's "?". It sits over the 3-D view and
// leaves the controls free, so nothing waits for it to be closed.
import { byId } from './dom';

/** The localStorage key that remembers the help was seen. */
export const HELP_SEEN = 'lsw.help.seen';

export function bindHelp(): void {
  const box = byId('help');
  const close = () => {
    box.hidden = true;
    try {
      localStorage.setItem(HELP_SEEN, '1');
    } catch {
      // Storage refused (private mode): the help shows again next time, nothing worse.
    }
  };
  byId('help-close').onclick = close;
  byId('help-open').onclick = () => (box.hidden = !box.hidden);
  window.addEventListener('keydown', (e) => e.key === 'Escape' && !box.hidden && close());
  let seen = false;
  try {
    seen = localStorage.getItem(HELP_SEEN) !== null;
  } catch {
    seen = false;
  }
  box.hidden = seen;
}

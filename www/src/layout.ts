// The page's layout controls: the side panel can be hidden to give the view the whole width
// (the plots and every panel section fold with their own <details> summaries).
import { byId } from './dom';

export function bindLayout(): void {
  const toggle = byId('toggle-side');
  toggle.onclick = () => {
    const hidden = document.body.dataset.side !== 'hidden';
    document.body.dataset.side = hidden ? 'hidden' : '';
    toggle.setAttribute('aria-expanded', String(!hidden));
  };
}

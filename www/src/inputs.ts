// The Input fieldset: the file picker, the URL form and the demo gallery buttons.
import { byId } from './dom';

export interface InputActions {
  file: (file: File) => void;
  url: (url: string) => void;
  /** A gallery button: its demo id and the preset it names, if any. */
  demo: (id: string, preset: string | undefined) => void;
}

export function bindInputs(act: InputActions): void {
  byId<HTMLInputElement>('file').onchange = (e) => {
    const input = e.target as HTMLInputElement;
    const f = input.files?.[0];
    if (f) act.file(f);
    input.value = ''; // the same file picked again is a new wrap
  };
  byId('url-form').onsubmit = (e) => {
    e.preventDefault();
    act.url(byId<HTMLInputElement>('url').value.trim());
  };
  for (const b of document.querySelectorAll<HTMLButtonElement>('[data-demo]')) b.onclick = () => act.demo(b.dataset.demo!, b.dataset.preset);
}

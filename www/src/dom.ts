// The page's elements by id. index.html is the one source of ids, and no element is ever
// replaced, so modules may look theirs up once when they are built.

/** The element with this id (a missing one is a bug in index.html, not a state to handle). */
export const byId = <T extends HTMLElement = HTMLElement>(id: string): T => document.getElementById(id) as T;

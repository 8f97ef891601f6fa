// A helper of the computation worker, one per wrap of a cloud: it finds the cloud's sharp creases
// in a wasm instance of its own while the steps run, so that the final fit does not spend that
// time on the one thread (1 M points: 0.4–0.7 s). The fit finds the same creases itself when no
// answer came in time; so an error here only costs that time, and is answered with none.
import init, { cloudCreases } from '../pkg/lsw.js';
import type { CreaseReply, CreaseRequest } from './protocol';

const ready = init();

self.onmessage = async (ev: MessageEvent<CreaseRequest>) => {
  let reply: CreaseReply;
  try {
    await ready;
    reply = { creases: cloudCreases(ev.data.job) };
  } catch {
    reply = { creases: null };
  }
  (self as unknown as Worker).postMessage(reply, reply.creases ? [reply.creases.buffer] : []);
};

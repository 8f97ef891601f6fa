// How many solver steps the worker runs before posting a frame: enough to amortise the copy,
// few enough to keep frames flowing (~30 ms of work) and to answer "pause" quickly.

/** Next batch size given the measured cost of one step (ms) and a frame budget (ms). */
export function batchSize(msPerStep: number, budgetMs = 30, maxBatch = 50): number {
  if (!(msPerStep > 0) || !Number.isFinite(msPerStep)) return 1;
  return Math.max(1, Math.min(maxBatch, Math.floor(budgetMs / msPerStep)));
}

// How many solver steps the worker runs before posting a frame: enough to amortise the copy,
// few enough to keep frames flowing (~30 ms of work) and to answer "pause" quickly.

/** Next batch size given the measured cost of one step (ms) and a frame budget (ms). */
export function batchSize(msPerStep: number, budgetMs = 30, maxBatch = 50): number {
  if (!(msPerStep > 0) || !Number.isFinite(msPerStep)) return 1;
  return Math.max(1, Math.min(maxBatch, Math.floor(budgetMs / msPerStep)));
}

/** Frames a lesson records over its whole run at least, on any machine: the scrubber then shows
 * the same spacing of the flow whatever the steps cost. */
export const LESSON_FRAMES = 32;

/** A lesson's batch: the frame budget's, but never more than its run's share of LESSON_FRAMES. */
export function lessonBatch(msPerStep: number, totalSteps: number): number {
  return batchSize(msPerStep, 30, Math.max(1, Math.min(50, Math.ceil(totalSteps / LESSON_FRAMES))));
}

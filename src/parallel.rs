//! Data-parallel loops, in one place: natively on rayon's thread pool, in wasm (one thread)
//! sequentially. Every loop maps indices to values that are collected in index order and
//! combined by the caller in that order, so the result does not depend on the number of threads
//! (a shared link must reproduce a result bit for bit).

/// `f(i)` for `i` in `0..n`, in index order, computed in chunks of `chunk` indices (each chunk
/// spread over the threads); `done(k)` hears after each chunk how many are done, so a long loop
/// can report progress on the caller's thread.
pub fn map_chunked<T, F>(n: usize, chunk: usize, f: F, done: &mut dyn FnMut(usize)) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    let chunk = chunk.max(1);
    let mut out = Vec::with_capacity(n);
    let mut start = 0;
    while start < n {
        let end = (start + chunk).min(n);
        extend_range(&mut out, start..end, &f);
        done(end);
        start = end;
    }
    out
}

/// `f(i)` for `i` in `0..n`, in index order.
pub fn map<T, F>(n: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    let mut out = Vec::with_capacity(n);
    extend_range(&mut out, 0..n, &f);
    out
}

/// `f(i)` for `i` in `0..n`, in index order, each index a task of its own: for a few items of
/// much work each (a loop the caller cut into chunks of about equal work), which [`map`] would
/// run on one thread.
pub fn map_each<T, F>(n: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    #[cfg(not(target_arch = "wasm32"))]
    {
        use rayon::prelude::*;
        (0..n).into_par_iter().with_min_len(1).map(f).collect()
    }
    #[cfg(target_arch = "wasm32")]
    {
        (0..n).map(f).collect()
    }
}

/// `f(k, chunk)` for the consecutive chunks of `chunk_len` items of `data` (the last may be
/// shorter); `done(k)` hears, every `group` chunks and at the end, how many chunks are done. For
/// loops that scatter into disjoint parts of one array. Natively the chunks are spread over the
/// threads all at once — not group by group, which would leave a core idle whenever a group's
/// busy chunks fall to one thread (a mesh's band: the surface fills a few slabs of the grid) —
/// and the counts come to this thread as chunks finish; in wasm they run in order.
pub fn for_each_chunk_mut<T, F>(
    data: &mut [T],
    chunk_len: usize,
    group: usize,
    f: F,
    done: &mut dyn FnMut(usize),
) where
    T: Send,
    F: Fn(usize, &mut [T]) + Sync + Send,
{
    let chunk_len = chunk_len.max(1);
    let (total, group) = (data.len().div_ceil(chunk_len), group.max(1));
    let mut count = 0;
    let mut finished = |count: usize| {
        if count % group == 0 || count == total {
            done(count);
        }
    };
    #[cfg(not(target_arch = "wasm32"))]
    {
        use rayon::prelude::*;
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        std::thread::scope(|scope| {
            let work = scope.spawn(move || {
                data.par_chunks_mut(chunk_len)
                    .enumerate()
                    .for_each_with(tx, |tx, (k, c)| {
                        f(k, c);
                        // (The receiver lives until every sender is gone.)
                        let _ = tx.send(());
                    });
            });
            for () in rx {
                count += 1;
                finished(count);
            }
            if let Err(panic) = work.join() {
                std::panic::resume_unwind(panic);
            }
        });
    }
    #[cfg(target_arch = "wasm32")]
    for (k, c) in data.chunks_mut(chunk_len).enumerate() {
        f(k, c);
        count += 1;
        finished(count);
    }
}

/// `(side(), main())`: natively `side` runs on a thread of its own while `main` runs on this
/// one (for work that only `main`'s result will need, done while an idle core waits out the
/// sequential parts of `main`); in wasm one after the other.
pub fn beside<S, RS, M, RM>(side: S, main: M) -> (RS, RM)
where
    S: FnOnce() -> RS + Send,
    RS: Send,
    M: FnOnce() -> RM,
{
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::thread::scope(|scope| {
            let handle = scope.spawn(side);
            let main = main();
            match handle.join() {
                Ok(side) => (side, main),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        })
    }
    #[cfg(target_arch = "wasm32")]
    {
        (side(), main())
    }
}

/// A result computed off the caller's thread (natively), for work that only a much later call
/// needs and that would otherwise hold up everything after it: see [`later`].
pub struct Later<T>(LaterState<T>);

enum LaterState<T> {
    Ready(T),
    #[cfg(not(target_arch = "wasm32"))]
    Running(std::thread::JoinHandle<T>),
}

/// `f` on a thread of its own natively, its parallel loops kept on that one thread (a pool of
/// one): it fills the idle core while the caller runs its sequential parts, and never holds the
/// shared pool's threads that the caller's own parallel loops wait for. In wasm (one thread),
/// or where no thread can be started, `f` runs here, now, with `progress` (from 0); natively its
/// progress is not reported. Either way the value is the same.
pub fn later<T, F>(f: F, progress: &mut dyn FnMut(f64)) -> Later<T>
where
    T: Send + 'static,
    F: FnOnce(&mut dyn FnMut(f64)) -> T + Send + 'static,
{
    #[cfg(not(target_arch = "wasm32"))]
    {
        if let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(1).build() {
            let run = move || pool.install(|| f(&mut |_| {}));
            return Later(LaterState::Running(std::thread::spawn(run)));
        }
    }
    progress(0.0);
    Later::ready(f(progress))
}

impl<T> Later<T> {
    /// A value already at hand.
    pub fn ready(value: T) -> Self {
        Later(LaterState::Ready(value))
    }

    /// Whether the value is computed on another thread (it may be done already).
    pub fn elsewhere(&self) -> bool {
        !matches!(self.0, LaterState::Ready(_))
    }

    /// The value, waiting for it if it is still being computed (a panic there resumes here).
    pub fn get(self) -> T {
        match self.0 {
            LaterState::Ready(value) => value,
            #[cfg(not(target_arch = "wasm32"))]
            LaterState::Running(handle) => match handle.join() {
                Ok(value) => value,
                Err(panic) => std::panic::resume_unwind(panic),
            },
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn extend_range<T: Send, F: Fn(usize) -> T + Sync + Send>(
    out: &mut Vec<T>,
    range: std::ops::Range<usize>,
    f: &F,
) {
    use rayon::prelude::*;
    // Below a few hundred items the pool's hand-off costs more than it saves.
    if range.len() < 512 {
        out.extend(range.map(f));
    } else {
        out.par_extend(range.into_par_iter().map(f));
    }
}

#[cfg(target_arch = "wasm32")]
fn extend_range<T: Send, F: Fn(usize) -> T + Sync + Send>(
    out: &mut Vec<T>,
    range: std::ops::Range<usize>,
    f: &F,
) {
    out.extend(range.map(f));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_index_order_and_reports_each_chunk() {
        let mut seen = vec![];
        let v = map_chunked(5000, 1024, |i| i * i, &mut |k| seen.push(k));
        assert_eq!(v, (0..5000).map(|i| i * i).collect::<Vec<_>>());
        assert_eq!(seen, vec![1024, 2048, 3072, 4096, 5000]);
        assert_eq!(map(3, |i| i + 1), vec![1, 2, 3]);
        assert_eq!(map_each(3, |i| i + 1), vec![1, 2, 3]);
        assert!(map_chunked(0, 8, |i| i, &mut |_| panic!("no chunk")).is_empty());
    }

    #[test]
    fn beside_returns_both_results() {
        let data = [1, 2, 3];
        let (a, b) = beside(|| data.iter().sum::<i32>(), || data.len());
        assert_eq!((a, b), (6, 3));
    }

    #[test]
    fn later_gives_its_work_s_value_and_reports_progress_only_when_run_in_place() {
        // (A parallel loop inside runs on the pool of one, in index order as everywhere.)
        let work = |_: &mut dyn FnMut(f64)| map(5000, |i| i * 3);
        let value = later(work, &mut |_| {}).get();
        assert_eq!(value, (0..5000).map(|i| i * 3).collect::<Vec<_>>());
        let mut reported = vec![];
        let now = later(
            |p: &mut dyn FnMut(f64)| {
                p(1.0);
                7
            },
            &mut |f| reported.push(f),
        );
        assert_eq!(now.get(), 7);
        // Natively the work runs elsewhere and reports nothing; in wasm it runs here, from 0.
        let expected: Vec<f64> = if cfg!(target_arch = "wasm32") {
            vec![0.0, 1.0]
        } else {
            vec![]
        };
        assert_eq!(reported, expected);
    }

    #[test]
    fn chunks_are_numbered_in_order_and_cover_the_data() {
        let mut data = vec![0usize; 10];
        let mut seen = vec![];
        for_each_chunk_mut(&mut data, 3, 2, |k, c| c.fill(k + 1), &mut |k| seen.push(k));
        assert_eq!(data, [1, 1, 1, 2, 2, 2, 3, 3, 3, 4]);
        assert_eq!(seen, vec![2, 4]);
    }
}

//! Stable sort of (cell, index) pairs by cell, shared by the spatial grids: a least-significant-
//! digit radix sort whose per-digit counting tables stay in the cache. A counting sort straight
//! into millions of cells moves each entry to a random place of a bucket array far larger than
//! the caches, and a comparison sort is O(n log n).

/// Bits per digit: a table of 4 096 counts stays in the cache.
pub const RADIX_BITS: u32 = 12;

/// `pairs` sorted by cell (every cell < `cells`), stable: in input order within a cell.
///
/// Natively, long inputs are cut into [`CHUNKS`] runs counted and scattered on the threads at
/// once: each run's entries of a digit go to their own stretch of that digit's bucket, after
/// those of the runs before it, so the result is the one stable order whatever the threads.
pub fn radix_sort_by_cell<K: Copy + Into<u64> + Send + Sync>(
    mut pairs: Vec<(K, u32)>,
    cells: u64,
) -> Vec<(K, u32)> {
    let bits = u64::BITS - cells.saturating_sub(1).leading_zeros();
    let Some(&first) = pairs.first() else {
        return pairs;
    };
    let chunks = match cfg!(target_arch = "wasm32") || pairs.len() < PARALLEL_FROM {
        true => 1,
        false => CHUNKS,
    };
    let len = pairs.len().div_ceil(chunks);
    let mut out = vec![first; pairs.len()];
    let mut shift = 0;
    while shift < bits {
        let digit = |k: K| ((k.into() >> shift) as usize) & ((1 << RADIX_BITS) - 1);
        let runs: Vec<&[(K, u32)]> = pairs.chunks(len).collect();
        let counts = |run: &[(K, u32)]| {
            let mut count = vec![0usize; 1 << RADIX_BITS];
            for &(k, _) in run {
                count[digit(k)] += 1;
            }
            count
        };
        let mut starts: Vec<Vec<usize>> = match runs.len() {
            1 => vec![counts(runs[0])],
            n => crate::parallel::map_each(n, |r| counts(runs[r])),
        };
        // Digit by digit, run by run: where each run's entries of each digit begin.
        let mut at = 0;
        for d in 0..1 << RADIX_BITS {
            for count in starts.iter_mut() {
                let n = count[d];
                count[d] = at;
                at += n;
            }
        }
        let shared = SharedOut(out.as_mut_ptr(), out.len());
        let scatter = |r: usize, start: &[usize]| {
            let mut start = start.to_vec();
            for &pair in runs[r] {
                let d = digit(pair.0);
                // SAFETY: the runs' digit stretches are disjoint, so no other run's thread
                // writes `start[d]` in this pass, and nothing reads `out` until it ends.
                unsafe { shared.write(start[d], pair) };
                start[d] += 1;
            }
        };
        match runs.len() {
            1 => scatter(0, &starts[0]),
            n => {
                crate::parallel::map_each(n, |r| scatter(r, &starts[r]));
            }
        }
        std::mem::swap(&mut pairs, &mut out);
        shift += RADIX_BITS;
    }
    pairs
}

/// Runs a long sort is cut into natively (a few per core, so that a slow thread is waited on
/// briefly).
const CHUNKS: usize = 8;

/// Shorter inputs are sorted on one thread: the hand-off would cost more than it saves.
const PARALLEL_FROM: usize = 1 << 16;

/// The output of a scatter pass, written from several threads at places that are disjoint by
/// construction: the runs' digit stretches partition it.
struct SharedOut<T>(*mut T, usize);

// SAFETY: the pointer is only written through [`SharedOut::write`], whose callers keep the
// threads on disjoint indices, into a buffer that outlives the pass.
unsafe impl<T: Send> Sync for SharedOut<T> {}

impl<T> SharedOut<T> {
    /// Writes `value` at index `i` (checked against the length; the old entry is not dropped).
    ///
    /// # Safety
    /// No other thread may read or write index `i` while this runs.
    unsafe fn write(&self, i: usize, value: T) {
        assert!(i < self.1, "radix scatter out of bounds");
        // SAFETY: in bounds (checked); the caller keeps other threads off index `i`.
        unsafe { self.0.add(i).write(value) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a stable comparison sort by cell gives, for one digit, several, and 60-bit keys.
    #[test]
    fn it_is_a_stable_sort_by_cell() {
        let mut rng = crate::demo::Rng::new(9);
        // (200 000 pairs: sorted in runs on several threads natively.)
        let cases = [
            (1u64, 10_000),
            (100, 10_000),
            (5_000, 200_000),
            (1 << 30, 10_000),
            (1 << 30, 200_000),
            (1 << 60, 10_000),
        ];
        for (cells, n) in cases {
            let pairs: Vec<(u64, u32)> = (0..n)
                .map(|i| (((rng.uniform() * cells as f64) as u64).min(cells - 1), i))
                .collect();
            let mut want = pairs.clone();
            want.sort_by_key(|&(k, _)| k);
            assert_eq!(radix_sort_by_cell(pairs, cells), want, "{cells} cells");
        }
        let small: Vec<(u32, u32)> = vec![(3, 0), (1, 1), (3, 2), (0, 3)];
        assert_eq!(
            radix_sort_by_cell(small, 4),
            vec![(0, 3), (1, 1), (3, 0), (3, 2)]
        );
        assert!(radix_sort_by_cell(Vec::<(u32, u32)>::new(), 0).is_empty());
    }
}

//! Deterministic parallel evaluation: element results are computed in parallel, in fixed chunks, and
//! consumed in element order.
//!
//! Consuming in a fixed order makes every sum (energy, gradient entries, Hessian values) bit-identical
//! for any number of threads, without locks or unsafe shared writes: only the element kernels run in
//! parallel, and while one chunk is being scattered the next one is already being computed.

use rayon::prelude::*;

/// Whether evaluations may use the rayon thread pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Parallelism {
    /// Everything on the calling thread.
    Sequential,
    /// Element kernels on the current rayon pool (all its threads). Default.
    #[default]
    Rayon,
}

/// Elements per chunk: large enough to amortise scheduling, small enough to keep buffers in cache.
pub const CHUNK: usize = 512;

/// Computes `compute(i)` for `i in 0..n` and passes each result to `consume` in increasing `i`.
///
/// # Errors
/// The first error returned by `consume`; later results are not consumed.
pub fn ordered_map<T, E, F, C>(n: usize, par: Parallelism, compute: F, mut consume: C) -> Result<(), E>
where
    T: Send,
    F: Fn(usize) -> T + Sync,
    C: FnMut(usize, T) -> Result<(), E> + Send,
    E: Send,
{
    let run = |range: std::ops::Range<usize>| -> Vec<T> {
        match par {
            Parallelism::Sequential => range.map(&compute).collect(),
            Parallelism::Rayon => range.into_par_iter().with_min_len(8).map(&compute).collect(),
        }
    };
    let chunks: Vec<std::ops::Range<usize>> = (0..n.div_ceil(CHUNK)).map(|c| c * CHUNK..((c + 1) * CHUNK).min(n)).collect();
    let Some(first) = chunks.first() else { return Ok(()) };
    let mut current = run(first.clone());
    for (c, range) in chunks.iter().enumerate() {
        let next_range = chunks.get(c + 1).cloned();
        let start = range.start;
        let mut consume_current = |items: Vec<T>| -> Result<(), E> {
            for (offset, item) in items.into_iter().enumerate() {
                consume(start + offset, item)?;
            }
            Ok(())
        };
        match (par, next_range) {
            (Parallelism::Rayon, Some(next)) => {
                let (next_items, result) = rayon::join(|| run(next), || consume_current(std::mem::take(&mut current)));
                result?;
                current = next_items;
            }
            (_, next) => {
                consume_current(std::mem::take(&mut current))?;
                if let Some(next) = next {
                    current = run(next);
                }
            }
        }
    }
    Ok(())
}

//! Deterministic parallel evaluation: element results are computed in parallel, in fixed chunks, and
//! consumed in element order.
//!
//! Consuming in a fixed order makes every sum (energy, gradient entries, Hessian values) bit-identical
//! for any number of threads, without locks or unsafe shared writes: only the element kernels run in
//! parallel, and while one chunk is being scattered the next one is already being computed. Results are
//! written in place into two reusable chunk buffers, so an evaluation allocates nothing.

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
pub const CHUNK: usize = 256;

/// Two reusable chunk buffers for [`ordered_map`].
#[derive(Debug, Default)]
pub struct ChunkBuffers<T> {
    front: Vec<T>,
    back: Vec<T>,
}

impl<T> ChunkBuffers<T> {
    /// Empty buffers (they grow to [`CHUNK`] entries on first use).
    pub fn new() -> Self {
        Self {
            front: Vec::new(),
            back: Vec::new(),
        }
    }
}

fn fill<T: Send, F: Fn(usize, &mut T) + Sync>(buf: &mut [T], start: usize, par: Parallelism, compute: &F) {
    match par {
        Parallelism::Sequential => buf.iter_mut().enumerate().for_each(|(i, slot)| compute(start + i, slot)),
        Parallelism::Rayon => buf
            .par_iter_mut()
            .with_min_len(4)
            .enumerate()
            .for_each(|(i, slot)| compute(start + i, slot)),
    }
}

/// Computes `compute(i, &mut slot)` for `i in 0..n` and passes each result to `consume(i, &slot)` in
/// increasing `i`. `init` creates a buffer slot.
///
/// # Errors
/// The first error returned by `consume`; later results are not consumed.
pub fn ordered_map<T, E, I, F, C>(
    n: usize,
    par: Parallelism,
    buffers: &mut ChunkBuffers<T>,
    init: I,
    compute: F,
    mut consume: C,
) -> Result<(), E>
where
    T: Send + Sync,
    I: Fn() -> T,
    F: Fn(usize, &mut T) + Sync,
    C: FnMut(usize, &T) -> Result<(), E> + Send,
    E: Send,
{
    let len = n.min(CHUNK);
    for buf in [&mut buffers.front, &mut buffers.back] {
        if buf.len() < len {
            buf.resize_with(len, &init);
        }
    }
    if n == 0 {
        return Ok(());
    }
    // Each chunk joins two tasks. From a thread outside the pool every join would hand its work to the
    // pool and sleep until it is done, a round trip through the kernel per chunk; so the whole loop runs
    // on a pool thread, where joins are cheap.
    if par == Parallelism::Rayon && rayon::current_thread_index().is_none() {
        rayon::scope(|_| run_chunks(n, par, buffers, &compute, &mut consume))
    } else {
        run_chunks(n, par, buffers, &compute, &mut consume)
    }
}

/// The chunk loop of [`ordered_map`], with buffers of at least `min(n, CHUNK)` slots.
fn run_chunks<T, E, F, C>(
    n: usize,
    par: Parallelism,
    buffers: &mut ChunkBuffers<T>,
    compute: &F,
    consume: &mut C,
) -> Result<(), E>
where
    T: Send + Sync,
    F: Fn(usize, &mut T) + Sync,
    C: FnMut(usize, &T) -> Result<(), E> + Send,
    E: Send,
{
    let n_chunks = n.div_ceil(CHUNK);
    let range = |c: usize| c * CHUNK..((c + 1) * CHUNK).min(n);
    let ChunkBuffers { front, back } = buffers;
    let (mut current, mut next) = (front, back);
    let r0 = range(0);
    fill(&mut current[..r0.len()], r0.start, par, compute);
    for c in 0..n_chunks {
        let r = range(c);
        let mut consume_current = |items: &[T]| -> Result<(), E> {
            for (offset, item) in items.iter().enumerate() {
                consume(r.start + offset, item)?;
            }
            Ok(())
        };
        if c + 1 < n_chunks {
            let rn = range(c + 1);
            let next_slice = &mut next[..rn.len()];
            let current_slice = &current[..r.len()];
            let result = match par {
                Parallelism::Rayon => {
                    rayon::join(
                        || fill(next_slice, rn.start, par, compute),
                        || consume_current(current_slice),
                    )
                    .1
                }
                Parallelism::Sequential => {
                    let result = consume_current(current_slice);
                    fill(next_slice, rn.start, par, compute);
                    result
                }
            };
            result?;
            std::mem::swap(&mut current, &mut next);
        } else {
            consume_current(&current[..r.len()])?;
        }
    }
    Ok(())
}

/// The lowest index `i < n` whose `ratio(i)` is not positive (NaN included), with that ratio: the
/// first inverted element of a state (an area or volume ratio), the same for any number of threads.
pub fn first_non_positive(n: usize, par: Parallelism, ratio: impl Fn(usize) -> f64 + Sync) -> Option<(usize, f64)> {
    let inverted = |i: usize| {
        let r = ratio(i);
        (r.is_nan() || r <= 0.0).then_some((i, r))
    };
    match par {
        Parallelism::Sequential => (0..n).find_map(inverted),
        Parallelism::Rayon => (0..n).into_par_iter().with_min_len(64).find_map_first(inverted),
    }
}

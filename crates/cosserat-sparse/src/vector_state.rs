//! Leaving the vector registers clean after faer's dense kernels.
//!
//! faer's dense kernels use the widest vector instructions of the machine (AVX-512 here), and some of
//! them return with the upper parts of the vector registers still marked as in use. Code compiled
//! for the baseline x86-64 target, such as the element kernels, uses the older SSE encodings; on a
//! thread in that state every such instruction pays for the mixed register state, which can make an
//! element assembly after a factorisation more than twice as slow (the `assembly_time` example with
//! `FACTORISE=1` shows it; docs/performance.md has the figures). Only the pool's workers matter, as
//! they run both the factor's kernels and the element kernels.
//!
//! So every thread that ran faer's kernels executes `vzeroupper` when they return: the two domains'
//! workers at the end of their factorisations, and the caller at the end of every factorisation and
//! solve ([`clear_this_thread`]); when faer itself runs in parallel, every worker of the pool
//! ([`clear_all_threads`]).

/// Marks the upper halves of the vector registers unused on the calling thread (on x86-64 with AVX;
/// elsewhere there is nothing to do).
pub(crate) fn clear_this_thread() {
    #[cfg(target_arch = "x86_64")]
    zero_upper();
}

/// [`clear_this_thread`] on every rayon worker and on the caller, after faer ran its kernels on the
/// pool (a broadcast wakes every worker, some tens of microseconds, so only then).
pub(crate) fn clear_all_threads() {
    rayon::broadcast(|_| clear_this_thread());
    clear_this_thread();
}

/// `vzeroupper` on this thread, if the CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
fn zero_upper() {
    #[target_feature(enable = "avx")]
    fn zero_upper_avx() {
        std::arch::x86_64::_mm256_zeroupper();
    }
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX, the only requirement of `zero_upper_avx`.
        unsafe { zero_upper_avx() }
    }
}

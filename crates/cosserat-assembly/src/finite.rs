//! Finiteness checks of assembled numbers, written so that the compiler vectorises them.
//!
//! Every element Hessian and every assembled Hessian is checked before it is used: a NaN must stop a
//! step with a diagnostic, never reach a factorisation or an output file. A search that stops at the
//! first non-finite entry is a scalar loop with a branch per entry; it cost a third of the time of
//! adding element Hessians into the global matrix. The checks here read every entry without an early
//! exit (a mask of `|x| < ∞` comparisons), and only when that fails is the position searched for.

/// Whether every value is finite (neither NaN nor ±∞).
#[inline]
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, x| ok & (x.abs() < f64::INFINITY))
}

/// The index of the first non-finite value, if any.
#[inline]
pub fn first_non_finite(values: &[f64]) -> Option<usize> {
    if all_finite(values) {
        None
    } else {
        values.iter().position(|v| !v.is_finite())
    }
}

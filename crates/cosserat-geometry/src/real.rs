//! The scalar type bound of all numerical kernels.

/// A real scalar: `f64` or a `num-dual` dual number over `f64`.
///
/// The bound gives nalgebra's matrix algebra (`RealField`) together with num-dual's operations with
/// `f64` constants (`x * 0.5`), so kernels are written once and differentiated by passing dual numbers.
///
/// Call math as methods (`x.sqrt()`): the path form `T::sqrt(x)` is ambiguous between the two traits.
/// Do not glob-import `num_dual::*`, which exports an unrelated item named `Real`.
pub trait Real: nalgebra::RealField + num_dual::DualNumCopy<Primitive = f64> {}

impl<T> Real for T where T: nalgebra::RealField + num_dual::DualNumCopy<Primitive = f64> {}

/// Converts an `f64` constant into the scalar type.
#[inline(always)]
pub fn cst<T: Real>(x: f64) -> T {
    T::from(x)
}

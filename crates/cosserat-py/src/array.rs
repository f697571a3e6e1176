//! NumPy arrays of the simulation's state: read-only views of its memory where the layout allows (a
//! `Vec` of nalgebra vectors or quaternions is a contiguous `n × k` block of `f64`), fresh arrays
//! otherwise.

use nalgebra::{Quaternion, Vector3};
use numpy::ndarray::{Array2, Array3, ArrayView2};
use numpy::{IntoPyArray, PyArray2, PyArray3};
use pyo3::prelude::*;

/// Types that are `K` contiguous `f64` and nothing else.
///
/// # Safety
/// Implementors must be `#[repr(C)]` (or transparent) over exactly `[f64; K]`.
pub(crate) unsafe trait FlatF64<const K: usize> {}

// nalgebra's `Vector3<f64>` is `ArrayStorage<f64, 3, 1>` = `[[f64; 3]; 1]`, `#[repr(C)]`; a
// `Quaternion<f64>` is `#[repr(C)]` over a `Vector4<f64>` (i, j, k, w).
unsafe impl FlatF64<3> for Vector3<f64> {}
unsafe impl FlatF64<4> for Quaternion<f64> {}
const _: () = assert!(std::mem::size_of::<Vector3<f64>>() == 3 * 8);
const _: () = assert!(std::mem::size_of::<Quaternion<f64>>() == 4 * 8);

/// A read-only `len × K` NumPy view of `items`, kept alive by `owner` (the Python object that owns the
/// memory).
///
/// The view stays valid as long as the buffer of `items` is neither freed nor moved: `owner` keeps the
/// simulation, and the simulation writes its state in place (`IncrementalPotential::commit`) and never
/// reallocates it. Its values change with every step (it is a view, not a snapshot).
pub(crate) fn view<'py, T: FlatF64<K>, const K: usize>(
    items: &[T],
    owner: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    // SAFETY: `T` is `K` contiguous f64 (FlatF64), so `items` is `K * len` initialised f64 with the
    // alignment of f64, borrowed for the duration of this call.
    let flat: &[f64] = unsafe { std::slice::from_raw_parts(items.as_ptr().cast::<f64>(), items.len() * K) };
    let shaped = ArrayView2::from_shape((items.len(), K), flat).expect("len × K elements");
    // SAFETY: the array borrows `flat` for as long as `owner` lives (numpy keeps `owner` as the array's
    // base); `owner` owns the simulation, whose state buffers are never freed or reallocated before it
    // is dropped (see above). The array is made read-only, so Python cannot write to Rust's memory.
    let array = unsafe { PyArray2::borrow_from_array(&shaped, owner.clone()) };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array)
}

/// A fresh `len × 3` array.
pub(crate) fn vectors<'py>(
    py: Python<'py>,
    items: impl ExactSizeIterator<Item = [f64; 3]>,
) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<[f64; 3]> = items.collect();
    Array2::from(rows).into_pyarray(py)
}

/// The three directors of rotations `q`: `out[k, i]` is director `k + 1` (column `k` of the rotation)
/// of node `i`.
pub(crate) fn directors<'py>(py: Python<'py>, q: &[Quaternion<f64>]) -> Bound<'py, PyArray3<f64>> {
    let mut out = Array3::<f64>::zeros((3, q.len(), 3));
    for (i, q) in q.iter().enumerate() {
        let r = cosserat::geometry::rotation::rotation_matrix(&q.normalize());
        for k in 0..3 {
            for a in 0..3 {
                out[[k, i, a]] = r[(a, k)];
            }
        }
    }
    out.into_pyarray(py)
}

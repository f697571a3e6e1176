//! Output frames as NumPy arrays: what `run` writes into a `.vtu` file, and the reader of such files.

use cosserat::io::{DataArray, OutputError, VtuFrame};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A triangle surface with point and cell data, as written to one `.vtu` file of a run.
///
/// The arrays were moved from the frame into NumPy without copying: `points` (n × 3), `triangles`
/// (m × 3, int64), and in `point_data` and `cell_data` one (n × k) array per name.
#[pyclass(name = "Frame", module = "cosserat", frozen)]
pub struct PyFrame {
    /// The time (or load factor) of the frame.
    #[pyo3(get)]
    time: f64,
    #[pyo3(get)]
    points: Py<PyArray2<f64>>,
    #[pyo3(get)]
    triangles: Py<PyArray2<i64>>,
    #[pyo3(get)]
    point_data: Py<PyDict>,
    #[pyo3(get)]
    cell_data: Py<PyDict>,
}

impl PyFrame {
    /// Moves a frame's arrays into NumPy.
    pub(crate) fn new(py: Python<'_>, frame: VtuFrame) -> PyResult<Self> {
        let triangles: Vec<[i64; 3]> = frame.triangles.iter().map(|t| t.map(|i| i as i64)).collect();
        Ok(Self {
            time: frame.time,
            points: Array2::from(frame.points).into_pyarray(py).unbind(),
            triangles: Array2::from(triangles).into_pyarray(py).unbind(),
            point_data: data_dict(py, frame.point_data)?,
            cell_data: data_dict(py, frame.cell_data)?,
        })
    }
}

fn data_dict(py: Python<'_>, arrays: Vec<DataArray>) -> PyResult<Py<PyDict>> {
    let dict = PyDict::new(py);
    for array in arrays {
        let n = array.n_tuples();
        let values = Array2::from_shape_vec((n, array.n_components), array.values)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("array `{}`: {e}", array.name)))?;
        dict.set_item(array.name, values.into_pyarray(py))?;
    }
    Ok(dict.unbind())
}

#[pymethods]
impl PyFrame {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Frame(time={}, points={}, triangles={})",
            self.time,
            self.points.bind(py).shape()[0],
            self.triangles.bind(py).shape()[0]
        )
    }
}

/// Reads a `.vtu` file written by a run (or by the `cosserat` binary) into a [`PyFrame`].
///
/// Raises `OSError` or `ValueError` for files that cannot be read or are not such frames.
#[pyfunction]
pub fn read_vtu(py: Python<'_>, path: PathBuf) -> PyResult<PyFrame> {
    let frame = py.detach(|| cosserat::io::read_vtu(&path)).map_err(|e| read_error(&path, &e))?;
    PyFrame::new(py, frame)
}

/// A file that cannot be read is the `OSError` of its cause (`FileNotFoundError`, `PermissionError`,
/// …), whose message names the path; one that is no frame a `ValueError` naming it.
fn read_error(path: &std::path::Path, e: &OutputError) -> PyErr {
    match e {
        OutputError::Io { source, .. } => std::io::Error::new(source.kind(), e.to_string()).into(),
        _ => pyo3::exceptions::PyValueError::new_err(format!("{}: {e}", path.display())),
    }
}

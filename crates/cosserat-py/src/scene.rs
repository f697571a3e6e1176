//! Scenes from Python: a TOML file or a dict of the same structure, with `--set`-style overrides.

use crate::error::scene_error;
use cosserat::scene::SceneSpec;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::Path;

/// The overrides as `key=value` texts: a dict `{"mesh.nx": 8}` (values written as TOML, strings
/// quoted), or a list of `"key=value"` strings as on the command line.
pub(crate) fn override_texts(overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(overrides) = overrides else {
        return Ok(Vec::new());
    };
    if let Ok(dict) = overrides.cast::<PyDict>() {
        return dict
            .iter()
            .map(|(k, v)| {
                let key = override_key(&k)?;
                Ok(format!("{key}={}", to_toml(&v)?))
            })
            .collect();
    }
    // A string is iterable too, but its characters are no overrides.
    if overrides.is_instance_of::<PyString>() || overrides.is_instance_of::<PyBytes>() {
        return Err(overrides_type_error(overrides));
    }
    let items = overrides.try_iter().map_err(|_| overrides_type_error(overrides))?;
    items.map(|item| override_item(&item?)).collect()
}

fn overrides_type_error(overrides: &Bound<'_, PyAny>) -> PyErr {
    PyTypeError::new_err(format!(
        "overrides must be a dict such as {{\"mesh.nx\": 8}} or a list of \"key=value\" strings (got {} {})",
        type_name(overrides),
        short_repr(overrides)
    ))
}

fn override_key(key: &Bound<'_, PyAny>) -> PyResult<String> {
    key.extract().map_err(|_| {
        PyTypeError::new_err(format!(
            "overrides: the keys of the dict must be strings such as \"mesh.nx\" (got {} {})",
            type_name(key),
            short_repr(key)
        ))
    })
}

fn override_item(item: &Bound<'_, PyAny>) -> PyResult<String> {
    item.extract().map_err(|_| {
        PyTypeError::new_err(format!(
            "overrides: every item of the list must be a \"key=value\" string (got {} {})",
            type_name(item),
            short_repr(item)
        ))
    })
}

/// The name of a value's type, for messages.
fn type_name(value: &Bound<'_, PyAny>) -> String {
    value.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

/// `repr(value)`, cut to a length that keeps a message readable.
fn short_repr(value: &Bound<'_, PyAny>) -> String {
    let text = value.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    match text.char_indices().nth(60) {
        Some((i, _)) => format!("{}...", &text[..i]),
        None => text,
    }
}

/// Reads and checks a scene file.
pub(crate) fn from_file(py: Python<'_>, path: &Path, overrides: &[String]) -> PyResult<SceneSpec> {
    cosserat::scene::load_scene(path, overrides).map_err(|e| scene_error(py, &e, false))
}

/// Checks a scene given as a dict; relative paths in it (meshes) are relative to `base_dir`.
pub(crate) fn from_dict(
    py: Python<'_>,
    scene: &Bound<'_, PyDict>,
    base_dir: &Path,
    overrides: &[String],
) -> PyResult<SceneSpec> {
    let toml::Value::Table(table) = to_toml(scene.as_any())? else {
        return Err(PyTypeError::new_err("a scene dict must be a table"));
    };
    let text = toml::to_string(&table)
        .map_err(|e| PyTypeError::new_err(format!("the scene dict cannot be written as TOML: {e}")))?;
    SceneSpec::from_str(&text, "<dict>", base_dir, overrides).map_err(|e| scene_error(py, &e, true))
}

/// A Python value as a TOML value: dicts are tables, lists and tuples arrays (NumPy arrays through
/// `tolist()`), and bool, int, float and str the scalars.
fn to_toml(value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let key: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("scene keys must be strings (got {k})")))?;
            table.insert(key, to_toml(&v)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value.try_iter()?.map(|item| to_toml(&item?)).collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if value.hasattr("tolist")? {
        // NumPy arrays and scalars.
        return to_toml(&value.call_method0("tolist")?);
    }
    Err(PyTypeError::new_err(format!(
        "a scene value must be a dict, list, bool, int, float or str (got {})",
        value.get_type().name()?
    )))
}

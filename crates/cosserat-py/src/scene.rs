//! Scenes from Python: a TOML file or a dict of the same structure, with `--set`-style overrides.

use crate::error::{scene_error, scene_value_error, short_repr, type_error};
use cosserat::geometry::Num;
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
                Ok(format!("{key}={}", override_value_text(&to_toml(&v, &key)?)))
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

/// The TOML text of an override's value. TOML writes a float in plain decimals, `1e-300` in three
/// hundred digits, which a message quoting the override would show; such floats keep an exponent.
fn override_value_text(value: &toml::Value) -> String {
    match value {
        toml::Value::Float(x) => {
            let text = Num(*x).to_string();
            if x.is_finite() && text.contains('e') {
                text
            } else {
                value.to_string()
            }
        }
        toml::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(override_value_text).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

fn overrides_type_error(overrides: &Bound<'_, PyAny>) -> PyErr {
    type_error(
        "overrides must be a dict such as {\"mesh.nx\": 8} or a list of \"key=value\" strings",
        overrides,
    )
}

fn override_key(key: &Bound<'_, PyAny>) -> PyResult<String> {
    key.extract().map_err(|_| {
        type_error(
            "overrides: the keys of the dict must be strings such as \"mesh.nx\"",
            key,
        )
    })
}

fn override_item(item: &Bound<'_, PyAny>) -> PyResult<String> {
    item.extract()
        .map_err(|_| type_error("overrides: every item of the list must be a \"key=value\" string", item))
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
    let toml::Value::Table(table) = to_toml(scene.as_any(), "")? else {
        return Err(PyTypeError::new_err("a scene dict must be a table"));
    };
    let text = toml::to_string(&table)
        .map_err(|e| PyTypeError::new_err(format!("the scene dict cannot be written as TOML: {e}")))?;
    SceneSpec::from_str(&text, "<dict>", base_dir, overrides).map_err(|e| scene_error(py, &e, true))
}

/// How deep a scene value may nest: far deeper than any scene's tables and arrays, and shallow enough
/// that a dict or list that contains itself ends here rather than overflowing the stack.
const MAX_DEPTH: usize = 32;

/// Where a value sits in the scene: its dotted path (for messages) and its nesting depth.
#[derive(Clone, Copy)]
struct Field<'a> {
    path: &'a str,
    depth: usize,
}

impl Field<'_> {
    fn child(&self, segment: &str) -> String {
        if self.path.is_empty() {
            segment.to_owned()
        } else {
            format!("{}.{segment}", self.path)
        }
    }

    /// The path for messages, `<scene>` at the top.
    fn name(&self) -> &str {
        if self.path.is_empty() { "<scene>" } else { self.path }
    }
}

/// A Python value as a TOML value: dicts are tables, lists and tuples arrays (NumPy arrays through
/// `tolist()`), and bool, int, float and str the scalars. `path` names the value in errors.
fn to_toml(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    to_toml_at(value, Field { path, depth: 0 })
}

fn to_toml_at(value: &Bound<'_, PyAny>, field: Field<'_>) -> PyResult<toml::Value> {
    if field.depth > MAX_DEPTH {
        return Err(scene_value_error(
            value.py(),
            field.name(),
            format!("nested more than {MAX_DEPTH} levels deep (does a dict or list contain itself?)"),
        ));
    }
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return integer(value, field);
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    let deeper = |path: &str, item: &Bound<'_, PyAny>| {
        to_toml_at(
            item,
            Field {
                path,
                depth: field.depth + 1,
            },
        )
    };
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let key: String = k
                .extract()
                .map_err(|_| type_error(&format!("`{}`: scene keys must be strings", field.name()), &k))?;
            let value = deeper(&field.child(&key), &v)?;
            table.insert(key, value);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(i, item)| deeper(&field.child(&i.to_string()), &item?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if value.hasattr("tolist")? {
        // NumPy arrays and scalars.
        return deeper(field.path, &value.call_method0("tolist")?);
    }
    Err(type_error(
        &format!(
            "`{}`: a scene value must be a dict, list, bool, int, float or str",
            field.name()
        ),
        value,
    ))
}

/// A Python int as a TOML integer, which has 64 bits.
fn integer(value: &Bound<'_, PyAny>, field: Field<'_>) -> PyResult<toml::Value> {
    match value.extract::<i64>() {
        Ok(i) => Ok(toml::Value::Integer(i)),
        Err(_) => Err(scene_value_error(
            value.py(),
            field.name(),
            format!("{} does not fit in a 64-bit integer", short_repr(value)),
        )),
    }
}

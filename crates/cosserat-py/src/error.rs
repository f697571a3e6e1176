//! The Python exceptions: scene errors carry the file, the line, the field and the reason as
//! attributes.

use cosserat::scene::error::Location;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _cosserat,
    SceneError,
    PyValueError,
    "A scene that cannot be loaded. Attributes: `file` (the scene file, or `None` for a dict or an \
     override), `line` (1-based, or `None`), `field` (dotted path such as `time.dt`, or `None`), \
     `override` (the `key=value` override at fault, or `None`) and `reason`."
);
create_exception!(
    _cosserat,
    SimulationError,
    PyRuntimeError,
    "A scene that loaded but cannot be simulated (mesh, material, memory), a script target that cannot \
     be set, or an output that cannot be written."
);
create_exception!(
    _cosserat,
    StepFailed,
    PyRuntimeError,
    "A step failed after every allowed time-step reduction; the state is that of the last completed \
     step."
);

/// The Python exception of a scene error; `from_dict` says that the text was generated from a dict,
/// whose line numbers mean nothing to the user.
pub(crate) fn scene_error(py: Python<'_>, e: &cosserat::scene::SceneError, from_dict: bool) -> PyErr {
    use cosserat::scene::SceneError as E;
    let err = SceneError::new_err(message(e, from_dict));
    let (mut file, mut line, mut over) = (None, None, None);
    match e.location() {
        Some(Location::File { file: f, line: l }) => {
            file = (!from_dict).then(|| f.clone());
            line = if from_dict { None } else { *l };
        }
        Some(Location::Override { text }) => over = Some(text.clone()),
        None => {}
    }
    let reason = match e {
        E::ReadScene { path, source } => {
            file = Some(path.display().to_string());
            source.to_string()
        }
        E::Syntax { message, .. } => format!("invalid TOML: {message}"),
        E::Schema { message, .. } => message.clone(),
        E::Invalid { reason, .. } => reason.clone(),
        E::Expression { source, .. } => source.to_string(),
        E::Obj { source, .. } => source.to_string(),
        E::Mesh { source, .. } => source.to_string(),
        E::Region { source, .. } => source.to_string(),
        E::Override { text, reason } => {
            over = Some(text.clone());
            reason.clone()
        }
        other => other.to_string(),
    };
    let field = e.field().filter(|f| !f.is_empty()).map(str::to_owned);
    with_attributes(py, err, file, line, field, over, reason)
}

/// `err` with the attributes of a `SceneError` (or the error of setting them).
fn with_attributes(
    py: Python<'_>,
    err: PyErr,
    file: Option<String>,
    line: Option<usize>,
    field: Option<String>,
    over: Option<String>,
    reason: String,
) -> PyErr {
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("file", file)?;
        value.setattr("line", line)?;
        value.setattr("field", field)?;
        value.setattr("override", over)?;
        value.setattr("reason", reason)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The message of a scene error. A dict's errors carry the location of the TOML text made from it, a
/// line the user never saw: they name the dict instead.
fn message(e: &cosserat::scene::SceneError, from_dict: bool) -> String {
    let text = e.to_string();
    match e.location() {
        Some(location @ Location::File { .. }) if from_dict => {
            let prefix = format!("{location}: ");
            match text.strip_prefix(&prefix) {
                Some(rest) => format!("scene dict: {rest}"),
                None => text,
            }
        }
        _ => text,
    }
}

/// A `SceneError` for a value given from Python that cannot become part of a scene: `field` is its
/// dotted path.
pub(crate) fn scene_value_error(py: Python<'_>, field: &str, reason: String) -> PyErr {
    let err = SceneError::new_err(format!("{field}: {reason}"));
    with_attributes(py, err, None, None, Some(field.to_owned()), None, reason)
}

/// The Python exception of a facade error: scene errors keep their attributes.
pub(crate) fn simulation_error(py: Python<'_>, e: &cosserat::SimulationError) -> PyErr {
    match e {
        cosserat::SimulationError::Scene(scene) => scene_error(py, scene, false),
        other => SimulationError::new_err(other.to_string()),
    }
}

/// A `TypeError` saying `what`, with the type and value that were given instead.
pub(crate) fn type_error(what: &str, value: &Bound<'_, PyAny>) -> PyErr {
    PyTypeError::new_err(format!("{what} (got {} {})", type_name(value), short_repr(value)))
}

/// The name of a value's type, for messages.
fn type_name(value: &Bound<'_, PyAny>) -> String {
    value.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

/// `repr(value)`, cut to a length that keeps a message readable.
pub(crate) fn short_repr(value: &Bound<'_, PyAny>) -> String {
    let text = value.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    match text.char_indices().nth(60) {
        Some((i, _)) => format!("{}...", &text[..i]),
        None => text,
    }
}

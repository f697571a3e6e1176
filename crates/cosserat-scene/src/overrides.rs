//! Command-line overrides: `--set key=value` applied to the parsed TOML document before it is checked
//! against the schema.
//!
//! The key is a dotted path; numeric segments index arrays of tables (`boundary.0.position.stiffness`,
//! `shell.2.mesh.path`). The value is read as a TOML value (`0.01`, `80`, `true`, `[0, 0, -9.81]`,
//! `"text"`), and taken as a plain string when it is not valid TOML (`tri3`, `../models/x.obj`).
//! Missing tables on the way are created, so `output.frames=false` works without an `\[output\]` table;
//! array entries are never created. An empty value (`solver.tolerance=`) removes the key, so that its
//! default applies (a key that is not there is left alone). A key the schema does not know is rejected
//! when the document is deserialised, and the message then names the override rather than a line of
//! the file: every value an override inserts carries a span past the end of the file text that
//! identifies the override.

use crate::error::SceneError;
use std::ops::Range;
use toml::Spanned;
use toml::de::{DeString, DeTable, DeValue};

/// A parsed `key=value` override.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Override {
    /// The override as given.
    pub text: String,
    /// The key path.
    pub path: Vec<String>,
    /// The value text.
    pub value: String,
}

impl Override {
    /// Parses `key=value`.
    ///
    /// # Errors
    /// [`SceneError::Override`] for a missing `=`, an empty key or an empty path segment.
    pub fn parse(text: &str) -> Result<Self, SceneError> {
        let error = |reason: &str| SceneError::Override {
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let (key, value) = text.split_once('=').ok_or_else(|| error("expected `key=value`"))?;
        let key = key.trim();
        if key.is_empty() {
            return Err(error("the key is empty"));
        }
        let path: Vec<String> = key.split('.').map(|s| s.trim().to_string()).collect();
        if path.iter().any(String::is_empty) {
            return Err(error(
                "the key has an empty segment (two dots in a row, or a leading or trailing dot)",
            ));
        }
        Ok(Self {
            text: text.to_string(),
            path,
            value: value.trim().to_string(),
        })
    }

    /// The dotted key.
    pub fn key(&self) -> String {
        self.path.join(".")
    }
}

/// Applies `ov` to `table`; everything it inserts gets the span `span` (past the end of the file).
pub(crate) fn apply<'i>(table: &mut DeTable<'i>, ov: &'i Override, span: Range<usize>) -> Result<(), SceneError> {
    let target = Target { ov, span };
    if ov.value.is_empty() {
        return target.remove_from_table(table, 0);
    }
    let span = target.span.clone();
    let value = match DeValue::parse(&ov.value) {
        Ok(v) => respan(v, &span),
        Err(_) => Spanned::new(span.clone(), DeValue::String(DeString::Borrowed(ov.value.as_str()))),
    };
    target.insert_in_table(table, 0, value)
}

/// The override being applied and the span its values get.
struct Target<'i> {
    ov: &'i Override,
    span: Range<usize>,
}

impl<'i> Target<'i> {
    fn error(&self, reason: String) -> SceneError {
        SceneError::Override {
            text: self.ov.text.clone(),
            reason,
        }
    }

    fn insert_in_table(
        &self,
        table: &mut DeTable<'i>,
        depth: usize,
        value: Spanned<DeValue<'i>>,
    ) -> Result<(), SceneError> {
        let segment = self.ov.path[depth].as_str();
        if depth + 1 == self.ov.path.len() {
            // Remove first: inserting over an existing key would keep the old key and its span.
            table.remove(segment);
            table.insert(Spanned::new(self.span.clone(), DeString::Borrowed(segment)), value);
            return Ok(());
        }
        if !table.contains_key(segment) {
            table.insert(
                Spanned::new(self.span.clone(), DeString::Borrowed(segment)),
                Spanned::new(self.span.clone(), DeValue::Table(DeTable::new())),
            );
        }
        let next = table.get_mut(segment).expect("present or inserted above").get_mut();
        self.insert_in_value(next, depth + 1, value)
    }

    fn insert_in_value(
        &self,
        current: &mut DeValue<'i>,
        depth: usize,
        value: Spanned<DeValue<'i>>,
    ) -> Result<(), SceneError> {
        let here = self.ov.path[..depth].join(".");
        match current {
            DeValue::Table(t) => self.insert_in_table(t, depth, value),
            DeValue::Array(a) => {
                let segment = &self.ov.path[depth];
                let index = parse_index(segment).ok_or_else(|| {
                    self.error(format!(
                        "`{here}` is an array: the next segment must be an index, not `{segment}`"
                    ))
                })?;
                let n = a.len();
                let entries = if n == 1 { "entry" } else { "entries" };
                let slot = a.get_mut(index).ok_or_else(|| {
                    self.error(format!("`{here}` has {n} {entries}, so index {index} does not exist"))
                })?;
                if depth + 1 == self.ov.path.len() {
                    *slot = value;
                    Ok(())
                } else {
                    self.insert_in_value(slot.get_mut(), depth + 1, value)
                }
            }
            other => Err(self.error(format!("`{here}` is a {}, not a table", other.type_str()))),
        }
    }
}

impl Target<'_> {
    /// Removes the override's key below `table` (from segment `depth` on), if it is there.
    fn remove_from_table(&self, table: &mut DeTable<'_>, depth: usize) -> Result<(), SceneError> {
        let segment = self.ov.path[depth].as_str();
        if depth + 1 == self.ov.path.len() {
            table.remove(segment);
            return Ok(());
        }
        let here = self.ov.path[..=depth].join(".");
        match table.get_mut(segment).map(Spanned::get_mut) {
            None => Ok(()),
            Some(DeValue::Table(t)) => self.remove_from_table(t, depth + 1),
            Some(DeValue::Array(a)) => {
                let next = &self.ov.path[depth + 1];
                let index = parse_index(next).ok_or_else(|| {
                    self.error(format!(
                        "`{here}` is an array: the next segment must be an index, not `{next}`"
                    ))
                })?;
                if depth + 2 == self.ov.path.len() {
                    return Err(self.error(format!("an entry of the array `{here}` cannot be removed")));
                }
                match a.get_mut(index).map(Spanned::get_mut) {
                    None => Ok(()),
                    Some(DeValue::Table(t)) => self.remove_from_table(t, depth + 2),
                    Some(other) => Err(self.error(format!("`{here}.{index}` is a {}, not a table", other.type_str()))),
                }
            }
            Some(other) => Err(self.error(format!("`{here}` is a {}, not a table", other.type_str()))),
        }
    }
}

fn parse_index(segment: &str) -> Option<usize> {
    segment.parse().ok()
}

/// The value with every span (its own and nested ones) replaced by `span`.
fn respan<'i>(value: Spanned<DeValue<'i>>, span: &Range<usize>) -> Spanned<DeValue<'i>> {
    let inner = match value.into_inner() {
        DeValue::Array(mut array) => {
            for item in array.iter_mut() {
                let taken = std::mem::replace(item, Spanned::new(0..0, DeValue::Boolean(false)));
                *item = respan(taken, span);
            }
            DeValue::Array(array)
        }
        DeValue::Table(table) => {
            let mut out = DeTable::new();
            for (key, item) in table {
                out.insert(Spanned::new(span.clone(), key.into_inner()), respan(item, span));
            }
            DeValue::Table(out)
        }
        other => other,
    };
    Spanned::new(span.clone(), inner)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn respan_reaches_nested_values() {
        let v = DeValue::parse("[1, { a = 2 }]").unwrap();
        let v = respan(v, &(100..100));
        assert_eq!(v.span(), 100..100);
        let array = v.get_ref().as_array().unwrap();
        assert!(array.iter().all(|item| item.span() == (100..100)));
        let table = array[1].get_ref().as_table().unwrap();
        assert!(table.iter().all(|(k, v)| k.span() == (100..100) && v.span() == (100..100)));
    }
}

//! A hint for a section written as the other kind of table: `[[time]]` where the format has one
//! `[time]` table, or `[boundary]` where it has a list of `[[boundary]]` tables.
//!
//! Serde's own message for these points elsewhere: it reads a struct from an array element by
//! element, so `[[time]]` is reported as a type error of the struct's first field
//! (`time.0: wanted exactly 1 element`). Rather than keep a list of which sections are tables and
//! which are arrays (one that would drift from the schema), the section is rewritten the other way
//! round and the document deserialised again; the hint is given only if the section then fits.

use super::source::path_of_span;
use crate::schema::SceneFile;
use serde::Deserialize;
use std::ops::Range;
use toml::Spanned;
use toml::de::{DeArray, DeTable, DeValue};

/// How a section is rewritten to test a hint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rewrite {
    /// An array of tables replaced by its first table.
    Unwrap,
    /// A table replaced by an array holding it.
    Wrap,
}

/// For a schema error with serde's `message` at the field path `path` of `document`: the section
/// written as the other kind of table, and what it should be (for `[[time]]`: `time` and "is a table
/// (`[time]`), not an array of tables (`[[time]]`)").
pub(super) fn wrong_kind_of_table(
    document: &DeTable<'_>,
    root_span: &Range<usize>,
    path: &str,
    message: &str,
) -> Option<(String, String)> {
    let segments: Vec<&str> = path.split('.').filter(|s| !s.is_empty()).collect();
    // Serde names a table where a list belongs, but not that `[[…]]` is how a list of tables is written.
    // An array's entry has no header of its own: a list expected there is a field of a struct read
    // from the array (the case below).
    let is_entry = segments.last().is_some_and(|s| s.parse::<usize>().is_ok());
    if message == "invalid type: map, expected a sequence"
        && !is_entry
        && rewritten_fits(document, root_span, &segments, Rewrite::Wrap)
    {
        let header = header(&segments);
        return Some((
            path.to_string(),
            format!("is an array of tables (one `[[{header}]]` per entry), not a table (`[{header}]`)"),
        ));
    }
    // An array where one table belongs fails inside one of its entries; the deepest such array is the one.
    (1..segments.len()).rev().find_map(|n| {
        let section = &segments[..n];
        let in_entry = segments[n].parse::<usize>().is_ok();
        (in_entry && rewritten_fits(document, root_span, section, Rewrite::Unwrap)).then(|| {
            let header = header(section);
            (
                section.join("."),
                format!("is a table (`[{header}]`), not an array of tables (`[[{header}]]`)"),
            )
        })
    })
}

/// The header that names a section: its path without array indices (`boundary.0.position` is written
/// `[boundary.position]` after a `[[boundary]]`).
fn header(section: &[&str]) -> String {
    let keys: Vec<&str> = section.iter().copied().filter(|s| s.parse::<usize>().is_err()).collect();
    keys.join(".")
}

/// Whether the section at `section` is of the kind `rewrite` turns into the other, and fits the schema
/// once rewritten: the document then deserialises, or fails where the section was read as a table or a
/// list of tables (a missing or unknown key), or fails elsewhere.
fn rewritten_fits(document: &DeTable<'_>, root_span: &Range<usize>, section: &[&str], rewrite: Rewrite) -> bool {
    let mut document = document.clone();
    let Some(slot) = slot_mut(&mut document, section) else {
        return false;
    };
    let replacement = match (rewrite, slot.get_ref()) {
        (Rewrite::Unwrap, DeValue::Array(a)) if !a.is_empty() && a.iter().all(is_table) => a[0].clone(),
        (Rewrite::Wrap, DeValue::Table(_)) => {
            let mut array = DeArray::new();
            array.push(slot.clone());
            Spanned::new(slot.span(), DeValue::Array(array))
        }
        _ => return false,
    };
    *slot = replacement;
    let deserializer = toml::de::Deserializer::from(Spanned::new(root_span.clone(), document.clone()));
    let Err(e) = SceneFile::deserialize(deserializer) else {
        return true;
    };
    if e.message().starts_with("missing field") || e.message().starts_with("unknown field") {
        return true;
    }
    let at = e.span().map(|s| path_of_span(&document, root_span, &s)).unwrap_or_default();
    let section = section.join(".");
    match rewrite {
        // A list, a number or a name read from the table fails at the table itself.
        Rewrite::Unwrap => at != section,
        // A list of numbers or names fails at the entry that is now a table.
        Rewrite::Wrap => at != section && !at.starts_with(&format!("{section}.")),
    }
}

fn is_table(value: &Spanned<DeValue<'_>>) -> bool {
    matches!(value.get_ref(), DeValue::Table(_))
}

/// The value at a field path (keys and array indices).
fn slot_mut<'a, 'i>(table: &'a mut DeTable<'i>, path: &[&str]) -> Option<&'a mut Spanned<DeValue<'i>>> {
    let (first, rest) = path.split_first()?;
    let mut slot = table.get_mut(*first)?;
    for segment in rest {
        slot = match slot.get_mut() {
            DeValue::Table(t) => t.get_mut(*segment)?,
            DeValue::Array(a) => a.get_mut(segment.parse::<usize>().ok()?)?,
            _ => return None,
        };
    }
    Some(slot)
}

//! The scene text, its parsed document and the overrides applied to it: turns spans and field paths
//! into [`Location`]s (a file line, or the override that set the value).
//!
//! Field paths are dotted (`boundary.0.position.stiffness`). Validation names the path of every value
//! it rejects, and the location comes from the document, so errors keep pointing at the right line
//! (or the right override) however the value got there.

use crate::error::Location;
use crate::overrides::Override;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// The source of one scene.
pub(crate) struct Source<'i> {
    name: String,
    text_len: usize,
    root_span: Range<usize>,
    line_starts: Vec<usize>,
    overrides: &'i [Override],
    document: DeTable<'i>,
}

impl<'i> Source<'i> {
    /// A source for `text` (named `name` in messages), its parsed and overridden document, and the
    /// overrides (override `k` has spans starting at [`Source::override_span`]`(k)`).
    pub(crate) fn new(
        name: &str,
        text: &str,
        root_span: Range<usize>,
        document: DeTable<'i>,
        overrides: &'i [Override],
    ) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        Self {
            name: name.to_string(),
            text_len: text.len(),
            root_span,
            line_starts,
            overrides,
            document,
        }
    }

    /// The (empty) span that marks values inserted by override `k`.
    pub(crate) fn override_span(text_len: usize, k: usize) -> Range<usize> {
        let start = text_len + 1 + k;
        start..start
    }

    /// The location of a byte offset (or of an override's marker span).
    pub(crate) fn location_of_offset(&self, offset: usize) -> Location {
        if offset > self.text_len {
            let k = offset - self.text_len - 1;
            if let Some(ov) = self.overrides.get(k) {
                return Location::Override { text: ov.text.clone() };
            }
        }
        let line = self.line_starts.partition_point(|&start| start <= offset);
        Location::File {
            file: self.name.clone(),
            line: Some(line.max(1)),
        }
    }

    /// The location of a field path: the key (or array element) deepest along the path that exists in
    /// the document. A path that does not exist at all gives the file without a line.
    pub(crate) fn location(&self, path: &str) -> Location {
        let mut best: Option<usize> = None;
        let mut current: Option<&DeValue<'i>> = None;
        let mut table: Option<&DeTable<'i>> = Some(&self.document);
        for segment in path.split('.').filter(|s| !s.is_empty()) {
            if let Some(t) = table.take() {
                match t.get_key_value(segment) {
                    Some((key, value)) => {
                        best = Some(key.span().start);
                        current = Some(value.get_ref());
                    }
                    None => break,
                }
            } else if let Some(DeValue::Array(a)) = current {
                match segment.parse::<usize>().ok().and_then(|i| a.get(i)) {
                    Some(item) => {
                        best = Some(item.span().start);
                        current = Some(item.get_ref());
                    }
                    None => break,
                }
            } else {
                break;
            }
            table = match current {
                Some(DeValue::Table(t)) => Some(t),
                _ => None,
            };
        }
        match best {
            Some(offset) => self.location_of_offset(offset),
            None => Location::File {
                file: self.name.clone(),
                line: None,
            },
        }
    }

    /// The dotted path a deserialisation error's span refers to: empty for the whole document, the
    /// table or array whose value span is exactly `span` (e.g. a table with a missing key), and
    /// otherwise the deepest key or array element containing the span's start.
    pub(crate) fn path_of_span(&self, span: &Range<usize>) -> String {
        path_of_span(&self.document, &self.root_span, span)
    }

    /// The document as deserialised (overrides applied) and the span of its root.
    pub(crate) fn document(&self) -> (&DeTable<'i>, &Range<usize>) {
        (&self.document, &self.root_span)
    }
}

/// [`Source::path_of_span`] in any document with the root span `root_span`.
pub(crate) fn path_of_span(document: &DeTable<'_>, root_span: &Range<usize>, span: &Range<usize>) -> String {
    if span == root_span {
        return String::new();
    }
    search_exact(document, span)
        .or_else(|| search_table(document, span.start))
        .unwrap_or_default()
        .join(".")
}

/// The longest path to a value whose span is exactly `span`.
fn search_exact(table: &DeTable<'_>, span: &Range<usize>) -> Option<Vec<String>> {
    let mut best: Option<Vec<String>> = None;
    let mut consider = |candidate: Vec<String>| {
        if best.as_ref().is_none_or(|b| candidate.len() > b.len()) {
            best = Some(candidate);
        }
    };
    for (key, value) in table {
        let name = key.get_ref().to_string();
        if value.span() == *span {
            consider(vec![name.clone()]);
        }
        match value.get_ref() {
            DeValue::Table(t) => {
                if let Some(mut rest) = search_exact(t, span) {
                    rest.insert(0, name.clone());
                    consider(rest);
                }
            }
            DeValue::Array(a) => {
                for (i, item) in a.iter().enumerate() {
                    let mut below = if item.span() == *span { Some(Vec::new()) } else { None };
                    if let DeValue::Table(t) = item.get_ref()
                        && let Some(rest) = search_exact(t, span)
                    {
                        below = Some(rest);
                    }
                    if let Some(mut rest) = below {
                        rest.insert(0, i.to_string());
                        rest.insert(0, name.clone());
                        consider(rest);
                    }
                }
            }
            _ => {}
        }
    }
    best
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.start <= offset && offset <= span.end
}

/// The longest path below `table` that leads to a key or value containing `offset`. Every entry is
/// searched, because the span of a table defined by several headers need not cover all its parts.
fn search_table(table: &DeTable<'_>, offset: usize) -> Option<Vec<String>> {
    let mut best: Option<Vec<String>> = None;
    for (key, value) in table {
        let below = search_value(value.get_ref(), offset);
        let candidate = match below {
            Some(mut rest) => {
                rest.insert(0, key.get_ref().to_string());
                Some(rest)
            }
            None if contains(&key.span(), offset) || contains(&value.span(), offset) => {
                Some(vec![key.get_ref().to_string()])
            }
            None => None,
        };
        if let Some(c) = candidate
            && best.as_ref().is_none_or(|b| c.len() > b.len())
        {
            best = Some(c);
        }
    }
    best
}

fn search_value(value: &DeValue<'_>, offset: usize) -> Option<Vec<String>> {
    match value {
        DeValue::Table(t) => search_table(t, offset),
        DeValue::Array(a) => {
            let mut best: Option<Vec<String>> = None;
            for (i, item) in a.iter().enumerate() {
                let candidate = match search_value(item.get_ref(), offset) {
                    Some(mut rest) => {
                        rest.insert(0, i.to_string());
                        Some(rest)
                    }
                    None if contains(&item.span(), offset) => Some(vec![i.to_string()]),
                    None => None,
                };
                if let Some(c) = candidate
                    && best.as_ref().is_none_or(|b| c.len() > b.len())
                {
                    best = Some(c);
                }
            }
            best
        }
        _ => None,
    }
}

//! The `.pvd` collection (ParaView Data) listing the frames of a run with their times.
//!
//! ParaView opens the collection as one time-dependent dataset. [`crate::RunWriter`] rewrites it
//! atomically after every frame, so it always lists exactly the frames written so far, in order. File
//! names are stored relative to the directory of the `.pvd` file, with `/` separators, and times with
//! the shortest decimal text that reads back to the same `f64`.

use std::path::Path;

use roxmltree::Document;

use crate::OutputError;
use crate::atomic::write_atomic;
use crate::vtu::{VtuFrame, xml_escape};
use crate::vtu_read::read_vtu;
use cosserat_geometry::Num;

/// One frame of a collection.
#[derive(Debug, Clone, PartialEq)]
pub struct PvdEntry {
    /// Simulation time of the frame.
    pub time: f64,
    /// Path of the frame file relative to the `.pvd` file's directory, e.g. `frame_00003.vtu`.
    pub file: String,
}

/// The complete `.pvd` document listing `entries` in the given order.
///
/// # Errors
/// [`OutputError::NonFiniteValue`] (array `timestep`) for a non-finite time, and
/// [`OutputError::InvalidName`] for an empty file name or one with a control character.
pub fn to_pvd_string(entries: &[PvdEntry]) -> Result<String, OutputError> {
    let mut xml = String::from("<?xml version=\"1.0\"?>\n");
    xml.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n");
    for (idx, entry) in entries.iter().enumerate() {
        if !entry.time.is_finite() {
            return Err(OutputError::NonFiniteValue {
                array: "timestep".to_owned(),
                tuple: idx,
                component: 0,
                value: entry.time,
            });
        }
        if entry.file.is_empty() || entry.file.chars().any(char::is_control) {
            let reason = "a frame file name must be non-empty and free of control characters";
            return Err(OutputError::InvalidName {
                what: "frame file",
                name: entry.file.clone(),
                reason,
            });
        }
        xml.push_str(&format!(
            "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
            Num(entry.time),
            xml_escape(&entry.file)
        ));
    }
    xml.push_str("  </Collection>\n</VTKFile>\n");
    Ok(xml)
}

/// Writes the collection atomically to `path`.
///
/// # Errors
/// As [`to_pvd_string`], plus the errors of [`crate::atomic::write_atomic`].
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> Result<(), OutputError> {
    let xml = to_pvd_string(entries)?;
    write_atomic(path, xml.as_bytes())
}

/// Reads the entries of a `.pvd` file, in file order.
///
/// # Errors
/// [`OutputError::Io`], [`OutputError::Xml`], or [`OutputError::Format`] naming the `DataSet` with a
/// missing or unreadable attribute.
pub fn read_pvd(path: &Path) -> Result<Vec<PvdEntry>, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|source| OutputError::Io {
        operation: "read",
        path: path.to_path_buf(),
        source,
    })?;
    let document = Document::parse(&text).map_err(|source| OutputError::Xml {
        path: path.to_path_buf(),
        source,
    })?;
    let format = |reason: String| OutputError::Format {
        path: path.to_path_buf(),
        reason,
    };
    let root = document.root_element();
    if !root.has_tag_name("VTKFile") || root.attribute("type") != Some("Collection") {
        return Err(format("not a VTKFile of type \"Collection\"".to_owned()));
    }
    let collection = root
        .children()
        .find(|node| node.has_tag_name("Collection"))
        .ok_or_else(|| format("<VTKFile> has no <Collection>".to_owned()))?;
    collection
        .children()
        .filter(|node| node.has_tag_name("DataSet"))
        .enumerate()
        .map(|(idx, node)| {
            let file = node
                .attribute("file")
                .ok_or_else(|| format(format!("DataSet {idx} has no file attribute")))?;
            let time = match node.attribute("timestep") {
                Some(text) => text
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|t| t.is_finite())
                    .ok_or_else(|| format(format!("DataSet {idx} has the invalid timestep \"{text}\"")))?,
                None => return Err(format(format!("DataSet {idx} has no timestep attribute"))),
            };
            Ok(PvdEntry {
                time,
                file: file.to_owned(),
            })
        })
        .collect()
}

/// Reads frame `frame_idx` of the collection at `pvd_path` (its file is resolved relative to the
/// collection's directory).
///
/// # Errors
/// The errors of [`read_pvd`] and [`crate::vtu_read::read_vtu`], and
/// [`OutputError::FrameIndexOutOfRange`] if the collection has no such frame.
pub fn read_pvd_frame(pvd_path: &Path, frame_idx: usize) -> Result<VtuFrame, OutputError> {
    let entries = read_pvd(pvd_path)?;
    let entry = entries.get(frame_idx).ok_or_else(|| OutputError::FrameIndexOutOfRange {
        frame_idx,
        n_frames: entries.len(),
        path: pvd_path.to_path_buf(),
    })?;
    let dir = pvd_path.parent().unwrap_or_else(|| Path::new("."));
    read_vtu(&dir.join(&entry.file))
}

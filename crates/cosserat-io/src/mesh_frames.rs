//! Frame sequences for graphics tools: OBJ and PLY per frame, and one USD stage with time samples.
//!
//! Each takes the same [`VtuFrame`] the VTU writer gets (the deformed mid-surface, quadratic elements
//! already subdivided), so every format shows the same triangles:
//!
//! - **OBJ** (`frame_00000.obj`, ...): `v` lines and `f` lines (1-based), with the time in a comment.
//!   Blender imports a numbered sequence with the "Stop-motion OBJ" add-on or as a mesh sequence
//!   cache; Houdini's File SOP reads `frame_$F4.obj`-style patterns.
//! - **PLY** (`frame_00000.ply`, ...): binary little-endian, `float` positions, the third director
//!   `director3` (when present) as the vertex normal `nx, ny, nz`, and `int` triangle lists.
//! - **USD** (`run.usda`, one file): a `Mesh` prim with the topology once and `points` as time
//!   samples, one per frame at time code = frame index (`timeCodesPerSecond` is the frame rate of the
//!   first two frames), and the three directors as `vector3f` primvars with vertex interpolation,
//!   also time-sampled. The samples stream into hidden part files while the run goes on, and the stage
//!   is assembled when the run ends ([`UsdWriter::finish`], called by [`crate::RunWriter::finish`]
//!   whatever the run's status).

use crate::OutputError;
use crate::atomic::write_atomic;
use crate::vtu::VtuFrame;
use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The frame formats of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameFormats {
    /// VTU frames and the `.pvd` collection (ParaView).
    pub vtu: bool,
    /// One OBJ file per frame.
    pub obj: bool,
    /// One PLY file per frame.
    pub ply: bool,
    /// One USD stage with time samples.
    pub usd: bool,
}

impl Default for FrameFormats {
    /// VTU only.
    fn default() -> Self {
        Self {
            vtu: true,
            obj: false,
            ply: false,
            usd: false,
        }
    }
}

/// The OBJ text of a frame.
pub fn to_obj_string(frame: &VtuFrame) -> String {
    let mut s = String::with_capacity(40 * frame.points.len() + 24 * frame.triangles.len());
    let _ = writeln!(s, "# cosserat frame, t = {}", frame.time);
    for p in &frame.points {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    for t in &frame.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// Writes a frame as OBJ, atomically.
///
/// # Errors
/// The errors of [`VtuFrame::validate`] (nothing is written then) and I/O errors naming the path.
pub fn write_obj(path: &Path, frame: &VtuFrame) -> Result<(), OutputError> {
    frame.validate()?;
    write_atomic(path, to_obj_string(frame).as_bytes())
}

/// The binary little-endian PLY bytes of a frame.
pub fn to_ply_bytes(frame: &VtuFrame) -> Vec<u8> {
    let normals = frame.point_array("director3").filter(|a| a.n_components == 3);
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment cosserat frame, t = {}\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n",
        frame.time,
        frame.points.len()
    );
    if normals.is_some() {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    let _ = write!(
        header,
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        frame.triangles.len()
    );
    let mut b = header.into_bytes();
    for (i, p) in frame.points.iter().enumerate() {
        for c in p {
            b.extend((*c as f32).to_le_bytes());
        }
        if let Some(n) = normals {
            for c in n.tuple(i) {
                b.extend((*c as f32).to_le_bytes());
            }
        }
    }
    for t in &frame.triangles {
        b.push(3);
        for &i in t {
            b.extend((i as i32).to_le_bytes());
        }
    }
    b
}

/// Writes a frame as binary PLY, atomically.
///
/// # Errors
/// The errors of [`VtuFrame::validate`] (nothing is written then) and I/O errors naming the path.
pub fn write_ply(path: &Path, frame: &VtuFrame) -> Result<(), OutputError> {
    frame.validate()?;
    write_atomic(path, &to_ply_bytes(frame))
}

/// The time-sampled attributes of the USD stage: `points` and the director primvars.
const USD_ATTRIBUTES: [(&str, &str, Option<&str>); 4] = [
    ("point3f[] points", "", None),
    ("vector3f[] primvars:director1", "director1", Some("vertex")),
    ("vector3f[] primvars:director2", "director2", Some("vertex")),
    ("vector3f[] primvars:director3", "director3", Some("vertex")),
];

/// Streams frames into one `.usda` stage (module docs).
#[derive(Debug)]
pub struct UsdWriter {
    path: PathBuf,
    /// One part file per attribute of [`USD_ATTRIBUTES`], holding its `time: [...]` samples.
    parts: Vec<(PathBuf, BufWriter<File>)>,
    topology: Option<(usize, Vec<[usize; 3]>)>,
    times: Vec<f64>,
}

fn io_error<'a>(operation: &'static str, path: &'a Path) -> impl FnOnce(std::io::Error) -> OutputError + 'a {
    move |source| OutputError::Io {
        operation,
        path: path.to_path_buf(),
        source,
    }
}

impl UsdWriter {
    /// A stage to be written at `path` (its part files go next to it).
    ///
    /// # Errors
    /// I/O errors naming the part file that cannot be created.
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, OutputError> {
        let path = path.into();
        let mut parts = Vec::new();
        for k in 0..USD_ATTRIBUTES.len() {
            let part = part_path(&path, k);
            let file = OpenOptions::new()
                .create(true)
                .write(true)
                .truncate(true)
                .open(&part)
                .map_err(io_error("create", &part))?;
            parts.push((part, BufWriter::new(file)));
        }
        Ok(Self {
            path,
            parts,
            topology: None,
            times: Vec::new(),
        })
    }

    /// Appends a frame's samples.
    ///
    /// # Errors
    /// [`OutputError::TopologyChanged`] if the frame's points or triangles differ in number or
    /// connectivity from the first frame's (a stage has one topology), and I/O errors.
    pub fn append(&mut self, frame: &VtuFrame) -> Result<(), OutputError> {
        match &self.topology {
            None => self.topology = Some((frame.points.len(), frame.triangles.clone())),
            Some((n, triangles)) => {
                if *n != frame.points.len() || *triangles != frame.triangles {
                    return Err(OutputError::TopologyChanged {
                        path: self.path.clone(),
                        frame_idx: self.times.len(),
                    });
                }
            }
        }
        let code = self.times.len();
        for ((_, array, _), (part, out)) in USD_ATTRIBUTES.iter().zip(&mut self.parts) {
            let values: Vec<[f64; 3]> = if array.is_empty() {
                frame.points.clone()
            } else {
                match frame.point_array(array).filter(|a| a.n_components == 3) {
                    Some(a) => (0..a.n_tuples())
                        .map(|i| [a.tuple(i)[0], a.tuple(i)[1], a.tuple(i)[2]])
                        .collect(),
                    None => continue,
                }
            };
            let mut line = format!("            {code}: [");
            for (i, v) in values.iter().enumerate() {
                let sep = if i == 0 { "" } else { ", " };
                let _ = write!(line, "{sep}({}, {}, {})", v[0] as f32, v[1] as f32, v[2] as f32);
            }
            line += "],\n";
            out.write_all(line.as_bytes()).map_err(io_error("write", part))?;
        }
        self.times.push(frame.time);
        Ok(())
    }

    /// Assembles the stage from the part files (atomically) and removes them; a run without frames
    /// writes no stage. Returns the stage's path if one was written.
    ///
    /// # Errors
    /// I/O errors naming the file.
    pub fn finish(self) -> Result<Option<PathBuf>, OutputError> {
        let mut bodies = Vec::new();
        for (part, out) in self.parts {
            out.into_inner()
                .map_err(|e| io_error("flush", &part)(e.into_error()))?
                .sync_all()
                .map_err(io_error("sync", &part))?;
            bodies.push(std::fs::read_to_string(&part).map_err(io_error("read", &part))?);
            std::fs::remove_file(&part).map_err(io_error("remove", &part))?;
        }
        let Some((_, triangles)) = &self.topology else {
            return Ok(None);
        };
        let rate = match self.times.as_slice() {
            [t0, t1, ..] if t1 > t0 => 1.0 / (t1 - t0),
            _ => 24.0,
        };
        let mut s = format!(
            "#usda 1.0\n(\n    defaultPrim = \"run\"\n    startTimeCode = 0\n    endTimeCode = {}\n    \
             timeCodesPerSecond = {rate}\n    upAxis = \"Z\"\n    metersPerUnit = 1\n)\n\n\
             def Xform \"run\"\n{{\n    def Mesh \"shells\"\n    {{\n        uniform token subdivisionScheme = \"none\"\n",
            self.times.len().saturating_sub(1)
        );
        let counts = vec!["3"; triangles.len()].join(", ");
        let indices: Vec<String> = triangles.iter().flatten().map(|i| i.to_string()).collect();
        let _ = writeln!(s, "        int[] faceVertexCounts = [{counts}]");
        let _ = writeln!(s, "        int[] faceVertexIndices = [{}]", indices.join(", "));
        for ((declaration, _, interpolation), body) in USD_ATTRIBUTES.iter().zip(&bodies) {
            if body.is_empty() {
                continue;
            }
            if let Some(i) = interpolation {
                let _ = write!(
                    s,
                    "        {declaration} (\n            interpolation = \"{i}\"\n        )\n"
                );
            }
            let _ = write!(s, "        {declaration}.timeSamples = {{\n{body}        }}\n");
        }
        s += "    }\n}\n";
        write_atomic(&self.path, s.as_bytes())?;
        Ok(Some(self.path))
    }
}

/// The hidden part file `k` of a stage.
fn part_path(path: &Path, k: usize) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "run.usda".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.part{k}"))
}

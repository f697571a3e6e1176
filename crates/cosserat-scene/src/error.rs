//! Errors of scene loading: [`SceneError`] names the file, the line, the field path and the reason;
//! the leaf errors [`ExprError`], [`ObjError`] and [`RegionError`] say what went wrong inside an
//! expression, an OBJ file or a region.
//!
//! Messages read like compiler diagnostics, e.g.
//! `scenes/x.toml:12: time.dt: must be positive (got -0.01)`, or, for a value set on the command line,
//! `override `time.dt=-1`: time.dt: must be positive (got -1)`.

use cosserat_fem::MeshError;
use std::fmt;
use std::path::PathBuf;
use thiserror::Error;

/// Where a scene value came from: a line of the scene file, or a `--set key=value` override.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// A place in the scene file (or the given source name); `line` is 1-based.
    File {
        /// The file name or source name as given to the loader.
        file: String,
        /// The line, if known.
        line: Option<usize>,
    },
    /// A value set by an override.
    Override {
        /// The override as given (`key=value`).
        text: String,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File { file, line: Some(line) } => write!(f, "{file}:{line}"),
            Location::File { file, line: None } => write!(f, "{file}"),
            Location::Override { text } => write!(f, "override `{text}`"),
        }
    }
}

/// A scene that cannot be loaded. Every variant says where (file and line, or the override) and,
/// after parsing, which field (a dotted path such as `boundary.0.position.stiffness`).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read the scene file: {source}", path.display())]
    ReadScene {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The text is not valid TOML.
    #[error("{location}: invalid TOML: {message}")]
    Syntax {
        /// Where.
        location: Location,
        /// The parser's message.
        message: String,
    },
    /// The TOML does not fit the scene schema: an unknown or misspelled key (the message lists the
    /// expected names), a missing required key, or a value of the wrong type.
    #[error("{location}: {}{message}", field_prefix(.field))]
    Schema {
        /// Where.
        location: Location,
        /// The field path (empty for the top level).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A value is out of range or inconsistent with another.
    #[error("{location}: {}{reason}", field_prefix(.field))]
    Invalid {
        /// Where.
        location: Location,
        /// The field path.
        field: String,
        /// Why it is rejected.
        reason: String,
    },
    /// An expression does not compile or evaluates to a non-finite value.
    #[error("{location}: {field}: {source}")]
    Expression {
        /// Where.
        location: Location,
        /// The field path.
        field: String,
        /// The cause.
        source: Box<ExprError>,
    },
    /// A mesh file could not be read or is not a valid simulation mesh.
    #[error("{location}: {field}: {source}")]
    Obj {
        /// Where the path was given.
        location: Location,
        /// The field path (`mesh.path` or `shell.<k>.mesh.path`).
        field: String,
        /// The cause.
        source: Box<ObjError>,
    },
    /// A Gmsh or PLY file could not be read or is not a valid simulation mesh.
    #[error("{location}: {field}: {source}")]
    MeshFile {
        /// Where the path was given.
        location: Location,
        /// The field path (`mesh.path` or `shell.<k>.mesh.path`).
        field: String,
        /// The cause.
        source: Box<MeshFileError>,
    },
    /// A generated or transformed mesh is invalid (bad generator parameter, degenerate element, …).
    #[error("{location}: {field}: {source}")]
    Mesh {
        /// Where.
        location: Location,
        /// The field path.
        field: String,
        /// The cause.
        source: Box<MeshError>,
    },
    /// A region selects no node, or cannot be evaluated.
    #[error("{location}: {field}: {source}")]
    Region {
        /// Where.
        location: Location,
        /// The field path of the region.
        field: String,
        /// The cause.
        source: Box<RegionError>,
    },
    /// A `--set key=value` override is malformed or does not fit the document.
    #[error("override `{text}`: {reason}")]
    Override {
        /// The override as given.
        text: String,
        /// Why it is rejected.
        reason: String,
    },
}

/// A number as messages show it: plain where that stays short, scientific notation elsewhere (the
/// rule of every message and text output of the project).
pub use cosserat_geometry::Num;

/// `"field: "`, or nothing for the top level.
fn field_prefix(field: &str) -> String {
    if field.is_empty() {
        String::new()
    } else {
        format!("{field}: ")
    }
}

impl SceneError {
    /// The location of the error, if it has one.
    pub fn location(&self) -> Option<&Location> {
        match self {
            SceneError::Syntax { location, .. }
            | SceneError::Schema { location, .. }
            | SceneError::Invalid { location, .. }
            | SceneError::Expression { location, .. }
            | SceneError::Obj { location, .. }
            | SceneError::MeshFile { location, .. }
            | SceneError::Mesh { location, .. }
            | SceneError::Region { location, .. } => Some(location),
            SceneError::ReadScene { .. } | SceneError::Override { .. } => None,
        }
    }

    /// The field path of the error, if it has one.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Schema { field, .. }
            | SceneError::Invalid { field, .. }
            | SceneError::Expression { field, .. }
            | SceneError::Obj { field, .. }
            | SceneError::MeshFile { field, .. }
            | SceneError::Mesh { field, .. }
            | SceneError::Region { field, .. } => Some(field),
            SceneError::ReadScene { .. } | SceneError::Syntax { .. } | SceneError::Override { .. } => None,
        }
    }
}

/// An expression that cannot be compiled or evaluated.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ExprError {
    /// A syntax error.
    #[error("`{expression}`: column {column}: {reason}")]
    Parse {
        /// The expression.
        expression: String,
        /// The 1-based character column.
        column: usize,
        /// What is wrong.
        reason: String,
    },
    /// A name that is neither an allowed variable nor a constant.
    #[error("`{expression}`: column {column}: unknown variable `{name}` (allowed here: {allowed})")]
    UnknownVariable {
        /// The expression.
        expression: String,
        /// The name.
        name: String,
        /// The 1-based character column.
        column: usize,
        /// The allowed variables, comma-separated.
        allowed: String,
    },
    /// A call of a function that is neither built in nor defined by the scene.
    #[error("`{expression}`: column {column}: unknown function `{name}`")]
    UnknownFunction {
        /// The expression.
        expression: String,
        /// The name.
        name: String,
        /// The 1-based character column.
        column: usize,
    },
    /// A user function definition is invalid.
    #[error("function `{name}`: {reason}")]
    Definition {
        /// The function's name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The expression evaluates to an infinite or NaN value.
    #[error("`{expression}` evaluates to {} at {at}", Num(*value))]
    NonFinite {
        /// The expression.
        expression: String,
        /// The value.
        value: f64,
        /// Where (time and/or position, or "a constant part").
        at: String,
    },
    /// A part of a region predicate is infinite or NaN at a node, although the comparison around it
    /// gives 0 or 1.
    #[error(
        "`{expression}`: a part of it is {} at {at} (a division by zero, or a function outside its domain), so whether the node is selected is not defined", Num(*value)
    )]
    NonFiniteOperand {
        /// The expression.
        expression: String,
        /// The first infinite or NaN value met.
        value: f64,
        /// The position.
        at: String,
    },
    /// A region predicate evaluates to something other than 0 or 1.
    #[error("`{expression}` evaluates to {} at {at}; a predicate must be true (1) or false (0), e.g. `x <= 0.1`", Num(*value))]
    NotBoolean {
        /// The expression.
        expression: String,
        /// The value.
        value: f64,
        /// The position.
        at: String,
    },
    /// More variables than the evaluator supports.
    #[error("`{expression}`: at most {max} variables are supported")]
    TooManyVariables {
        /// The expression.
        expression: String,
        /// The limit.
        max: usize,
    },
    /// The compiled form was rejected by the evaluator (an internal inconsistency).
    #[error("`{expression}`: the evaluator rejected the compiled form: {message}")]
    Backend {
        /// The expression.
        expression: String,
        /// The evaluator's message.
        message: String,
    },
}

/// An OBJ file that cannot be used as a shell mesh. Lines are 1-based; face and vertex numbers are
/// 0-based in the order of the file (OBJ's own numbering is the vertex number plus one).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ObjError {
    /// The file could not be read.
    #[error("cannot read `{}`: {source}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A statement could not be parsed.
    #[error("`{}` line {line}: {reason}", path.display())]
    Parse {
        /// The path.
        path: PathBuf,
        /// The line.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A face that is not a triangle.
    #[error("`{}` line {line}: face {face} has {n_vertices} vertices; only triangles are supported", path.display())]
    NonTriangle {
        /// The path.
        path: PathBuf,
        /// The line.
        line: usize,
        /// The face number.
        face: usize,
        /// Its vertex count.
        n_vertices: usize,
    },
    /// The file has no faces.
    #[error("`{}` has no triangles", path.display())]
    Empty {
        /// The path.
        path: PathBuf,
    },
    /// A degenerate face.
    #[error("`{}` line {line}: face {face} is degenerate (area {area:e}): {}", path.display(), cosserat_fem::error::degenerate_cause(*area, "vertices"))]
    DegenerateFace {
        /// The path.
        path: PathBuf,
        /// The line of the face.
        line: usize,
        /// The face number.
        face: usize,
        /// Its area.
        area: f64,
    },
    /// A vertex that no face uses.
    #[error("`{}` line {line}: vertex {vertex} is not used by any face", path.display())]
    UnreferencedVertex {
        /// The path.
        path: PathBuf,
        /// The line of the vertex.
        line: usize,
        /// The vertex number.
        vertex: usize,
    },
    /// An edge shared by more than two faces.
    #[error("`{}` line {line}: the edge between vertices {a} and {b} is shared by {n_faces} faces (at most two are allowed)", path.display())]
    NonManifoldEdge {
        /// The path.
        path: PathBuf,
        /// The line of the first face beyond the second at that edge.
        line: usize,
        /// One vertex of the edge.
        a: usize,
        /// The other vertex.
        b: usize,
        /// The number of faces at the edge.
        n_faces: usize,
    },
    /// A face with the same three vertices as an earlier one (in any order): a doubled triangle.
    #[error("`{}` line {line}: face {face} has the same three vertices as face {first} (line {first_line}); a doubled triangle is not a surface", path.display())]
    DuplicateFace {
        /// The path.
        path: PathBuf,
        /// The line of the later face.
        line: usize,
        /// The later face number.
        face: usize,
        /// The line of the earlier face.
        first_line: usize,
        /// The earlier face number.
        first: usize,
    },
    /// Any other mesh defect found by validation.
    #[error("`{}`: {source}", path.display())]
    Mesh {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: MeshError,
    },
}

/// A Gmsh or PLY mesh file that cannot be read or used.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum MeshFileError {
    /// The file could not be read.
    #[error("cannot read `{}`: {source}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Malformed or unsupported content.
    #[error("`{}` {at}: {reason}", path.display())]
    Parse {
        /// The path.
        path: PathBuf,
        /// Where: a line, a byte offset or an element.
        at: crate::gmsh::Location,
        /// What is wrong.
        reason: String,
    },
    /// The file has no triangles.
    #[error("`{}` has no triangles", path.display())]
    Empty {
        /// The path.
        path: PathBuf,
    },
    /// Any other mesh defect found by validation.
    #[error("`{}`: {source}", path.display())]
    Mesh {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: MeshError,
    },
}

/// A region that cannot be resolved.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RegionError {
    /// The region selects none of the nodes its user needs.
    #[error("the region ({region}) selects no {kind} node of shell `{shell}`")]
    Empty {
        /// A description of the region.
        region: String,
        /// `displacement` or `rotation`.
        kind: &'static str,
        /// The shell's name.
        shell: String,
    },
    /// A vertex index beyond the mesh.
    #[error("vertex {vertex} does not exist: shell `{shell}` has {n_vertices} vertices")]
    VertexOutOfRange {
        /// The index.
        vertex: usize,
        /// The shell's name.
        shell: String,
        /// Its vertex count.
        n_vertices: usize,
    },
    /// A group name the mesh file does not have.
    #[error("shell `{shell}` has no group `{group}` (its mesh file's groups: {})", if available.is_empty() { "none" } else { available.as_str() })]
    UnknownGroup {
        /// The name asked for.
        group: String,
        /// The shell's name.
        shell: String,
        /// The groups there are, comma-separated.
        available: String,
    },
    /// A boundary loop index beyond the mesh's loops.
    #[error("boundary loop {index} does not exist: shell `{shell}` has {n_loops} boundary loop(s)")]
    LoopOutOfRange {
        /// The index.
        index: usize,
        /// The shell's name.
        shell: String,
        /// Its number of loops.
        n_loops: usize,
    },
    /// A point farther from the mesh than its bounding box (grown by 1 % of its diagonal).
    #[error("the point ({}, {}, {}) lies outside the bounding box of shell `{shell}` ([{}, {}] × [{}, {}] × [{}, {}], grown by 1 % of its diagonal)", Num(point[0]), Num(point[1]), Num(point[2]), Num(min[0]), Num(max[0]), Num(min[1]), Num(max[1]), Num(min[2]), Num(max[2]))]
    PointOutsideMesh {
        /// The point.
        point: [f64; 3],
        /// The shell's name.
        shell: String,
        /// The bounding box minimum (ungrown).
        min: [f64; 3],
        /// The bounding box maximum (ungrown).
        max: [f64; 3],
    },
    /// A predicate that failed at a node.
    #[error(transparent)]
    Predicate(#[from] ExprError),
    /// The mesh's boundary could not be traced.
    #[error("the boundary of shell `{shell}` cannot be traced: {source}")]
    Topology {
        /// The shell's name.
        shell: String,
        /// The cause.
        source: MeshError,
    },
}

/// A shell mesh that cannot be built by [`crate::mesh_source::build_mesh`].
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum MeshSourceError {
    /// The generator rejected a parameter.
    #[error("{0}")]
    Generator(MeshError),
    /// The OBJ file cannot be read or used.
    #[error("{0}")]
    Obj(ObjError),
    /// The Gmsh or PLY file cannot be read or used.
    #[error("{0}")]
    File(MeshFileError),
    /// A pipeline step cannot be applied.
    #[error("{step}: {reason}")]
    Invalid {
        /// The step (a field name of the mesh section).
        step: &'static str,
        /// Why.
        reason: String,
    },
    /// The final mesh has a degenerate or folded element.
    #[error("the resulting mesh is invalid: {0}")]
    Result(MeshError),
}

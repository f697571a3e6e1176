//! The TOML scene format: serde types mirroring the file, and the only place that knows TOML.
//!
//! These types say what a scene file may contain; [`crate::spec::SceneSpec::from_str`] checks the
//! values and turns them into a [`crate::spec::SceneSpec`]. Every table rejects unknown keys, so a
//! misspelled key is an error that lists the expected names, and every choice is a `snake_case`
//! string. Optional values are `Option`s here; their defaults are applied in validation and listed
//! on each field below.
//!
//! A minimal scene:
//! ```toml
//! name = "strip"
//!
//! [time]
//! dt = 0.01
//! end = 1.0
//!
//! [mesh]
//! generator = "rectangle"
//! lx = 0.1
//! ly = 0.01
//! nx = 20
//! ny = 2
//! element = "tri6"
//!
//! [material]
//! model = "plate"
//! thickness = 1e-3
//! youngs_modulus = 1e6
//! poisson_ratio = 0.3
//! density = 1000.0
//! length_scale = 1e-6
//!
//! [[boundary]]
//! region = { predicate = "x <= -0.05 + 1e-9" }
//! position = { stiffness = 1e6 }
//! rotation = { stiffness = 1e4, directors = [3] }
//! ```
//!
//! Shells: either one shell from top-level `\[mesh\]` + `\[material\]`, or several `[\[shell\]]` tables, each
//! with its own `name`, `\[shell.mesh\]` and `[shell.material]`. Boundary conditions, loads, rest fields
//! and probes name their shell with `shell = "name"` or `shell = 0` (index); with a single shell the
//! key may be omitted.
//!
//! Models: `[material] model` is `"plate"` or `"shell"` (the Cosserat shell), or one of the comparison
//! models: `"kirchhoff_love"` (Tri3 mesh, positions only, with `law = "stvk" | "neo_hookean"` and
//! optional `rest_volume`; no rotation conditions, torques, rest fields or director probes) and
//! `"micropolar_volume"` (a flat rectangular grid extruded into `layers` Tet4 layers of the given
//! thickness; regions and probes select node columns). Both run a scene of exactly one shell; checks
//! in `validate/model.rs`.
//!
//! Contact: an optional `\[contact\]` section with obstacles and friction coefficients (see
//! [`ContactSection`]); a scene without it builds no contact structure.
//!
//! Expressions: wherever a scripted value is allowed ([`ExprValue`]), write a number or a string with
//! a formula (see [`crate::expr`] for the syntax). Time functions use the variable `t` (seconds; in
//! quasi-static runs the load factor), rest fields `x, y, z, t` (the rest position of the quadrature
//! point), region predicates `x, y, z` (the rest position of the node). Named helper functions can be
//! declared in `\[functions\]`.

mod contact;
mod value;

pub use contact::{ContactSection, ContactSurfaceSection, FrictionSection, ObstacleSection};
pub use value::{AxisName, AxisValue, ExprValue, ShellRef};

use serde::Deserialize;
use std::collections::BTreeMap;

/// The whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The scene's name (default output directory `out/<name>/`).
    pub name: String,
    /// Free text describing the scene (ignored by the simulator).
    pub description: Option<String>,
    /// Time integration or quasi-static loading.
    pub time: TimeSection,
    /// Newton and linear solver settings (all optional).
    pub solver: Option<SolverSection>,
    /// Gravitational acceleration `[gx, gy, gz]` \[m/s²\]. Default `[0, 0, 0]`: no gravity unless asked
    /// for (most of the paper's scenes switch it off). Each component at most 1e150 in magnitude
    /// (larger ones approach a magnitude whose square overflows).
    pub gravity: Option<[f64; 3]>,
    /// Named helper functions for expressions: `name = { args = ["u"], body = "…" }`.
    pub functions: Option<BTreeMap<String, FunctionSection>>,
    /// The mesh of the single shell (with `\[material\]`).
    pub mesh: Option<MeshSection>,
    /// The material of the single shell (with `\[mesh\]`).
    pub material: Option<MaterialSection>,
    /// Several shells (instead of `\[mesh\]` + `\[material\]`).
    pub shell: Option<Vec<ShellSection>>,
    /// Boundary conditions.
    pub boundary: Option<Vec<BoundarySection>>,
    /// External loads.
    pub load: Option<Vec<LoadSection>>,
    /// Prescribed rest curvature and rest-metric growth.
    pub rest_field: Option<Vec<RestFieldSection>>,
    /// Probes written to `probes.csv`.
    pub probe: Option<Vec<ProbeSection>>,
    /// Output settings.
    pub output: Option<OutputSection>,
    /// Frictional contact (default: none; then no contact structure is built).
    pub contact: Option<ContactSection>,
}

/// A user function for expressions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FunctionSection {
    /// Parameter names.
    pub args: Vec<String>,
    /// The body, an expression of the parameters.
    pub body: String,
}

/// Dynamic or quasi-static.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeMode {
    /// Backward Euler in time (default).
    Dynamic,
    /// A sequence of equilibria at increasing load factors.
    QuasiStatic,
    /// Equilibria traced along the load path by arc-length continuation, through limit points of the
    /// load (snap-through) and of the deflection (snap-back); the load factor is an unknown.
    ArcLength,
}

/// `\[time\]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSection {
    /// `"dynamic"` (default), `"quasi_static"` or `"arc_length"`.
    pub mode: Option<TimeMode>,
    /// (Maximum) time step \[s\]; required in dynamic mode.
    pub dt: Option<f64>,
    /// End time \[s\]; required in dynamic mode. In `arc_length` mode the load factor at which the
    /// path ends, reached from below: a step that would pass it, by its predictor or by its corrector,
    /// lands on it (default 1).
    pub end: Option<f64>,
    /// Output frames per second (default 30, the reference code's default).
    pub output_fps: Option<f64>,
    /// Interval between output frames \[s\] (instead of `output_fps`).
    pub output_interval: Option<f64>,
    /// Dynamic: adaptive time stepping, halve `dt` after a failed step, grow by 1.05 after a success
    /// up to `dt`. Default `true` (the reference code's baseline); fixed-step scenes set `false`.
    /// Quasi-static: where a level needs more than 30 Newton iterations, the following levels
    /// are reached through intermediate ones (not written), which grow back where Newton converges
    /// quickly; levels that converge within that are never split. Default `true`; `false` inserts
    /// intermediate levels only when a solve fails (bisection).
    pub adaptive: Option<bool>,
    /// Quasi-static load factors (increasing, in `(0, 1]`, ending at 1).
    pub levels: Option<Vec<f64>>,
    /// Quasi-static: `n` equal load steps `1/n, 2/n, …, 1` (instead of `levels`).
    pub n_levels: Option<usize>,
    /// Arc length: the load-factor increment of the first step, which sets the arc length of every
    /// step (later steps shorten where the corrector needs more iterations, never lengthen beyond it;
    /// default 0.05).
    pub initial_increment: Option<f64>,
    /// Arc length: at most this many steps before the path must reach `end` (default 1000).
    pub max_steps: Option<usize>,
}

/// Linear solver names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinearSolverName {
    /// Cholesky, then LDLᵀ, then LU as needed.
    Auto,
    /// Sparse Cholesky.
    Cholesky,
    /// Sparse symmetric indefinite LDLᵀ.
    Ldlt,
    /// Sparse LU.
    Lu,
    /// Block-Jacobi preconditioned conjugate gradients (large positive definite systems, e.g. the
    /// volumetric model).
    Cg,
}

/// What Newton's method does with a Hessian that is not positive definite
/// (`cosserat_solver::IndefiniteHessian`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IndefiniteHessianName {
    /// Cholesky of the Hessian shifted to positive definiteness (a trust-region step): the most
    /// robust through snaps, but it cannot settle on a solution that is a saddle of the energy.
    Shift,
    /// The Hessian's own indefinite factorisation while its steps pass in full, then the shift for the
    /// rest of the step: for strips driven through saddles of their massless rotations (the twisting
    /// strip).
    Adaptive,
    /// The Hessian's own indefinite factorisation throughout, ascending directions negated (the
    /// reference code's treatment).
    Factorise,
}

/// Two-domain Cholesky names (`cosserat_solver::DomainSplit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DomainSplitName {
    /// Split systems of at least 20 000 unknowns whose mesh bisects well.
    Auto,
    /// One factorisation of the whole matrix.
    Off,
    /// Split whenever the mesh can be bisected.
    Always,
}

/// Newton start names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialGuessName {
    /// The velocities extrapolated linearly in time from the last two steps (the previous velocities in
    /// the first step; default).
    Extrapolated,
    /// Whichever of `"extrapolated"`, `"previous_velocity"` and `"zero"` has the least incremental
    /// potential: the nearest to the step's solution in the energy's own norm. For motions that reverse
    /// from step to step (a thin sheet pulled taut at once); not for steps that
    /// rotate a body far, nor with contact.
    LeastEnergy,
    /// The previous step's velocities.
    PreviousVelocity,
    /// Zero velocities (the reference code).
    Zero,
}

/// `\[solver\]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// An absolute residual tolerance in N and N·m (the paper's scenes use 1e-7). Without it the
    /// tolerance is relative: `relative_tolerance` times the problem's force scale (the largest
    /// external load, reaction or first residual of the step, in a quasi-static level taken at the
    /// last equilibrium rather than at the level's predicted start; in a dynamic step also the largest
    /// nodal momentum over the time step), never below the residual's round-off floor. Torques count
    /// as forces over the mesh's median node spacing, so the test does not depend on the unit of
    /// length.
    pub tolerance: Option<f64>,
    /// The relative residual tolerance when no absolute `tolerance` is given (default 1e-5 for dynamic
    /// runs, where it bounds each step's velocity error far below the time discretisation's; 1e-6 for
    /// quasi-static and arc-length runs).
    pub relative_tolerance: Option<f64>,
    /// Maximum Newton iterations per step (default 100).
    pub max_newton_iterations: Option<usize>,
    /// Maximum line-search halvings (default 20).
    pub max_line_search_iterations: Option<usize>,
    /// Linear solver (default `"auto"`).
    pub linear_solver: Option<LinearSolverName>,
    /// Two-domain Cholesky: both halves of the mesh factorised at once, one per core (default
    /// `"auto"`).
    pub domain_split: Option<DomainSplitName>,
    /// Newton's starting point (default `"extrapolated"`: the velocities extrapolated from the last two
    /// steps, which saves a third to a half of the Newton iterations of smooth motion). In
    /// `quasi_static` mode `"extrapolated"` starts each level from the last increments extrapolated to
    /// its load and `"zero"` from the last equilibrium (the same equilibria; for the thinnest shells,
    /// docs/time-integration.md); the other two are dynamic only.
    pub initial_guess: Option<InitialGuessName>,
    /// Project element Hessians onto the PSD cone (default `false`).
    pub project_pd: Option<bool>,
    /// What Newton's method does where the Hessian is not positive definite (default `"factorise"` in
    /// quasi-static runs, with the shift as the last resort of a level that fails every bisection;
    /// `"shift"` in dynamic and arc-length runs; `"adaptive"` or `"factorise"` where a time step's
    /// solution is a saddle of the energy, docs/stability.md).
    pub indefinite_hessian: Option<IndefiniteHessianName>,
    /// Maximum halvings of one step before the run stops (default 8).
    pub max_step_reductions: Option<usize>,
    /// Keep the last factorisation of the Newton matrix, also into the next step, while each
    /// iteration cuts the residual by at least this factor (in (0, 1); default 0: factorise every
    /// iteration; dynamic and quasi-static runs): chord steps cost a gradient and two triangular
    /// solves instead of a Hessian and a factorisation. For large systems whose factorisation
    /// dominates a step; the tolerance is the same, the iteration count grows (0.1 suits the
    /// volumetric Lotus slab, docs/micropolar-volume.md).
    pub reuse_factorisation: Option<f64>,
    /// The mixed-integration-point Newton method (default `true` in quasi-static runs, `false`
    /// otherwise): the geometric terms of the Newton matrix use stresses predicted linearly along the
    /// previous steps instead of the stresses at the iterate (the first matrix of a level started from
    /// a prediction, the last equilibrium's), and a full step that raises the energy by
    /// a thin shell's spurious stretch is taken anyway (undone unless each step after it cuts the
    /// energy's excess over its start fourfold until it falls below, within eight steps). The same
    /// solutions with fewer iterations on thin shells under large rotations (README, settings);
    /// ignored by the arc-length corrector.
    pub mixed_integration_points: Option<bool>,
}

/// Mesh generator names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GeneratorName {
    /// `lx, ly, nx, ny`.
    Rectangle,
    /// `radius, n_radial, n_angular`.
    Disk,
    /// `inner_radius, radius, n_radial, n_angular`, optional `slit`.
    Annulus,
    /// `radius, length, n_around, n_along`.
    Cylinder,
    /// `radius, level`.
    Icosphere,
    /// `radius, frequency, min_z`.
    IcosphereCap,
    /// `radius, n_lon, n_lat`.
    UvSphere,
    /// `radius, n_lon, n_lat`, optional `polar_hole_degrees`.
    Hemisphere,
    /// `radius, width, n_along, n_across`.
    Mobius,
}

impl GeneratorName {
    /// The name in the scene file.
    pub fn as_str(self) -> &'static str {
        match self {
            GeneratorName::Rectangle => "rectangle",
            GeneratorName::Disk => "disk",
            GeneratorName::Annulus => "annulus",
            GeneratorName::Cylinder => "cylinder",
            GeneratorName::Icosphere => "icosphere",
            GeneratorName::IcosphereCap => "icosphere_cap",
            GeneratorName::UvSphere => "uv_sphere",
            GeneratorName::Hemisphere => "hemisphere",
            GeneratorName::Mobius => "mobius",
        }
    }
}

/// Element names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElementName {
    /// Linear triangle.
    Tri3,
    /// Quadratic triangle.
    Tri6,
}

/// `\[mesh\]`: a generator with its parameters, or an OBJ file, plus element choice and shaping steps
/// (see [`crate::mesh_source`] for the order in which they apply).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// A procedural mesh (exclusive with `path`).
    pub generator: Option<GeneratorName>,
    /// A mesh file, relative to the scene file's directory or absolute (exclusive with `generator`),
    /// read by its extension in any case: `.obj` (Wavefront OBJ), `.msh` (Gmsh MSH 4.1) or `.ply`;
    /// any other extension is refused.
    pub path: Option<String>,
    /// OBJ input: merge vertices closer than this distance \[m\] (files split along seams; default: no
    /// merging, and a warning when vertices coincide).
    pub weld: Option<f64>,
    /// Displacement element (default `"tri6"`, the paper's).
    pub element: Option<ElementName>,
    /// Rotation element (default: the displacement element, so Tri6/Tri6 with quadratic displacements;
    /// `"tri3"` there selects the paper's pair Tri6/Tri3, and with it the paper's strain interpolation
    /// unless `material.strain_interpolation` says otherwise).
    pub rotation_element: Option<ElementName>,
    /// Quadrature degree override (default: the model's pairing, degree 2 for Tri3/Tri3 and Tri6/Tri3
    /// and 4 for Tri6/Tri6, except Tri6/Tri6 with `material.strain_interpolation = "regge_stabilized"`,
    /// the default discretisation, which takes degree 2, the 3-point rule its strains are built for;
    /// `4` gives it the six-point rule at about twice the cost, docs/model-notes.md).
    pub quadrature_degree: Option<usize>,
    /// Rectangle size along x \[m\].
    pub lx: Option<f64>,
    /// Rectangle size along y \[m\].
    pub ly: Option<f64>,
    /// Rectangle quads along x.
    pub nx: Option<usize>,
    /// Rectangle quads along y.
    pub ny: Option<usize>,
    /// Radius \[m\] (outer radius of an annulus; centre-line radius of a Möbius band).
    pub radius: Option<f64>,
    /// Annulus inner radius \[m\].
    pub inner_radius: Option<f64>,
    /// Disk/annulus rings.
    pub n_radial: Option<usize>,
    /// Disk/annulus vertices per ring.
    pub n_angular: Option<usize>,
    /// Annulus cut open along +x; its two sides are the groups `slit_start` (the elements above the
    /// axis) and `slit_end` (below it).
    pub slit: Option<bool>,
    /// Cylinder length \[m\].
    pub length: Option<f64>,
    /// Cylinder vertices per ring.
    pub n_around: Option<usize>,
    /// Cylinder rings / Möbius vertex columns.
    pub n_along: Option<usize>,
    /// Icosphere subdivision level.
    pub level: Option<usize>,
    /// Icosphere-cap subdivision frequency.
    pub frequency: Option<usize>,
    /// Icosphere-cap lowest corner height \[m\].
    pub min_z: Option<f64>,
    /// UV sphere/hemisphere vertices per ring.
    pub n_lon: Option<usize>,
    /// UV sphere/hemisphere latitude bands.
    pub n_lat: Option<usize>,
    /// Hemisphere polar hole angle \[degrees\].
    pub polar_hole_degrees: Option<f64>,
    /// Möbius band width \[m\].
    pub width: Option<f64>,
    /// Möbius band quads across.
    pub n_across: Option<usize>,
    /// Uniform refinements (default 0).
    pub refine: Option<usize>,
    /// Project every node radially onto a sphere.
    pub project_to_sphere: Option<SphereSection>,
    /// Flatten a spherical cap into a disk with curved boundary edges.
    pub flatten_cap: Option<FlattenCapSection>,
    /// Rotate, centre, scale and translate the rest mesh.
    pub transform: Option<TransformSection>,
    /// Initial positions: the rest positions moved rigidly. Only the positions move: the directors keep
    /// their rest orientation, so a turned start is strained (a perturbation, as the buckling circles'
    /// tilt of 1.5°), and beyond 90° its elements start inside out. To start a shell turned without
    /// strain, turn its rest mesh with `transform`.
    pub initial: Option<InitialSection>,
    /// Displace every node (corners and Tri6 nodes) by `[dx, dy, dz]`, functions of the node's
    /// position `x, y, z` after the transform (e.g. the Papyrus scroll's wavy sheet); applied before
    /// `initial`.
    pub displace: Option<[ExprValue; 3]>,
}

/// `project_to_sphere = { center, radius }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSection {
    /// Centre \[m\] (default the origin).
    pub center: Option<[f64; 3]>,
    /// Radius \[m\].
    pub radius: f64,
}

/// `flatten_cap = { radius }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlattenCapSection {
    /// Radius of the sphere and of the final disk \[m\].
    pub radius: f64,
}

/// One rotation step: `{ axis = "x", degrees = 90 }` or `{ axis = [1, 1, 0], degrees = 30 }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationStep {
    /// The axis (through the origin, or through the transform's fixed point).
    pub axis: AxisValue,
    /// The angle \[degrees\], right-handed about the axis.
    pub degrees: f64,
}

/// `transform = { rotate, center, height, scale, translate }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformSection {
    /// Rotations about the origin, applied in order.
    pub rotate: Option<Vec<RotationStep>>,
    /// Move the bounding-box centre (after rotation) to the origin.
    pub center: Option<bool>,
    /// Scale uniformly to this extent along z \[m\] (exclusive with `scale`).
    pub height: Option<f64>,
    /// Scale uniformly by this factor (exclusive with `height`).
    pub scale: Option<f64>,
    /// Translation after scaling \[m\].
    pub translate: Option<[f64; 3]>,
}

/// `initial = { rotate, about, translate }`: initial positions `R (X − p) + p + d`; the directors keep
/// their rest orientation (a strained start, see `initial`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Rotations about `about`, applied in order.
    pub rotate: Option<Vec<RotationStep>>,
    /// Fixed point of the rotation \[m\] (default the origin).
    pub about: Option<[f64; 3]>,
    /// Translation \[m\].
    pub translate: Option<[f64; 3]>,
}

/// Model names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelName {
    /// The flat-reference plate energy.
    Plate,
    /// The curved-shell energy.
    Shell,
    /// The Kirchhoff–Love thin shell with a hyperelastic material (Wen & Barbič 2023; `cosserat-kl`):
    /// Tri3 displacements only, no rotations; needs `law`.
    KirchhoffLove,
    /// The volumetric micropolar continuum on Tet4 elements (`cosserat-volume`): a rectangle mesh
    /// extruded into a slab of `layers` element layers through the thickness.
    MicropolarVolume,
}

/// Volume measure names of the Kirchhoff–Love thickness integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestVolumeName {
    /// The exact rest volume of each face.
    Exact,
    /// Mid-surface area times thickness.
    MidSurface,
}

/// Hyperelastic law names of the Kirchhoff–Love model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LawName {
    /// St. Venant–Kirchhoff.
    Stvk,
    /// Compressible neo-Hookean.
    NeoHookean,
}

/// Curved-term counting names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurvedTermsName {
    /// The supplement's energy (default).
    Supplement,
    /// The reference code's term registration.
    ReferenceCompatibility,
}

/// Membrane volume names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MembraneVolumeName {
    /// Quadratic trace term (default).
    Quadratic,
    /// Nonlinear area-ratio term (plate only).
    Nonlinear,
}

/// Axial-vector variant names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxlName {
    /// `axl(skew M)` (default).
    SkewPart,
    /// The reference code's negated upper triangle.
    UpperTriangle,
}

/// Strain-interpolation names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrainInterpolationName {
    /// Every quadrature point's own strains (the paper's discretisation).
    Paper,
    /// Element means plus scaled fluctuations of the membrane, drilling and shear strains; on elements
    /// longer than the thickness too flexible in in-plane bending (a run warns).
    Stabilized,
    /// Assumed covariant membrane, drilling and shear strains interpolated from tying points on the
    /// element edges and at its centroid (MITC6-style).
    Assumed,
    /// Membrane strains interpolated into the linear Regge space by their edge-tangential and interior
    /// moments; drilling, shear and curvature strains at the points.
    Regge,
    /// Regge membrane strains with stabilised element means of the shear and drilling strains (for thin
    /// and curved shells on coarse meshes; docs/model-notes.md).
    ReggeStabilized,
}

impl StrainInterpolationName {
    /// The name in the scene file.
    pub fn as_str(self) -> &'static str {
        match self {
            StrainInterpolationName::Paper => "paper",
            StrainInterpolationName::Stabilized => "stabilized",
            StrainInterpolationName::Assumed => "assumed",
            StrainInterpolationName::Regge => "regge",
            StrainInterpolationName::ReggeStabilized => "regge_stabilized",
        }
    }

    /// The override (`--set`) that selects it.
    pub fn scene_override(self) -> String {
        format!("material.strain_interpolation={}", self.as_str())
    }
}

/// Rest-curvature source names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurvatureSourceName {
    /// Exact normals on curved elements, averaged elsewhere (default).
    Auto,
    /// Exact element normals.
    Exact,
    /// Averaged nodal normals.
    Averaged,
}

/// Normal weighting names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalWeightingName {
    /// Max (1999) weights (default).
    Max,
    /// Angle weights.
    Angle,
    /// Area weights.
    Area,
    /// Equal weights.
    Uniform,
}

/// `\[material\]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    /// `"plate"`, `"shell"`, `"kirchhoff_love"` or `"micropolar_volume"`.
    pub model: ModelName,
    /// Hyperelastic law of the Kirchhoff–Love model: `"stvk"` or `"neo_hookean"` (required there, not
    /// allowed otherwise).
    pub law: Option<LawName>,
    /// Volume measure of the Kirchhoff–Love thickness integral: `"exact"` (default) or `"mid_surface"`
    /// (thin-shell approximation for meshes locally more curved than `2/h`; Kirchhoff–Love only).
    pub rest_volume: Option<RestVolumeName>,
    /// Element layers through the thickness of the micropolar volume model (default 1, the paper's
    /// Lotus Tet4 row; not allowed otherwise).
    pub layers: Option<usize>,
    /// Thickness `h` \[m\].
    pub thickness: f64,
    /// Young's modulus `E` \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson ratio `ν` in (−1, 0.5).
    pub poisson_ratio: f64,
    /// Volumetric density `ρ` \[kg/m³\].
    pub density: f64,
    /// Internal length `L_c` \[m\] (required by the Cosserat models; not allowed for
    /// `"kirchhoff_love"`).
    pub length_scale: Option<f64>,
    /// `μ_c / μ` (default 1).
    pub mu_c_factor: Option<f64>,
    /// `(b₁, b₂, b₃)` of the curvature energy (default `[1, 1, 0]`).
    pub curvature_coefficients: Option<[f64; 3]>,
    /// `κ_b` (default 1).
    pub bending_correction: Option<f64>,
    /// Mass-proportional damping \[1/s\] (default 0).
    pub damping: Option<f64>,
    /// Angular inertia density `ρ_θ` \[kg/m\] (default 0).
    pub angular_inertia_density: Option<f64>,
    /// Curved-term counting (default `"supplement"`).
    pub curved_terms: Option<CurvedTermsName>,
    /// Membrane volume term (default `"quadratic"`).
    pub membrane_volume: Option<MembraneVolumeName>,
    /// Axial vector (default `"skew_part"`).
    pub axl: Option<AxlName>,
    /// How the quadrature points' strains enter the energy: `"paper"`, `"stabilized"`, `"assumed"`,
    /// `"regge"` or `"regge_stabilized"` (default: `"regge_stabilized"` on Tri6/Tri6, the default pair,
    /// locking-free on thin and curved shells; `"paper"` on Tri6/Tri3 and Tri3/Tri3).
    /// docs/model-notes.md compares them on the locking benchmarks.
    pub strain_interpolation: Option<StrainInterpolationName>,
    /// Rest-curvature normal field (default `"auto"`).
    pub curvature_source: Option<CurvatureSourceName>,
    /// Weighting of averaged normals (default `"max"`).
    pub normal_weighting: Option<NormalWeightingName>,
}

/// `[\[shell\]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShellSection {
    /// Name (default `shell<k>`), unique.
    pub name: Option<String>,
    /// The mesh.
    pub mesh: MeshSection,
    /// The material.
    pub material: MaterialSection,
}

/// `region = { … }`: exactly one of the keys.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSection {
    /// `box = { center, size }`.
    #[serde(rename = "box")]
    pub aabb: Option<BoxSection>,
    /// A boolean expression of `x, y, z`.
    pub predicate: Option<String>,
    /// Corner vertex indices (0-based, in the OBJ file's order or the generator's). With quadratic
    /// elements the mid-edge nodes of every edge whose two corners are listed are selected too, so
    /// the vertices of an edge select the whole edge. The `rectangle` generator numbers its vertices
    /// column by column: vertex `(i, j)` (`i ≤ nx` along x, `j ≤ ny` along y) is `i·(ny + 1) + j`, so
    /// the edge `x = −lx/2` is `0..=ny`. Boxes and predicates are usually easier.
    pub nodes: Option<Vec<usize>>,
    /// Boundary loop index.
    pub boundary_loop: Option<usize>,
    /// A named group of the mesh file: a Gmsh physical group (curves or surfaces) or an OBJ `g`/`o`
    /// group; or of the generator: `slit_start` and `slit_end`, the two sides of a slit annulus (on
    /// an unrefined mesh).
    pub group: Option<String>,
    /// The nearest node to a point.
    pub nearest: Option<[f64; 3]>,
    /// Every node (`all = true`).
    pub all: Option<bool>,
}

/// `box = { center, size }` (full size, faces included).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSection {
    /// Centre \[m\].
    pub center: [f64; 3],
    /// Full size per axis \[m\].
    pub size: [f64; 3],
}

/// Timing names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimingName {
    /// Evaluate at the start of the step.
    StartOfStep,
    /// Evaluate at the end of the step.
    EndOfStep,
}

/// `position = { stiffness, exact, axes }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionSection {
    /// Penalty stiffness \[N/m\] (exclusive with `exact`).
    pub stiffness: Option<f64>,
    /// Exact elimination (`exact = true`).
    pub exact: Option<bool>,
    /// Constrained world axes (default all).
    pub axes: Option<Vec<AxisName>>,
}

/// `rotation = { stiffness, directors }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationSection {
    /// Penalty stiffness \[N·m\].
    pub stiffness: f64,
    /// Constrained directors (columns of the rotation), 1-based (default `[1, 2, 3]`; `[3]` is the
    /// paper's "d3 clamp").
    pub directors: Option<Vec<usize>>,
}

/// `angular_velocity = { stiffness, axes, target }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AngularVelocitySection {
    /// Penalty stiffness.
    pub stiffness: f64,
    /// Constrained components (default all).
    pub axes: Option<Vec<AxisName>>,
    /// Target angular velocity \[rad/s\] per component, functions of `t` (default zero).
    pub target: Option<[ExprValue; 3]>,
}

/// `motion = { rotate = { axis, center, angle }, translate = \[..\] }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    /// Rotation about a fixed axis.
    pub rotate: Option<MotionRotation>,
    /// Translation \[m\] per component, functions of `t`.
    pub translate: Option<[ExprValue; 3]>,
}

/// `rotate = { axis, center, angle }` of a motion.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionRotation {
    /// The axis direction.
    pub axis: AxisValue,
    /// A point on the axis \[m\] (default the origin).
    pub center: Option<[f64; 3]>,
    /// The angle \[rad\] as a function of `t`.
    pub angle: ExprValue,
}

/// `[\[boundary\]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySection {
    /// Name (default `boundary<k>`).
    pub name: Option<String>,
    /// The shell (default the only one).
    pub shell: Option<ShellRef>,
    /// The constrained nodes.
    pub region: RegionSection,
    /// Prescribed positions.
    pub position: Option<PositionSection>,
    /// Prescribed rotations.
    pub rotation: Option<RotationSection>,
    /// Prescribed angular velocity.
    pub angular_velocity: Option<AngularVelocitySection>,
    /// Motion of the targets (default fixed).
    pub motion: Option<MotionSection>,
    /// When the motion is evaluated (default `"end_of_step"`).
    pub timing: Option<TimingName>,
    /// Active interval `[t0, t1)` (default always).
    pub active: Option<[f64; 2]>,
}

/// Force distribution names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DistributionName {
    /// Equal shares of the total (default).
    Equal,
    /// The vector on every node.
    PerNode,
    /// A line load per unit length along the selected boundary edges.
    PerLength,
    /// A line load along the selected boundary edges with the given total.
    TotalOverLength,
    /// A load per unit area over the elements whose nodes are all selected.
    PerArea,
    /// A load over the elements whose nodes are all selected with the given total.
    TotalOverArea,
}

/// `[\[load\]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSection {
    /// Name (default `load<k>`).
    pub name: Option<String>,
    /// The shell (default the only one).
    pub shell: Option<ShellRef>,
    /// The loaded nodes.
    pub region: RegionSection,
    /// A force \[N\] (exclusive with `torque`), each component at most 1e150 in magnitude (larger
    /// ones approach a magnitude whose square overflows).
    pub force: Option<[f64; 3]>,
    /// A torque \[N·m\] (exclusive with `force`), each component at most 1e150 in magnitude (larger
    /// ones approach a magnitude whose square overflows).
    pub torque: Option<[f64; 3]>,
    /// A pressure \[Pa\] on the elements whose nodes are all selected, positive along the normal
    /// of the element node order (exclusive with `force` and `torque`), at most 1e150 in magnitude
    /// (larger ones approach a magnitude whose square overflows).
    pub pressure: Option<f64>,
    /// Whether the pressure follows the deformed surface (default `true`) or keeps the rest normals
    /// and areas (dead pressure).
    pub follower: Option<bool>,
    /// Distribution (default `"equal"`).
    pub distribution: Option<DistributionName>,
    /// A function of the rest position `x, y, z` that multiplies the load's intensity point by point
    /// (default 1): integrated over the elements by `per_area` and `total_over_area`, taken at the
    /// nodes by the other distributions. Not with `pressure`.
    pub profile: Option<ExprValue>,
    /// Scale over time (default 1).
    pub scale: Option<ExprValue>,
    /// When the scale is evaluated (default `"start_of_step"`).
    pub timing: Option<TimingName>,
}

/// One prescribed rest-curvature entry `Γ_rest[row, col]` (1-based, as in the paper's `Γ_ij`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvatureEntrySection {
    /// Row `i` (1–3): the world axis of the rotation.
    pub row: usize,
    /// Column `j` (1–3): the world direction along which it accumulates.
    pub col: usize,
    /// The value \[rad/m\], a function of `x, y, z, t`.
    pub value: ExprValue,
}

/// `[[rest_field]]`. Several tables on one shell act as one: their curvature entries add up, tables
/// with entries share one `frame`, all share one `timing`, and one of them at most has a `growth`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestFieldSection {
    /// The shell (default the only one).
    pub shell: Option<ShellRef>,
    /// Rest-curvature entries.
    pub curvature: Option<Vec<CurvatureEntrySection>>,
    /// The frame rotation `Q` of `Γ_rest ← Qᵀ Γ_rest Q`, as rotation steps.
    pub frame: Option<Vec<RotationStep>>,
    /// Growth `s(x, y, z, t)`: the rest metric becomes `e^{2s} a₀`.
    pub growth: Option<ExprValue>,
    /// When the fields are evaluated (default `"start_of_step"`).
    pub timing: Option<TimingName>,
}

/// Probe quantity names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QuantityName {
    /// `ux, uy, uz` (default).
    Displacement,
    /// `x, y, z`.
    Position,
    /// `vx, vy, vz`.
    Velocity,
    /// `d3x, d3y, d3z`.
    Director,
}

/// Probe reduction names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReductionName {
    /// The nearest node.
    Nearest,
    /// The mean over the region.
    Mean,
}

/// `[\[probe\]]`: `point = \[..\]` (nearest node) or `region = { … }` (mean).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSection {
    /// Name: CSV columns are `<name>.<component>`.
    pub name: String,
    /// The shell (default the only one).
    pub shell: Option<ShellRef>,
    /// A point: the nearest node is probed.
    pub point: Option<[f64; 3]>,
    /// A region: its nodes are averaged.
    pub region: Option<RegionSection>,
    /// The quantity (default `"displacement"`).
    pub quantity: Option<QuantityName>,
    /// The reduction (default `"nearest"` with `point`, `"mean"` with `region`).
    pub reduction: Option<ReductionName>,
}

/// `\[output\]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Write VTU frames (default `true`).
    pub frames: Option<bool>,
    /// Subdivision level of quadratic elements in frames (default 1).
    pub subdivision: Option<usize>,
    /// Frame formats, each named once (default `["vtu"]`): `"vtu"` (ParaView), `"obj"` and `"ply"`
    /// (one file per frame), `"usd"` (one `run.usda` with time samples).
    pub formats: Option<Vec<FrameFormatName>>,
    /// Write a checkpoint every this many steps (load levels in quasi-static runs) into
    /// `checkpoint/` of the output folder; `cosserat resume DIR` continues the run from it, with the
    /// same results as a run that was never stopped (default: no checkpoints). Counted in steps, not
    /// in time, because a run can only stop and restart between two steps and an adaptive time step
    /// makes a time interval land between them. Not for arc-length runs or USD frames.
    pub checkpoint_every: Option<usize>,
}

/// Frame format names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameFormatName {
    /// VTU frames and a `.pvd` collection.
    Vtu,
    /// OBJ per frame.
    Obj,
    /// Binary PLY per frame.
    Ply,
    /// One USD stage (`.usda`) with time samples.
    Usd,
}

impl FrameFormatName {
    /// The name in the scene file.
    pub fn as_str(self) -> &'static str {
        match self {
            FrameFormatName::Vtu => "vtu",
            FrameFormatName::Obj => "obj",
            FrameFormatName::Ply => "ply",
            FrameFormatName::Usd => "usd",
        }
    }
}

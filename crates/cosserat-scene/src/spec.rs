//! The validated, typed description of a scene: what the simulator runs.
//!
//! A TOML scene is parsed and checked into a [`SceneSpec`]. Every choice is an enum, every number has
//! been range-checked, every region has been resolved into node indices (and is known to select
//! something), and every scripted quantity is a callable function of time (and rest position). The
//! simulator never sees strings or TOML.
//!
//! Conventions:
//! - Node indices in a [`NodeSelection`] are *local* to their shell: displacement nodes index
//!   `ShellMesh` displacement nodes (Tri6 nodes for quadratic elements, Tri3 vertices otherwise),
//!   rotation nodes index the rotation mesh (corner vertices for Tri3 rotations).
//! - Positions are in metres, angles in radians, times in seconds.
//! - Boundary targets are evaluated at the end of each step (`t + Δt`) unless stated otherwise; loads
//!   and rest fields at the evaluation time given by their [`Timing`].

use cosserat_assembly::{ElementPair, ShellMesh};
use cosserat_fem::QuadratureRule;
use cosserat_material::MaterialParameters;
use cosserat_material::rest::RestOptions;
use cosserat_solver::linear::LinearSolverKind;
use cosserat_solver::time_step::InitialGuess;
use nalgebra::{Matrix3, Vector3};
use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

/// A scalar function of time, `f(t)`.
#[derive(Clone)]
pub struct TimeFunction {
    f: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    description: String,
}

impl TimeFunction {
    /// A function from a closure, with a human-readable description (the expression it came from).
    pub fn new(description: impl Into<String>, f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        Self {
            f: Arc::new(f),
            description: description.into(),
        }
    }

    /// A constant.
    pub fn constant(value: f64) -> Self {
        Self::new(format!("{value}"), move |_| value)
    }

    /// The value at time `t`.
    #[inline]
    pub fn eval(&self, t: f64) -> f64 {
        (self.f)(t)
    }

    /// The description.
    pub fn description(&self) -> &str {
        &self.description
    }
}

impl fmt::Debug for TimeFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "TimeFunction({})", self.description)
    }
}

/// The closure type behind a [`FieldFunction`].
type FieldClosure = dyn Fn(&Vector3<f64>, f64) -> f64 + Send + Sync;

/// A scalar function of the rest position and time, `f(X, t)`.
#[derive(Clone)]
pub struct FieldFunction {
    f: Arc<FieldClosure>,
    description: String,
    time_dependent: bool,
}

impl FieldFunction {
    /// A field from a closure. `time_dependent = false` lets the simulator evaluate it once.
    pub fn new(
        description: impl Into<String>,
        time_dependent: bool,
        f: impl Fn(&Vector3<f64>, f64) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Self {
            f: Arc::new(f),
            description: description.into(),
            time_dependent,
        }
    }

    /// The value at rest position `x` and time `t`.
    #[inline]
    pub fn eval(&self, x: &Vector3<f64>, t: f64) -> f64 {
        (self.f)(x, t)
    }

    /// Whether the value changes with time.
    pub fn is_time_dependent(&self) -> bool {
        self.time_dependent
    }

    /// The description.
    pub fn description(&self) -> &str {
        &self.description
    }
}

impl fmt::Debug for FieldFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "FieldFunction({})", self.description)
    }
}

/// When a scripted quantity is evaluated for the step `tⁿ → tⁿ + Δt`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Timing {
    /// At `tⁿ` (the reference code's convention for loads and rest fields).
    #[default]
    StartOfStep,
    /// At `tⁿ + Δt` (the reference code's convention for boundary targets).
    EndOfStep,
}

/// A complete scene.
#[derive(Debug, Clone)]
pub struct SceneSpec {
    /// Scene name (default output directory `out/<name>/`).
    pub name: String,
    /// The file it was read from, if any.
    pub source: Option<PathBuf>,
    /// The shells.
    pub shells: Vec<ShellSpec>,
    /// Time integration or quasi-static loading.
    pub time: TimeSpec,
    /// Newton and linear-solver settings.
    pub solver: SolverSpec,
    /// Gravitational acceleration \[m/s²\].
    pub gravity: Vector3<f64>,
    /// Boundary conditions.
    pub boundaries: Vec<BoundarySpec>,
    /// External loads.
    pub loads: Vec<LoadSpec>,
    /// Prescribed rest curvature and rest-metric growth.
    pub rest_fields: Vec<RestFieldSpec>,
    /// Probes written to `probes.csv`.
    pub probes: Vec<ProbeSpec>,
    /// Output settings.
    pub output: OutputSpec,
}

/// One shell: its mesh, elements, material and model.
#[derive(Debug, Clone)]
pub struct ShellSpec {
    /// Name (for summaries and errors).
    pub name: String,
    /// The rest mesh, already upgraded to the displacement element.
    pub mesh: ShellMesh,
    /// Displacement/rotation element pair.
    pub pair: ElementPair,
    /// Material parameters (validated).
    pub material: MaterialParameters,
    /// Model options and rest-curvature source.
    pub rest: RestOptions,
    /// Quadrature rule override.
    pub quadrature: Option<QuadratureRule>,
    /// Mass-proportional damping `d` \[1/s\].
    pub damping: f64,
    /// Angular inertia density `ρ_θ` \[kg/m\].
    pub angular_inertia_density: f64,
    /// Initial displacement-node positions when they differ from the rest positions (local order).
    pub initial_positions: Option<Vec<Vector3<f64>>>,
}

/// Time integration settings.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeSpec {
    /// Backward Euler in time.
    Dynamic {
        /// (Maximum) time step \[s\].
        dt: f64,
        /// End time \[s\] (`0` writes only the initial frame).
        end: f64,
        /// Adaptive time stepping (grow by 1.05 after success, halve on failure).
        adaptive: bool,
        /// Interval between output frames and probe rows \[s\].
        output_interval: f64,
    },
    /// A sequence of equilibria; the pseudo time `t` is the load factor in `[0, 1]`.
    QuasiStatic {
        /// Load factors at which equilibria are computed and written (increasing, ending at 1).
        levels: Vec<f64>,
    },
}

/// Newton and linear solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSpec {
    /// Residual tolerance: max |∂Π/∂u| / Δt, in N (translations) and N·m (rotations).
    pub tolerance: f64,
    /// Maximum Newton iterations per step.
    pub max_newton_iterations: usize,
    /// Maximum line-search halvings per iteration.
    pub max_line_search_iterations: usize,
    /// Linear solver.
    pub linear_solver: LinearSolverKind,
    /// Newton's starting point each step.
    pub initial_guess: InitialGuess,
    /// Project element Hessians of the shell energy onto the PSD cone.
    pub project_pd: bool,
    /// Maximum number of time-step halvings of one step before the run stops.
    pub max_step_reductions: usize,
}

/// Nodes of one shell selected by a region.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeSelection {
    /// Index of the shell in [`SceneSpec::shells`].
    pub shell: usize,
    /// Selected displacement nodes (local indices, sorted, unique).
    pub disp_nodes: Vec<usize>,
    /// Selected rotation nodes (local indices, sorted, unique).
    pub rot_nodes: Vec<usize>,
}

/// A rigid motion over time applied to the rest (or creation-time) positions of constrained nodes:
/// `x̄(t) = R(t) (X − c) + c + d(t)`, and rotation targets `R̄(t) = R(t)`.
#[derive(Debug, Clone)]
pub struct MotionSpec {
    /// Rotation about a fixed axis through `center`: `(unit axis, center, angle(t) \[rad\])`.
    pub rotation: Option<(Vector3<f64>, Vector3<f64>, TimeFunction)>,
    /// Translation `d(t)` \[m\], per component.
    pub translation: Option<[TimeFunction; 3]>,
}

impl MotionSpec {
    /// No motion: targets stay at their initial values.
    pub fn fixed() -> Self {
        Self {
            rotation: None,
            translation: None,
        }
    }
}

/// How prescribed positions are enforced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PositionEnforcement {
    /// A penalty `½ k |x − x̄|²` with stiffness `k` \[N/m\] (the paper's way).
    Penalty(f64),
    /// Exact elimination of the constrained velocity unknowns.
    Exact,
}

/// A boundary condition on a region.
#[derive(Debug, Clone)]
pub struct BoundarySpec {
    /// Name (for summaries and errors).
    pub name: String,
    /// The constrained nodes.
    pub selection: NodeSelection,
    /// Prescribed positions: enforcement and active world axes.
    pub position: Option<(PositionEnforcement, [bool; 3])>,
    /// Prescribed rotations: penalty stiffness \[N·m\] and constrained directors (columns).
    pub rotation: Option<(f64, [bool; 3])>,
    /// Prescribed angular velocity: penalty stiffness, active components, target \[rad/s\] over time.
    pub angular_velocity: Option<(f64, [bool; 3], [TimeFunction; 3])>,
    /// The motion of the targets.
    pub motion: MotionSpec,
    /// When the motion is evaluated (default: end of step).
    pub timing: Timing,
    /// Time interval in which the condition is active (`[start, end)`), default always.
    pub active: (f64, f64),
}

/// How a total force is distributed over the selected nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForceDistribution {
    /// Equal shares per selected node (the reference code's way).
    Equal,
    /// The given vector is applied to every selected node.
    PerNode,
    /// Consistent nodal weights of a line load along the selected boundary edges: the vector is a
    /// force per unit length \[N/m\].
    PerLength,
    /// Consistent nodal weights of a line load scaled so that the total equals the vector \[N\].
    TotalOverLength,
}

/// An external load.
#[derive(Debug, Clone)]
pub enum LoadKind {
    /// A force on displacement nodes.
    Force {
        /// The force vector (meaning per [`ForceDistribution`]).
        vector: Vector3<f64>,
        /// Distribution.
        distribution: ForceDistribution,
    },
    /// A torque on rotation nodes \[N·m\].
    Torque {
        /// The torque vector.
        vector: Vector3<f64>,
        /// Distribution (`PerLength` and `TotalOverLength` use the rotation nodes' boundary edges).
        distribution: ForceDistribution,
    },
}

/// A load on a region, scaled by a function of time (or of the load factor in quasi-static runs).
#[derive(Debug, Clone)]
pub struct LoadSpec {
    /// Name.
    pub name: String,
    /// The loaded nodes.
    pub selection: NodeSelection,
    /// Force or torque.
    pub kind: LoadKind,
    /// Scale over time.
    pub scale: TimeFunction,
    /// When the scale is evaluated.
    pub timing: Timing,
}

/// Prescribed rest fields of a shell, evaluated at the rest positions of its quadrature points.
#[derive(Debug, Clone)]
pub struct RestFieldSpec {
    /// Index of the shell.
    pub shell: usize,
    /// Entries `(row, column, value)` of the rest curvature `Γ_rest` (0-based, world axes), before
    /// the optional frame rotation.
    pub curvature: Vec<(usize, usize, FieldFunction)>,
    /// `Γ_rest ← Qᵀ Γ_rest Q` with this rotation (e.g. the scroll's 3° about z).
    pub curvature_frame: Option<Matrix3<f64>>,
    /// Growth `s(X, t)`: the rest metric becomes `e^{2s} a₀`.
    pub growth: Option<FieldFunction>,
    /// When the fields are evaluated.
    pub timing: Timing,
}

/// The quantity a probe reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProbeQuantity {
    /// Displacement `x − X`: columns `ux, uy, uz`.
    Displacement,
    /// Position `x`: columns `x, y, z`.
    Position,
    /// Velocity: columns `vx, vy, vz`.
    Velocity,
    /// Director `d₃ = R e_z` of the rotation nodes: columns `d3x, d3y, d3z`.
    Director,
}

/// How a probe reduces its nodes to one value per component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProbeReduction {
    /// The node nearest to the probe point (the selection has one node).
    Nearest,
    /// The mean over the selected nodes.
    Mean,
}

/// A probe: one CSV column per component, named `<name>.<component>`.
#[derive(Debug, Clone)]
pub struct ProbeSpec {
    /// Name.
    pub name: String,
    /// The probed nodes.
    pub selection: NodeSelection,
    /// The quantity.
    pub quantity: ProbeQuantity,
    /// The reduction.
    pub reduction: ProbeReduction,
}

impl ProbeSpec {
    /// Column names of this probe.
    pub fn columns(&self) -> [String; 3] {
        let c = match self.quantity {
            ProbeQuantity::Displacement => ["ux", "uy", "uz"],
            ProbeQuantity::Position => ["x", "y", "z"],
            ProbeQuantity::Velocity => ["vx", "vy", "vz"],
            ProbeQuantity::Director => ["d3x", "d3y", "d3z"],
        };
        c.map(|c| format!("{}.{c}", self.name))
    }
}

/// Output settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputSpec {
    /// Write VTU frames.
    pub frames: bool,
    /// Subdivision level of quadratic elements in the frames (each level splits a triangle into 4).
    pub subdivision: usize,
}

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
use cosserat_solver::linear::{DomainSplit, LinearSolverKind};
use cosserat_solver::time_step::InitialGuess;
use cosserat_solver::{IndefiniteHessian, Tolerance};
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
        Self::new(cosserat_geometry::Num(value).to_string(), move |_| value)
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
    /// Frictional contact; `None` builds no contact structure at all.
    pub contact: Option<ContactSpec>,
    /// What the inputs do that is allowed but probably not meant (coincident OBJ vertices, ...), for
    /// the run to report.
    pub warnings: Vec<String>,
}

/// The hyperelastic law of a Kirchhoff–Love shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum HyperelasticLaw {
    /// St. Venant–Kirchhoff.
    StVenantKirchhoff,
    /// Compressible neo-Hookean.
    NeoHookean,
}

/// The volume measure of a Kirchhoff–Love shell's thickness integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum KlRestVolume {
    /// The exact rest volume of each face (requires `h/2` below every rest radius of curvature).
    #[default]
    Exact,
    /// Mid-surface area times thickness (thin-shell approximation; admits sharper rest curvature).
    MidSurface,
}

/// The settings of a Kirchhoff–Love shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KlSettings {
    /// The hyperelastic law.
    pub law: HyperelasticLaw,
    /// The volume measure through the thickness.
    pub rest_volume: KlRestVolume,
}

/// Which mechanical model a shell of a scene is simulated with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ModelKind {
    /// The three-director Cosserat shell (plate or curved shell, per [`ShellSpec::rest`]).
    #[default]
    Cosserat,
    /// The Kirchhoff–Love thin shell of `cosserat-kl` on the Tri3 mesh: vertex positions only.
    /// [`ShellSpec::material`] supplies thickness, Young's modulus, Poisson ratio, density; its
    /// Cosserat-only entries are unused.
    KirchhoffLove(KlSettings),
    /// The volumetric micropolar continuum of `cosserat-volume`: the Tri3 rectangle mesh (the
    /// mid-surface) extruded into a slab of `layers` Tet4 layers through the thickness. Selections of
    /// the shell's nodes stand for the columns of slab nodes above them.
    MicropolarVolume {
        /// Element layers through the thickness (at least 1).
        layers: usize,
    },
}

/// One shell: its mesh, elements, material and model.
#[derive(Debug, Clone)]
pub struct ShellSpec {
    /// Name (for summaries and errors).
    pub name: String,
    /// The mechanical model.
    pub model: ModelKind,
    /// The rest mesh, already upgraded to the displacement element.
    pub mesh: ShellMesh,
    /// Displacement/rotation element pair.
    pub pair: ElementPair,
    /// Material parameters (validated).
    pub material: MaterialParameters,
    /// Model options and rest-curvature source.
    pub rest: RestOptions,
    /// Quadrature rule override (`None`: [`ShellSpec::quadrature_rule`]'s default).
    pub quadrature: Option<QuadratureRule>,
    /// Mass-proportional damping `d` \[1/s\].
    pub damping: f64,
    /// Angular inertia density `ρ_θ` \[kg/m\].
    pub angular_inertia_density: f64,
    /// Initial displacement-node positions when they differ from the rest positions (local order).
    pub initial_positions: Option<Vec<Vector3<f64>>>,
}

impl ShellSpec {
    /// The quadrature rule the shell is integrated with: the override, or the pair's default with the
    /// shell's strain interpolation ([`ElementPair::default_quadrature`]).
    pub fn quadrature_rule(&self) -> QuadratureRule {
        self.quadrature
            .unwrap_or_else(|| self.pair.default_quadrature(self.rest.interpolation))
    }
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
        /// Intermediate levels where a level needs many Newton iterations (not written).
        adaptive: bool,
    },
    /// Equilibria traced along the load path by arc-length continuation; the pseudo time `t` of
    /// scripts is the load factor, which may fall and rise along the path.
    ArcLength {
        /// The load-factor increment of the first step (sets the arc length).
        initial_increment: f64,
        /// The load factor at which the path ends, reached from below.
        end: f64,
        /// At most this many steps.
        max_steps: usize,
    },
}

/// Newton and linear solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSpec {
    /// Residual tolerance on max |∂Π/∂u| / Δt, in N (translations) and N·m (rotations): relative to
    /// the load scale (with the round-off floor) unless the scene gives an absolute one.
    pub tolerance: Tolerance,
    /// Maximum Newton iterations per step.
    pub max_newton_iterations: usize,
    /// Maximum line-search halvings per iteration.
    pub max_line_search_iterations: usize,
    /// Linear solver.
    pub linear_solver: LinearSolverKind,
    /// Whether the Cholesky factorisation splits the mesh into two domains factorised at once.
    pub domain_split: DomainSplit,
    /// Newton's starting point each step.
    pub initial_guess: InitialGuess,
    /// Project element Hessians of the shell energy onto the PSD cone.
    pub project_pd: bool,
    /// What Newton's method does with a Hessian that is not positive definite.
    pub indefinite_hessian: IndefiniteHessian,
    /// Maximum number of time-step halvings of one step before the run stops.
    pub max_step_reductions: usize,
    /// Keep the last factorisation while each Newton iteration cuts the residual by at least this
    /// factor (chord steps, also into the next step); `None` factorises every iteration.
    pub reuse_factorisation: Option<f64>,
    /// Newton matrices with stresses predicted along the steps (the mixed-integration-point method).
    pub mixed_integration_points: bool,
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

    /// The map `X ↦ R(t) (X − c) + c + d(t)` at time `t`.
    pub fn map_at(&self, t: f64) -> impl Fn(&Vector3<f64>) -> Vector3<f64> + use<> {
        let (rotation, center) = match &self.rotation {
            Some((axis, center, angle)) => (
                nalgebra::Rotation3::from_scaled_axis(axis * angle.eval(t)).into_inner(),
                *center,
            ),
            None => (Matrix3::identity(), Vector3::zeros()),
        };
        let translation = self.translation.as_ref().map_or_else(Vector3::zeros, |d| {
            Vector3::new(d[0].eval(t), d[1].eval(t), d[2].eval(t))
        });
        move |x: &Vector3<f64>| rotation * (x - center) + center + translation
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
    /// Consistent nodal weights `∫ N_a dA` of a load per unit area over the rest surface of the
    /// elements whose nodes are all selected: the vector is a force per unit area \[N/m²\].
    PerArea,
    /// Consistent nodal weights of a load per unit area scaled so that the total equals the vector
    /// \[N\].
    TotalOverArea,
}

impl ForceDistribution {
    /// Whether the load is spread over boundary edges.
    pub fn is_line(self) -> bool {
        matches!(self, Self::PerLength | Self::TotalOverLength)
    }

    /// Whether the load is spread over elements.
    pub fn is_area(self) -> bool {
        matches!(self, Self::PerArea | Self::TotalOverArea)
    }
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
        /// Distribution (`PerLength` and `TotalOverLength` use the rotation nodes' boundary edges,
        /// `PerArea` and `TotalOverArea` the rotation elements).
        distribution: ForceDistribution,
    },
    /// A pressure on the elements whose displacement nodes are all selected, along the normal of the
    /// element node order.
    Pressure {
        /// The pressure \[Pa\].
        value: f64,
        /// Along the current normal over the current area (follower), or the rest ones (dead).
        follower: bool,
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
    /// A function of the rest position that multiplies the load's intensity (none: uniform).
    pub profile: Option<FieldFunction>,
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
    /// The formats frames are written in (when `frames`).
    pub formats: FrameFormats,
    /// Steps (load levels) between two checkpoints; `None`: no checkpoints.
    pub checkpoint_every: Option<usize>,
}

/// The formats of output frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameFormats {
    /// VTU frames and the `.pvd` collection.
    pub vtu: bool,
    /// One OBJ file per frame.
    pub obj: bool,
    /// One PLY file per frame.
    pub ply: bool,
    /// One USD stage with time samples.
    pub usd: bool,
}

/// Frictional contact of a scene: which shells take part, the obstacles, friction coefficients and
/// the barrier parameters (the model of `cosserat-contact`: an IPC log barrier on the gap
/// `d − (h_a + h_b)` with width `d̂`, lagged smoothed Coulomb friction, CCD-limited Newton steps).
#[derive(Debug, Clone)]
pub struct ContactSpec {
    /// Barrier stiffness `κ` \[J/m²\] (energy per pair `−κ (g − d̂)² ln(g/d̂)`).
    pub stiffness: f64,
    /// Barrier width `d̂` \[m\]: pairs interact while their gap is below it.
    pub barrier_width: f64,
    /// Stick–slide velocity threshold `ε_v` \[m/s\] of the smoothed friction (default 0.1).
    pub stick_velocity: f64,
    /// Project each pair's barrier Hessian onto the positive semi-definite cone (default true).
    pub project_pd: bool,
    /// CCD: fraction of a pair's gap that a Newton step may close at most (default 0.1).
    pub min_gap_fraction: f64,
    /// The shells that take part (self-contact included), with their contact thickness.
    pub surfaces: Vec<ContactSurfaceSpec>,
    /// Triangle meshes whose vertices are not unknowns: static or moved by a script.
    pub obstacles: Vec<ObstacleSpec>,
    /// Friction coefficients between bodies; pairs not listed are frictionless.
    pub friction: Vec<FrictionSpec>,
}

/// A triangle mesh: vertex positions \[m\] and triangles as vertex triples.
pub type SurfaceMesh = (Vec<Vector3<f64>>, Vec<[usize; 3]>);

/// A shell that takes part in contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSurfaceSpec {
    /// Index of the shell in [`SceneSpec::shells`].
    pub shell: usize,
    /// Contact thickness \[m\]: two bodies keep the sum of their thicknesses apart.
    pub thickness: f64,
}

/// A contact obstacle: a triangle mesh that is not simulated.
#[derive(Debug, Clone)]
pub struct ObstacleSpec {
    /// Name (friction entries refer to it).
    pub name: String,
    /// Vertex positions at rest (at `t = 0` before any motion) \[m\].
    pub positions: Vec<Vector3<f64>>,
    /// Triangles as vertex triples.
    pub triangles: Vec<[usize; 3]>,
    /// Contact thickness \[m\].
    pub thickness: f64,
    /// Scripted rigid motion of the rest positions, evaluated at the end of each step; `None` is a
    /// static obstacle.
    pub motion: Option<MotionSpec>,
}

impl ObstacleSpec {
    /// The closed surface of an axis-aligned box with centre `center` and full edge lengths `size`
    /// \[m\]: 8 vertices and 12 triangles, outward normals.
    pub fn box_mesh(center: Vector3<f64>, size: Vector3<f64>) -> SurfaceMesh {
        let half = size * 0.5;
        // Vertex k has the sign pattern of its bits: bit 0 → x, bit 1 → y, bit 2 → z.
        let positions = (0..8)
            .map(|k| {
                let s = |bit: usize| if k & (1 << bit) != 0 { 1.0 } else { -1.0 };
                center + Vector3::new(s(0) * half.x, s(1) * half.y, s(2) * half.z)
            })
            .collect();
        let triangles = vec![
            // −z, +z
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
            // −y, +y
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            // −x, +x
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
        ];
        (positions, triangles)
    }

    /// The positions at time `t` (the motion applied to the rest positions; the rest positions for a
    /// static obstacle).
    pub fn positions_at(&self, t: f64) -> Vec<Vector3<f64>> {
        match &self.motion {
            None => self.positions.clone(),
            Some(m) => {
                let map = m.map_at(t);
                self.positions.iter().map(map).collect()
            }
        }
    }
}

/// A body of the contact model, for friction coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactBody {
    /// A shell, by index in [`SceneSpec::shells`].
    Shell(usize),
    /// An obstacle, by index in [`ContactSpec::obstacles`].
    Obstacle(usize),
}

/// A friction coefficient between two bodies (the same body twice: self-friction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSpec {
    /// The two bodies.
    pub bodies: [ContactBody; 2],
    /// The Coulomb coefficient `μ` \[-\].
    pub coefficient: f64,
}

//! The `[contact]` section of a scene file: barrier parameters, the shells that take part, obstacles
//! and friction coefficients.
//!
//! ```toml
//! [contact]
//! stiffness = 10.0          # κ [J/m²]
//! barrier_width = 1e-3      # d̂ [m]
//! thickness = 5e-4          # default contact thickness of shells and obstacles [m]
//! stick_velocity = 0.01     # ε_v [m/s]
//!
//! [[contact.obstacle]]
//! name = "floor"
//! box = { center = [0.0, 0.0, -0.011], size = [2.0, 2.0, 0.01] }
//!
//! [[contact.obstacle]]
//! name = "weight"
//! mesh = { path = "box.obj", transform = { center = true, height = 0.03, translate = [0.0, 0.0, 0.5] } }
//! motion = { translate = [0.0, 0.0, "-0.4*ramp(t, 1, 2)"] }
//!
//! [[contact.friction]]
//! between = ["shell", "floor"]
//! mu = 1.0
//! ```
//!
//! Without `[[contact.surface]]` tables every shell takes part with the default thickness.

use super::{BoxSection, MeshSection, MotionSection, ShellRef};
use serde::Deserialize;

/// `\[contact\]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// Barrier stiffness `κ` \[J/m²\] (energy per pair; not the reference code's cubic penalty).
    pub stiffness: f64,
    /// Barrier width `d̂` \[m\]: pairs interact while their gap (distance minus the thicknesses) is
    /// below it.
    pub barrier_width: f64,
    /// Default contact thickness of shells and obstacles \[m\] (required unless every surface and
    /// obstacle gives its own).
    pub thickness: Option<f64>,
    /// Stick–slide velocity threshold `ε_v` \[m/s\] (default 0.1).
    pub stick_velocity: Option<f64>,
    /// Project pair Hessians of the barrier onto the PSD cone (default `true`).
    pub project_pd: Option<bool>,
    /// CCD: the smallest fraction of its gap a pair keeps along a Newton step (default 0.1).
    pub min_gap_fraction: Option<f64>,
    /// The shells that take part (default: all, with the default thickness).
    pub surface: Option<Vec<ContactSurfaceSection>>,
    /// Obstacles.
    pub obstacle: Option<Vec<ObstacleSection>>,
    /// Friction coefficients (default: none).
    pub friction: Option<Vec<FrictionSection>>,
}

/// `[\[contact.surface\]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSurfaceSection {
    /// The shell (default the only one).
    pub shell: Option<ShellRef>,
    /// Contact thickness \[m\] (default `contact.thickness`).
    pub thickness: Option<f64>,
}

/// `[\[contact.obstacle\]]`: `box = { center, size }` or `mesh = { … }` (a generator or an OBJ
/// `path`, with the shaping steps of a shell mesh; always flat triangles).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSection {
    /// Name, unique among shells and obstacles.
    pub name: String,
    /// A closed box (12 triangles).
    #[serde(rename = "box")]
    pub aabb: Option<BoxSection>,
    /// A triangle mesh.
    pub mesh: Option<MeshSection>,
    /// Contact thickness \[m\] (default `contact.thickness`).
    pub thickness: Option<f64>,
    /// Scripted rigid motion of the obstacle, evaluated at the end of each step (default: static).
    pub motion: Option<MotionSection>,
}

/// `[\[contact.friction\]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionSection {
    /// Two body names (shells or obstacles); the same name twice sets self-friction.
    pub between: [String; 2],
    /// The Coulomb coefficient `μ` (≥ 0).
    pub mu: f64,
}

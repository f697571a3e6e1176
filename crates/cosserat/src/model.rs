//! The mechanical model of a scene: the Cosserat shells of `cosserat-assembly`, or one of the comparison
//! models (Kirchhoff–Love, volumetric micropolar). Each builds its own incremental potential on the
//! shared parts of `cosserat-assembly` (inertia, loads, boundary terms) and answers, through the
//! [`Model`] trait, what a run needs from it; the simulation knows no model beyond this trait.

use crate::error::SimulationError;
use crate::placement::ShellPlacement;
use cosserat_assembly::{IncrementalPotential, SystemOptions, SystemState};
use cosserat_io::{ModelRecord, VtuFrame};
use cosserat_scene::spec::{ModelKind, SceneSpec};
use cosserat_solver::ScriptError;
use nalgebra::Vector3;

/// What a run needs from a mechanical model.
pub trait Model: Send {
    /// The model for the run record.
    fn record(&self) -> ModelRecord;

    /// The displacement and rotation element names for the run record (`"tri6"`, `"tri3"`, ...).
    fn element_names(&self) -> (String, String);

    /// Where each shell of the scene is in the system, in the scene's shell order.
    fn placements(&self) -> &[ShellPlacement];

    /// Rest positions of all displacement nodes of the system \[m\].
    fn rest_positions(&self) -> &[Vector3<f64>];

    /// The contact triangles of shell `shell` over system displacement nodes, or `None` if the model
    /// cannot take part in contact.
    fn contact_triangles(&self, shell: usize) -> Option<Vec<[usize; 3]>>;

    /// Quadrature points with a curved rest geometry (the curved-shell terms run there).
    fn n_curved_points(&self) -> usize {
        0
    }

    /// Number of cells of the model's meshes.
    fn n_cells(&self) -> usize;

    /// Sets the scene's rest fields (rest curvature, rest-metric growth) for the step from `t` to
    /// `t + dt`.
    ///
    /// # Errors
    /// [`ScriptError`] naming the entry, its expression and the point where a value is not finite.
    fn apply_rest_fields(&mut self, potential: &mut IncrementalPotential, t: f64, dt: f64) -> Result<(), ScriptError>;

    /// The output frame of a state at time `t`.
    fn frame(&self, state: &SystemState, t: f64) -> VtuFrame;
}

/// A model with the potential it built.
pub struct BuiltModel {
    /// The incremental potential, with the model's elastic terms, inertia and loads.
    pub potential: IncrementalPotential,
    /// The model.
    pub model: Box<dyn Model>,
}

/// Builds the model of a scene: the comparison models run a scene of one shell (checked when the scene
/// was read); otherwise the shells are Cosserat shells.
///
/// # Errors
/// Invalid meshes or materials, named by shell.
pub fn build(spec: &SceneSpec, options: &SystemOptions) -> Result<BuiltModel, SimulationError> {
    match spec.shells.first().map(|s| s.model) {
        Some(ModelKind::KirchhoffLove(settings)) => crate::kl_model::build(spec, settings, options),
        Some(ModelKind::MicropolarVolume { layers }) => crate::volume_model::build(spec, layers, options),
        _ => crate::cosserat_model::build(spec, options),
    }
}

/// Writes the scene's initial positions (a pose other than the rest pose) into the state, shell by
/// shell, where each shell is a block of the system's displacement nodes.
pub(crate) fn apply_initial_positions(spec: &SceneSpec, placements: &[ShellPlacement], state: &mut SystemState) {
    for (shell, placement) in spec.shells.iter().zip(placements) {
        if let Some(x0) = &shell.initial_positions {
            let nodes = placement.disp.nodes(&(0..x0.len()).collect::<Vec<_>>());
            for (&i, x) in nodes.iter().zip(x0) {
                state.x[i] = *x;
            }
        }
    }
}

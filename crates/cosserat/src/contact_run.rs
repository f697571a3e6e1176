//! Contact in a simulation: the contact term built from a scene's [`ContactSpec`] and the shells'
//! layouts, and the statistics a run collects about it (active pairs, the smallest gap reached, the
//! time spent in contact energies, broad phases and CCD) for `summary.json`.
//!
//! Shells contribute their displacement elements as flat triangles: a Tri3 element as it is, a Tri6
//! element split into four through its mid-edge nodes (node order: corners 0, 1, 2, then mid-edges
//! 3 = (0, 1), 4 = (1, 2), 5 = (2, 0)). Surface ids are the shell indices, obstacle ids follow them,
//! so friction coefficients between named bodies map onto the term's friction table.

use crate::error::SimulationError;
use cosserat_assembly::{DofLayout, IncrementalPotential, ShellLayout, SystemState};
use cosserat_contact::{ContactParameters, ContactSurface, ContactTerm, Obstacle};
use cosserat_scene::spec::{ContactBody, ContactSpec};
use nalgebra::Vector3;
use serde_json::json;

/// The contact term at `index` of the potential's extra terms, with the start-of-step state and the
/// layout beside it (disjoint borrows of the potential's parts), or `None` if that term is not one.
pub(crate) fn contact_parts(
    potential: &mut IncrementalPotential,
    index: usize,
) -> Option<(&mut ContactTerm, &SystemState, &DofLayout)> {
    let parts = &mut potential.parts;
    let term = parts.extra.get_mut(index)?.as_any_mut()?.downcast_mut::<ContactTerm>()?;
    Some((term, &parts.state, &parts.layout))
}

/// The flat contact triangles of a shell in global displacement-node indices: Tri3 elements as they
/// are, Tri6 elements split into four through their mid-edge nodes.
pub fn surface_triangles(layout: &ShellLayout) -> Vec<[usize; 3]> {
    let mut out = Vec::with_capacity(4 * layout.disp_elements.len());
    for el in &layout.disp_elements {
        if el.len() == 6 {
            out.extend([
                [el[0], el[3], el[5]],
                [el[3], el[1], el[4]],
                [el[5], el[4], el[2]],
                [el[3], el[4], el[5]],
            ]);
        } else {
            out.push([el[0], el[1], el[2]]);
        }
    }
    out
}

/// The contact term of a scene: surfaces of the listed shells (over the nodes of `layouts`, at rest
/// positions `rest`), the obstacles at their rest positions, and the friction table.
///
/// # Errors
/// Invalid parameters or meshes, named by [`cosserat_contact::ContactError`].
pub fn build_contact_term(
    spec: &ContactSpec,
    layouts: &[ShellLayout],
    rest: &[Vector3<f64>],
) -> Result<ContactTerm, SimulationError> {
    let n_shells = layouts.len();
    let surfaces: Vec<ContactSurface> = spec
        .surfaces
        .iter()
        .map(|s| ContactSurface {
            id: s.shell,
            triangles: surface_triangles(&layouts[s.shell]),
            thickness: s.thickness,
        })
        .collect();
    let obstacles: Vec<Obstacle> = spec
        .obstacles
        .iter()
        .enumerate()
        .map(|(o, ob)| Obstacle {
            id: n_shells + o,
            positions: ob.positions_at(0.0),
            triangles: ob.triangles.clone(),
            thickness: ob.thickness,
        })
        .collect();
    let mut params = ContactParameters::new(spec.stiffness, spec.barrier_width);
    params.stick_velocity = spec.stick_velocity;
    params.project_pd = spec.project_pd;
    params.ccd.min_gap_fraction = spec.min_gap_fraction;
    let id = |b: ContactBody| match b {
        ContactBody::Shell(s) => s,
        ContactBody::Obstacle(o) => n_shells + o,
    };
    for f in &spec.friction {
        params.friction.set(id(f.bodies[0]), id(f.bodies[1]), f.coefficient)?;
    }
    Ok(ContactTerm::try_new(surfaces, obstacles, params, rest)?)
}

/// Contact statistics over the committed states of a run, from the term's counters after each step.
///
/// Newton's last evaluation of a step is at its converged state, and the step's candidate pairs cover
/// every pair within the barrier there (the time stepper solves again otherwise), so the counters of
/// that evaluation give the active pairs and the smallest gap of the committed state without another
/// broad phase.
#[derive(Debug, Clone)]
pub struct ContactMonitor {
    steps: usize,
    active_sum: usize,
    active_max: usize,
    min_gap: f64,
}

impl Default for ContactMonitor {
    fn default() -> Self {
        Self {
            steps: 0,
            active_sum: 0,
            active_max: 0,
            min_gap: f64::INFINITY,
        }
    }
}

impl ContactMonitor {
    /// Records the state a step converged to, from the term's counters.
    pub fn record(&mut self, term: &ContactTerm) {
        let s = term.stats();
        self.steps += 1;
        self.active_sum += s.n_active;
        self.active_max = self.active_max.max(s.n_active);
        if s.min_gap.is_finite() {
            self.min_gap = self.min_gap.min(s.min_gap);
        }
    }

    /// The smallest gap (distance minus the thicknesses) reached in a committed state \[m\] (`+∞`
    /// while no pair was a candidate).
    pub fn min_gap(&self) -> f64 {
        self.min_gap
    }

    /// The most pairs within the barrier in a committed state.
    pub fn max_active_pairs(&self) -> usize {
        self.active_max
    }

    /// The summary entry: counters of the term and of the monitor; `step_seconds` is the time of all
    /// steps, for the contact share.
    pub fn summary(&self, term: &ContactTerm, step_seconds: f64) -> serde_json::Value {
        let s = term.stats();
        let energy = s.energy_time.as_secs_f64();
        let ccd = s.ccd_time.as_secs_f64();
        let broad = s.broad_phase_time.as_secs_f64();
        let share = |x: f64| if step_seconds > 0.0 { x / step_seconds } else { 0.0 };
        let mesh = term.mesh();
        json!({
            "n_vertices": mesh.n_vertices(),
            "n_triangles": mesh.triangles().len(),
            "n_edges": mesh.edges().len(),
            "energy_seconds": energy,
            "ccd_seconds": ccd,
            "broad_phase_seconds": broad,
            "share_of_step": share(energy + ccd + broad),
            "energy_share": share(energy),
            "ccd_share": share(ccd),
            "broad_phase_share": share(broad),
            "n_evaluations": s.n_evaluations,
            "n_ccd_queries": s.n_ccd_queries,
            "mean_active_pairs": if self.steps > 0 { self.active_sum as f64 / self.steps as f64 } else { 0.0 },
            "max_active_pairs": self.active_max,
            "min_gap": if self.min_gap.is_finite() { json!(self.min_gap) } else { json!(null) },
        })
    }
}

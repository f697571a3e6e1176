//! Scenes with the Kirchhoff–Love comparison model (`[material] model = "kirchhoff_love"`): the system
//! of `cosserat-kl` built from a scene's single Tri3 shell, with the layout the scripts, probes and
//! contact of a Cosserat run use, and the output frames of a shell without rotations.
//!
//! The Kirchhoff–Love system has vertex velocities as its only unknowns (`n_rot_nodes = 0`), so the
//! layout handed to the run has no rotation nodes; its displacement elements are the Tri3 faces, so a
//! contact term sees the same triangles as for a Tri3 Cosserat shell. Frames carry displacement,
//! velocity and, as `director3`, the area-weighted vertex normal (the Kirchhoff–Love director).

use crate::error::SimulationError;
use cosserat_assembly::term::{Evaluation, NodeRotations};
use cosserat_assembly::{ElementPair, IncrementalPotential, ShellLayout, System, SystemOptions, SystemState};
use cosserat_kl::{HyperelasticModel, KlMaterial, KlShell, RestVolume, build_kl_system};
use cosserat_scene::output::{DataArray, VtuFrame};
use cosserat_scene::spec::{HyperelasticLaw, KlRestVolume, KlSettings, ShellSpec};
use nalgebra::Vector3;

/// The `cosserat-kl` material of a scene's hyperelastic law.
pub fn hyperelastic_model(law: HyperelasticLaw) -> HyperelasticModel {
    match law {
        HyperelasticLaw::NeoHookean => HyperelasticModel::NeoHookean,
        _ => HyperelasticModel::StVenantKirchhoff,
    }
}

/// What a run needs beyond the system to write frames of a Kirchhoff–Love shell.
#[derive(Debug, Clone)]
pub struct KlModel {
    triangles: Vec<[usize; 3]>,
    rest: Vec<Vector3<f64>>,
    law: HyperelasticLaw,
}

/// Builds the Kirchhoff–Love system of a scene's shell, with a layout for scripts, probes and contact.
///
/// # Errors
/// [`SimulationError::Setup`] naming the shell when `cosserat-kl` rejects the mesh or the material
/// (e.g. a shell thicker than twice a rest radius of curvature).
pub fn build(
    shell: &ShellSpec,
    settings: KlSettings,
    options: &SystemOptions,
) -> Result<(System, KlModel), SimulationError> {
    let mesh = &shell.mesh.corners;
    let p = &shell.material;
    let law = settings.law;
    let mut kl = KlShell::new(
        KlMaterial::new(hyperelastic_model(law), p.youngs_modulus, p.poisson_ratio),
        p.thickness,
        p.density,
    );
    kl.damping = shell.damping;
    kl.thickness_rule = kl.thickness_rule.with_rest_volume(match settings.rest_volume {
        KlRestVolume::MidSurface => RestVolume::MidSurface,
        _ => RestVolume::Exact,
    });
    let system = build_kl_system(mesh, &kl, Vec::new(), options)
        .map_err(|e| SimulationError::Setup(format!("shell `{}` (Kirchhoff–Love): {e}", shell.name)))?;
    let n = mesh.n_nodes();
    let element_areas = mesh
        .elements
        .iter()
        .map(|t| {
            0.5 * (mesh.nodes[t[1]] - mesh.nodes[t[0]])
                .cross(&(mesh.nodes[t[2]] - mesh.nodes[t[0]]))
                .norm()
        })
        .collect();
    let layout = ShellLayout {
        name: shell.name.clone(),
        pair: ElementPair::Tri3Tri3,
        disp_nodes: 0..n,
        rot_nodes: 0..0,
        points: 0..0,
        disp_elements: mesh.elements.iter().map(|t| t.to_vec()).collect(),
        rot_elements: Vec::new(),
        rest_disp_positions: mesh.nodes.clone(),
        rest_rot_positions: Vec::new(),
        rest_point_positions: Vec::new(),
        rot_to_disp: Vec::new(),
        element_areas,
        active_terms: system.active_terms.clone(),
        n_curved_points: 0,
    };
    let model = KlModel {
        triangles: mesh.elements.clone(),
        rest: mesh.nodes.clone(),
        law,
    };
    Ok((
        System {
            potential: system.potential,
            shells: vec![layout],
        },
        model,
    ))
}

impl KlModel {
    /// The scene-file name of the law, for the summary.
    pub fn law_name(&self) -> &'static str {
        match self.law {
            HyperelasticLaw::NeoHookean => "neo_hookean",
            _ => "stvk",
        }
    }

    /// The frame of a state: the Tri3 surface with displacement, velocity and the vertex normal.
    pub fn frame(&self, state: &SystemState, t: f64) -> VtuFrame {
        let n = self.rest.len();
        let mut normals = vec![Vector3::zeros(); n];
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|v| state.x[v]);
            // Twice the area times the unit normal: area weighting.
            let w = (b - a).cross(&(c - a));
            for &v in tri {
                normals[v] += w;
            }
        }
        let points: Vec<[f64; 3]> = state.x[..n].iter().map(|x| [x.x, x.y, x.z]).collect();
        let displacement: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let d = state.x[i] - self.rest[i];
                [d.x, d.y, d.z]
            })
            .collect();
        let velocity: Vec<[f64; 3]> = state.v[..n].iter().map(|v| [v.x, v.y, v.z]).collect();
        let director: Vec<[f64; 3]> = normals
            .iter()
            .map(|m| {
                let u = m.try_normalize(0.0).unwrap_or_else(Vector3::z);
                [u.x, u.y, u.z]
            })
            .collect();
        let mut frame = VtuFrame::new(points, self.triangles.clone(), t);
        frame.point_data = vec![
            DataArray::vectors("displacement", &displacement),
            DataArray::vectors("velocity", &velocity),
            DataArray::vectors("director3", &director),
        ];
        frame
    }
}

/// The elastic energy \[J\] of the start-of-step state held by the first extra term (the model's
/// elastic term), for models whose energy is not in `parts.shells`.
///
/// # Errors
/// A non-finite energy, named by the term.
pub fn extra_elastic_energy(potential: &IncrementalPotential) -> Result<f64, SimulationError> {
    let parts = &potential.parts;
    let Some(term) = parts.extra.first() else {
        return Ok(0.0);
    };
    let u = vec![0.0; potential.n_dofs()];
    let rotations =
        NodeRotations::Matrices(parts.state.q.iter().map(cosserat_geometry::rotation::rotation_matrix).collect());
    let eval = Evaluation {
        state: &parts.state,
        layout: &parts.layout,
        u: &u,
        dt: potential.dt,
        rotations: &rotations,
        parallelism: potential.parallelism,
    };
    Ok(term.value(&eval)?)
}

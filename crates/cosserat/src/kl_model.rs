//! Scenes with the Kirchhoff–Love comparison model (`[material] model = "kirchhoff_love"`): the system
//! of `cosserat-kl` built from a scene's single Tri3 shell, placed for the scripts, probes and
//! contact of a Cosserat run, and the output frames of a shell without rotations.
//!
//! The Kirchhoff–Love system has vertex velocities as its only unknowns (`n_rot_nodes = 0`), so its
//! placement has no rotation nodes; its contact triangles are the Tri3 faces, as for a Tri3 Cosserat
//! shell. Frames carry displacement, velocity and, as `director3`, the area-weighted vertex normal (the
//! Kirchhoff–Love director).

use crate::error::SimulationError;
use crate::model::{BuiltModel, Model, apply_initial_positions};
use crate::placement::{NodeMap, ShellPlacement};
use cosserat_assembly::{IncrementalPotential, SystemOptions, SystemState};
use cosserat_io::{DataArray, ModelRecord, VtuFrame};
use cosserat_kl::{HyperelasticModel, KlMaterial, KlShell, RestVolume, build_kl_system};
use cosserat_scene::spec::{HyperelasticLaw, KlRestVolume, KlSettings, SceneSpec};
use cosserat_solver::ScriptError;
use nalgebra::Vector3;

/// The `cosserat-kl` material of a scene's hyperelastic law.
pub fn hyperelastic_model(law: HyperelasticLaw) -> HyperelasticModel {
    match law {
        HyperelasticLaw::NeoHookean => HyperelasticModel::NeoHookean,
        _ => HyperelasticModel::StVenantKirchhoff,
    }
}

/// A Kirchhoff–Love shell in a system.
#[derive(Debug, Clone)]
pub struct KlModel {
    triangles: Vec<[usize; 3]>,
    rest: Vec<Vector3<f64>>,
    law: HyperelasticLaw,
    placements: Vec<ShellPlacement>,
}

/// Builds the Kirchhoff–Love system of a scene's single shell, at its initial positions.
///
/// # Errors
/// [`SimulationError::Setup`] naming the shell when `cosserat-kl` rejects the mesh or the material
/// (e.g. a shell thicker than twice a rest radius of curvature).
pub fn build(spec: &SceneSpec, settings: KlSettings, options: &SystemOptions) -> Result<BuiltModel, SimulationError> {
    let shell = &spec.shells[0];
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
    let system = build_kl_system(mesh, &kl, options)
        .map_err(|e| SimulationError::Setup(format!("shell `{}` (Kirchhoff–Love): {e}", shell.name)))?;
    let placements = vec![ShellPlacement {
        name: shell.name.clone(),
        disp: NodeMap::Offset(0),
        rot: NodeMap::Offset(0),
        rest_disp: mesh.nodes.clone(),
        rest_rot: Vec::new(),
        disp_elements: mesh.elements.iter().map(|t| t.to_vec()).collect(),
        rot_elements: Vec::new(),
    }];
    let mut potential = system.potential;
    apply_initial_positions(spec, &placements, &mut potential.parts.state);
    let model = KlModel {
        triangles: mesh.elements.clone(),
        rest: mesh.nodes.clone(),
        law,
        placements,
    };
    Ok(BuiltModel {
        potential,
        model: Box::new(model),
    })
}

impl Model for KlModel {
    fn record(&self) -> ModelRecord {
        ModelRecord::KirchhoffLove {
            law: match self.law {
                HyperelasticLaw::NeoHookean => "neo_hookean",
                _ => "stvk",
            }
            .into(),
        }
    }

    fn element_names(&self) -> (String, String) {
        ("tri3".into(), "-".into())
    }

    fn placements(&self) -> &[ShellPlacement] {
        &self.placements
    }

    fn rest_positions(&self) -> &[Vector3<f64>] {
        &self.rest
    }

    fn contact_triangles(&self, _shell: usize) -> Option<Vec<[usize; 3]>> {
        Some(self.triangles.clone())
    }

    fn n_cells(&self) -> usize {
        self.triangles.len()
    }

    /// A Kirchhoff–Love scene has no rest fields (refused when the scene is read).
    fn apply_rest_fields(&mut self, _: &mut IncrementalPotential, _: f64, _: f64) -> Result<(), ScriptError> {
        Ok(())
    }

    /// The Tri3 surface with displacement, velocity and, as `director3`, the area-weighted vertex
    /// normal (the Kirchhoff–Love director).
    fn frame(&self, state: &SystemState, t: f64) -> VtuFrame {
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

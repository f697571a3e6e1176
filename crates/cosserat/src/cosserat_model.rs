//! The Cosserat shells of a scene (`[material] model = "plate" | "shell"`): the system of
//! `cosserat-assembly`, the scene's rest fields written into the shells' energies before every step, and
//! frames sampled on the displacement elements ([`crate::frames::OutputMesh`]).

use crate::error::SimulationError;
use crate::frames::OutputMesh;
use crate::model::{BuiltModel, Model, apply_initial_positions};
use crate::placement::{NodeMap, ShellPlacement};
use cosserat_assembly::{
    ElementPair, IncrementalPotential, ShellInput, ShellLayout, SystemOptions, SystemState, build_system,
};
use cosserat_geometry::Num;
use cosserat_io::{ModelRecord, VtuFrame};
use cosserat_scene::spec::{FieldFunction, RestFieldSpec, SceneSpec, Timing};
use cosserat_solver::ScriptError;
use nalgebra::{Matrix3, Vector3};

/// Cosserat shells in a system.
pub struct CosseratModel {
    layouts: Vec<ShellLayout>,
    placements: Vec<ShellPlacement>,
    rest_positions: Vec<Vector3<f64>>,
    output: OutputMesh,
    rest_fields: Vec<RestFieldScript>,
}

/// The rest fields of one shell.
#[derive(Debug)]
struct RestFieldScript {
    shell: usize,
    points: Vec<Vector3<f64>>,
    curvature: Vec<(usize, usize, FieldFunction)>,
    frame: Option<Matrix3<f64>>,
    growth: Option<FieldFunction>,
    timing: Timing,
    time_dependent: bool,
    applied: bool,
}

/// The growth factor `exp(2 s)` and the rest curvature of one point, as the shell term takes them.
type RestFieldValues = (Option<f64>, Option<Matrix3<f64>>);

/// Builds the Cosserat system of a scene's shells, at their initial positions.
///
/// # Errors
/// Invalid meshes or materials (named by shell), several rest-field tables of one shell that cannot be
/// merged.
pub fn build(spec: &SceneSpec, options: &SystemOptions) -> Result<BuiltModel, SimulationError> {
    let inputs: Vec<ShellInput> = spec
        .shells
        .iter()
        .map(|s| ShellInput {
            name: s.name.clone(),
            mesh: s.mesh.clone(),
            pair: s.pair,
            material: s.material,
            rest: s.rest,
            quadrature: s.quadrature,
            damping: s.damping,
            angular_inertia_density: s.angular_inertia_density,
        })
        .collect();
    let system = build_system(&inputs, options)?;
    let mut potential = system.potential;
    for s in &mut potential.parts.shells {
        s.set_project_pd(spec.solver.project_pd);
    }
    let layouts = system.shells;
    let placements: Vec<ShellPlacement> = layouts.iter().map(placement).collect();
    apply_initial_positions(spec, &placements, &mut potential.parts.state);
    let model = CosseratModel {
        rest_positions: layouts.iter().flat_map(|l| l.rest_disp_positions.iter().copied()).collect(),
        output: OutputMesh::new(&layouts, spec.output.subdivision),
        rest_fields: rest_field_scripts(&spec.rest_fields, &layouts)?,
        placements,
        layouts,
    };
    Ok(BuiltModel {
        potential,
        model: Box::new(model),
    })
}

/// Where a Cosserat shell's nodes are: a block of displacement nodes and one of rotation nodes.
fn placement(layout: &ShellLayout) -> ShellPlacement {
    let local = |elements: &[Vec<usize>], start: usize| -> Vec<Vec<usize>> {
        elements.iter().map(|e| e.iter().map(|&i| i - start).collect()).collect()
    };
    ShellPlacement {
        name: layout.name.clone(),
        disp: NodeMap::Offset(layout.disp_nodes.start),
        rot: NodeMap::Offset(layout.rot_nodes.start),
        rest_disp: layout.rest_disp_positions.clone(),
        rest_rot: layout.rest_rot_positions.clone(),
        disp_elements: local(&layout.disp_elements, layout.disp_nodes.start),
        rot_elements: local(&layout.rot_elements, layout.rot_nodes.start),
    }
}

/// One script per shell: entries of several rest-field tables on the same shell add up.
fn rest_field_scripts(
    specs: &[RestFieldSpec],
    layouts: &[ShellLayout],
) -> Result<Vec<RestFieldScript>, SimulationError> {
    let mut scripts: Vec<RestFieldScript> = Vec::new();
    for r in specs {
        let new = RestFieldScript {
            shell: r.shell,
            points: layouts[r.shell].rest_point_positions.clone(),
            curvature: r.curvature.clone(),
            frame: r.curvature_frame,
            growth: r.growth.clone(),
            timing: r.timing,
            time_dependent: r.curvature.iter().any(|c| c.2.is_time_dependent())
                || r.growth.as_ref().is_some_and(|g| g.is_time_dependent()),
            applied: false,
        };
        match scripts.iter_mut().find(|s| s.shell == r.shell) {
            None => scripts.push(new),
            Some(existing) => {
                // A table without curvature entries (growth alone) has no frame to disagree with.
                let frames_differ =
                    !existing.curvature.is_empty() && !new.curvature.is_empty() && existing.frame != new.frame;
                if frames_differ || existing.timing != new.timing || (existing.growth.is_some() && new.growth.is_some())
                {
                    return Err(SimulationError::Setup(format!(
                        "shell {}: several rest fields with different frames, timings or growth; merge them into one",
                        r.shell
                    )));
                }
                if existing.curvature.is_empty() {
                    existing.frame = new.frame;
                }
                existing.curvature.extend(new.curvature);
                existing.growth = existing.growth.take().or(new.growth);
                existing.time_dependent |= new.time_dependent;
            }
        }
    }
    Ok(scripts)
}

impl RestFieldScript {
    /// The growth factor and the rest curvature at every point at time `tau`.
    fn values(&self, tau: f64) -> Result<Vec<RestFieldValues>, ScriptError> {
        let check = |v: f64, what: &dyn Fn() -> String, f: &FieldFunction, x: &Vector3<f64>| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(ScriptError(format!(
                    "shell {}: {} `{}` is {v} at t = {}, X = ({}, {}, {})",
                    self.shell,
                    what(),
                    f.description(),
                    Num(tau),
                    Num(x.x),
                    Num(x.y),
                    Num(x.z)
                )))
            }
        };
        self.points
            .iter()
            .map(|x| {
                let g = match &self.growth {
                    Some(f) => Some((2.0 * check(f.eval(x, tau), &|| "rest-metric growth".into(), f, x)?).exp()),
                    None => None,
                };
                let c = if self.curvature.is_empty() {
                    None
                } else {
                    let mut m = Matrix3::zeros();
                    for (i, j, f) in &self.curvature {
                        m[(*i, *j)] += check(f.eval(x, tau), &|| format!("rest curvature ({i}, {j})"), f, x)?;
                    }
                    Some(self.frame.map_or(m, |q| q.transpose() * m * q))
                };
                Ok((g, c))
            })
            .collect()
    }
}

impl Model for CosseratModel {
    fn record(&self) -> ModelRecord {
        ModelRecord::Cosserat
    }

    fn element_names(&self) -> (String, String) {
        let name = |k: cosserat_fem::ElementKind| format!("{k:?}").to_lowercase();
        let pairs: Vec<ElementPair> = self.layouts.iter().map(|l| l.pair).collect();
        let mut d: Vec<String> = pairs.iter().map(|p| name(p.displacement())).collect();
        let mut r: Vec<String> = pairs.iter().map(|p| name(p.rotation())).collect();
        d.dedup();
        r.dedup();
        (d.join(","), r.join(","))
    }

    fn placements(&self) -> &[ShellPlacement] {
        &self.placements
    }

    fn rest_positions(&self) -> &[Vector3<f64>] {
        &self.rest_positions
    }

    fn contact_triangles(&self, shell: usize) -> Option<Vec<[usize; 3]>> {
        Some(crate::contact_run::surface_triangles(
            &self.layouts[shell].disp_elements,
        ))
    }

    fn n_curved_points(&self) -> usize {
        self.layouts.iter().map(|l| l.n_curved_points).sum()
    }

    fn n_cells(&self) -> usize {
        self.layouts.iter().map(|l| l.disp_elements.len()).sum()
    }

    fn apply_rest_fields(&mut self, potential: &mut IncrementalPotential, t: f64, dt: f64) -> Result<(), ScriptError> {
        for rf in &mut self.rest_fields {
            if rf.applied && !rf.time_dependent {
                continue;
            }
            let tau = match rf.timing {
                Timing::StartOfStep => t,
                Timing::EndOfStep => t + dt,
            };
            let values = rf.values(tau)?;
            potential.parts.shells[rf.shell].set_rest_fields_dyn(&mut |p| values[p]);
            rf.applied = true;
        }
        Ok(())
    }

    fn frame(&self, state: &SystemState, t: f64) -> VtuFrame {
        self.output.frame(&self.layouts, state, t)
    }
}

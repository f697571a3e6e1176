//! Scenes with the volumetric micropolar comparison model (`[material] model = "micropolar_volume"`):
//! the shell's flat Tri3 grid (its mid-surface) extruded into a slab of Tet4 elements and simulated with
//! `cosserat-volume`, typically with the conjugate-gradient solver (`[solver] linear_solver = "cg"`), as
//! the paper's Lotus "Tet4" row.
//!
//! The scene is written as for a shell: regions, probes and rest fields refer to the mid-surface. Its
//! placement maps each vertex to the column of slab nodes above it (all layers), so a boundary
//! condition holds the whole column, a load is shared by it, a probe reports the column's mean (the
//! mid-surface point), and a rest field is evaluated at the rest centroid of every tetrahedron, between
//! steps, through the volume term's [`RestCurvature`] handle. Frames show the mid-surface: the grid's
//! triangles over the column means of positions, velocities and (quaternion-averaged) rotations.

use crate::error::SimulationError;
use crate::frames::PointColumns;
use crate::model::{BuiltModel, Model};
use crate::placement::{NodeMap, ShellPlacement};
use cosserat_assembly::{IncrementalPotential, SystemOptions, SystemState};
use cosserat_geometry::Num;
use cosserat_geometry::rotation::{rotation_matrix, same_hemisphere};
use cosserat_io::{ModelRecord, VtuFrame};
use cosserat_scene::spec::{FieldFunction, SceneSpec, ShellSpec, Timing};
use cosserat_solver::ScriptError;
use cosserat_volume::grid::PlanarGrid;
use cosserat_volume::mesh::slab;
use cosserat_volume::{RestCurvature, VolumeInput, build_volume_system};
use nalgebra::{Matrix3, Quaternion, Vector3};

/// The rest fields of a volumetric scene, evaluated at the element centroids.
#[derive(Debug)]
struct RestFieldScript {
    curvature: Vec<(usize, usize, FieldFunction)>,
    frame: Option<Matrix3<f64>>,
    timing: Timing,
    time_dependent: bool,
}

/// A volumetric slab in a system: the columns of slab nodes under the mid-surface vertices, the output
/// triangles, and the rest-curvature script.
#[derive(Debug)]
pub struct VolumeModel {
    placements: Vec<ShellPlacement>,
    /// Slab nodes of each mid-surface vertex, bottom to top.
    columns: Vec<Vec<usize>>,
    triangles: Vec<[usize; 3]>,
    rest: Vec<Vector3<f64>>,
    points: Vec<Vector3<f64>>,
    rest_curvature: RestCurvature,
    fields: Vec<RestFieldScript>,
    applied: bool,
    n_elements: usize,
}

fn setup(shell: &ShellSpec, reason: impl std::fmt::Display) -> SimulationError {
    SimulationError::Setup(format!("shell `{}` (micropolar volume): {reason}", shell.name))
}

/// Builds the slab of the scene's single shell.
///
/// # Errors
/// [`SimulationError::Setup`] naming the shell when the mesh is not a flat grid, an initial pose is
/// given, or `cosserat-volume` rejects the material or the slab.
pub fn build(spec: &SceneSpec, layers: usize, options: &SystemOptions) -> Result<BuiltModel, SimulationError> {
    let shell = &spec.shells[0];
    if shell.initial_positions.is_some() {
        return Err(setup(
            shell,
            "an initial pose (`mesh.initial`) is not available for the slab",
        ));
    }
    let corners = &shell.mesh.corners;
    let grid = PlanarGrid::detect(&corners.nodes).map_err(|r| setup(shell, r))?;
    let [nx, ny] = grid.cells();
    let [lx, ly] = grid.size();
    let p = &shell.material;
    let mut slab_grid = slab([lx, ly, p.thickness], [nx, ny, layers]).map_err(|e| setup(shell, e))?;
    let center = grid.center();
    slab_grid.mesh.nodes.iter_mut().for_each(|x| *x += center);
    let input = VolumeInput {
        mesh: slab_grid.mesh.clone(),
        material: p.continuum(),
        damping: shell.damping,
        angular_inertia_density: shell.angular_inertia_density,
    };
    let volume = build_volume_system(&input, options).map_err(|e| setup(shell, e))?;
    let columns: Vec<Vec<usize>> = grid
        .vertex_ij
        .iter()
        .map(|&(i, j)| (0..=layers).map(|k| slab_grid.node(i, j, k)).collect())
        .collect();
    // Scene nodes are the mid-surface's vertices; each stands for its column of slab nodes, whose
    // displacement and rotation nodes are the same.
    let surface_elements: Vec<Vec<usize>> = corners.elements.iter().map(|t| t.to_vec()).collect();
    let placements = vec![ShellPlacement {
        name: shell.name.clone(),
        disp: NodeMap::Columns(columns.clone()),
        rot: NodeMap::Columns(columns.clone()),
        rest_disp: corners.nodes.clone(),
        rest_rot: corners.nodes.clone(),
        disp_elements: surface_elements.clone(),
        rot_elements: surface_elements,
    }];
    let fields = spec
        .rest_fields
        .iter()
        .map(|r| RestFieldScript {
            time_dependent: r.curvature.iter().any(|c| c.2.is_time_dependent()),
            curvature: r.curvature.clone(),
            frame: r.curvature_frame,
            timing: r.timing,
        })
        .collect();
    let model = VolumeModel {
        placements,
        columns,
        triangles: corners.elements.clone(),
        rest: volume.rest_positions.clone(),
        points: volume.point_positions.clone(),
        rest_curvature: volume.rest_curvature.clone(),
        fields,
        applied: false,
        n_elements: slab_grid.mesh.n_elements(),
    };
    Ok(BuiltModel {
        potential: volume.potential,
        model: Box::new(model),
    })
}

impl Model for VolumeModel {
    fn record(&self) -> ModelRecord {
        ModelRecord::MicropolarVolume {
            n_tetrahedra: self.n_elements,
        }
    }

    fn element_names(&self) -> (String, String) {
        ("tet4".into(), "tet4".into())
    }

    fn placements(&self) -> &[ShellPlacement] {
        &self.placements
    }

    fn rest_positions(&self) -> &[Vector3<f64>] {
        &self.rest
    }

    /// The slab does not take part in contact (a scene that asks for it is refused when it is built).
    fn contact_triangles(&self, _shell: usize) -> Option<Vec<[usize; 3]>> {
        None
    }

    fn n_cells(&self) -> usize {
        self.n_elements
    }

    /// Sets the rest curvature of every element for the step from `t` to `t + dt` (once for fields that
    /// do not depend on time). Entries of several rest-field tables add up.
    fn apply_rest_fields(&mut self, _: &mut IncrementalPotential, t: f64, dt: f64) -> Result<(), ScriptError> {
        if self.fields.is_empty() || (self.applied && !self.fields.iter().any(|f| f.time_dependent)) {
            return Ok(());
        }
        let mut values = Vec::with_capacity(self.points.len());
        for x in &self.points {
            let mut total = Matrix3::zeros();
            for f in &self.fields {
                let tau = match f.timing {
                    Timing::StartOfStep => t,
                    Timing::EndOfStep => t + dt,
                };
                let mut m = Matrix3::zeros();
                for (i, j, value) in &f.curvature {
                    let v = value.eval(x, tau);
                    if !v.is_finite() {
                        return Err(ScriptError(format!(
                            "rest curvature ({i}, {j}) `{}` is {v} at t = {}, X = ({}, {}, {})",
                            value.description(),
                            Num(tau),
                            Num(x.x),
                            Num(x.y),
                            Num(x.z)
                        )));
                    }
                    m[(*i, *j)] += v;
                }
                total += f.frame.map_or(m, |q| q.transpose() * m * q);
            }
            values.push(total);
        }
        self.rest_curvature.set(|p| values[p]);
        self.applied = true;
        Ok(())
    }

    /// The mid-surface grid with column means of displacement, velocity, directors and angular
    /// velocity.
    fn frame(&self, state: &SystemState, t: f64) -> VtuFrame {
        let mut out = PointColumns::with_capacity(self.columns.len());
        for column in &self.columns {
            let w = 1.0 / column.len() as f64;
            let (mut x, mut rest, mut v, mut w_ang) =
                (Vector3::zeros(), Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
            let reference = state.q[column[0]];
            let mut q = Quaternion::new(0.0, 0.0, 0.0, 0.0);
            for &k in column {
                x += state.x[k] * w;
                rest += self.rest[k] * w;
                v += state.v[k] * w;
                w_ang += state.omega[k] * w;
                q += same_hemisphere(&state.q[k], &reference) * w;
            }
            out.push(&x, &rest, &v, &rotation_matrix(&q.normalize()), &w_ang);
        }
        out.into_frame(self.triangles.clone(), t)
    }
}

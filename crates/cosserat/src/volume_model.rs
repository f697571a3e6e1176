//! Scenes with the volumetric micropolar comparison model (`[material] model = "micropolar_volume"`):
//! the shell's flat Tri3 grid (its mid-surface) extruded into a slab of Tet4 elements and simulated with
//! `cosserat-volume`, typically with the conjugate-gradient solver (`[solver] linear_solver = "cg"`), as
//! the paper's Lotus "Tet4" row.
//!
//! The scene is written as for a shell: regions, probes and rest fields refer to the mid-surface. Here
//! each selected vertex becomes the column of slab nodes above it (all layers), so a boundary condition
//! holds the whole column, a `nearest` probe reports the column's mean (the mid-surface point), and a
//! rest field is evaluated at the rest centroid of every tetrahedron, between steps, through the
//! volume term's [`RestCurvature`] handle. Frames show the mid-surface: the grid's triangles over the
//! column means of positions, velocities and (quaternion-averaged) rotations.

use crate::error::SimulationError;
use crate::frames::PointColumns;
use cosserat_assembly::{ElementPair, ShellLayout, System, SystemOptions, SystemState};
use cosserat_geometry::rotation::{rotation_matrix, same_hemisphere};
use cosserat_scene::grid::PlanarGrid;
use cosserat_scene::output::VtuFrame;
use cosserat_scene::spec::{FieldFunction, NodeSelection, ProbeReduction, RestFieldSpec, SceneSpec, ShellSpec, Timing};
use cosserat_volume::mesh::slab;
use cosserat_volume::{MicropolarMaterial, RestCurvature, VolumeInput, build_volume_system};
use nalgebra::{Matrix3, Quaternion, Vector3};

/// The rest fields of a volumetric scene, evaluated at the element centroids.
#[derive(Debug)]
struct RestFieldScript {
    curvature: Vec<(usize, usize, FieldFunction)>,
    frame: Option<Matrix3<f64>>,
    timing: Timing,
    time_dependent: bool,
}

/// What a run needs beyond the system for a volumetric slab: the columns of the mid-surface vertices,
/// the output triangles, and the rest-curvature script.
#[derive(Debug)]
pub struct VolumeModel {
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

/// Builds the slab of the scene's single shell and rewrites the scene's selections onto its nodes (rest
/// fields move into the returned model). Returns the system, the model, and the rewritten scene.
///
/// # Errors
/// [`SimulationError::Setup`] naming the shell when the mesh is not a flat grid, an initial pose is
/// given, or `cosserat-volume` rejects the material or the slab.
pub fn build(
    mut spec: SceneSpec,
    layers: usize,
    options: &SystemOptions,
) -> Result<(System, VolumeModel, SceneSpec), SimulationError> {
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
    let mut material = MicropolarMaterial::new(p.youngs_modulus, p.poisson_ratio, p.density, p.length_scale);
    material.mu_c_factor = p.mu_c_factor;
    material.curvature_coefficients = p.curvature_coefficients;
    let input = VolumeInput {
        mesh: slab_grid.mesh.clone(),
        material,
        damping: shell.damping,
        angular_inertia_density: shell.angular_inertia_density,
    };
    let volume = build_volume_system(&input, options).map_err(|e| setup(shell, e))?;
    let columns: Vec<Vec<usize>> = grid
        .vertex_ij
        .iter()
        .map(|&(i, j)| (0..=layers).map(|k| slab_grid.node(i, j, k)).collect())
        .collect();
    let n = volume.rest_positions.len();
    let elements: Vec<Vec<usize>> = slab_grid.mesh.elements.iter().map(|t| t.to_vec()).collect();
    let layout = ShellLayout {
        name: shell.name.clone(),
        pair: ElementPair::Tri3Tri3,
        disp_nodes: 0..n,
        rot_nodes: 0..n,
        points: 0..volume.point_positions.len(),
        disp_elements: elements.clone(),
        rot_elements: elements,
        rest_disp_positions: volume.rest_positions.clone(),
        rest_rot_positions: volume.rest_positions.clone(),
        rest_point_positions: volume.point_positions.clone(),
        rot_to_disp: (0..n).collect(),
        element_areas: volume.element_volumes.iter().map(|v| v / p.thickness).collect(),
        active_terms: volume.potential.active_terms(),
        n_curved_points: 0,
    };
    let remap = |sel: &mut NodeSelection, columns: &[Vec<usize>]| {
        let lift = |nodes: &[usize]| {
            let mut out: Vec<usize> = nodes.iter().flat_map(|&v| columns[v].iter().copied()).collect();
            out.sort_unstable();
            out.dedup();
            out
        };
        sel.disp_nodes = lift(&sel.disp_nodes);
        sel.rot_nodes = lift(&sel.rot_nodes);
    };
    for b in &mut spec.boundaries {
        remap(&mut b.selection, &columns);
    }
    for l in &mut spec.loads {
        remap(&mut l.selection, &columns);
    }
    for probe in &mut spec.probes {
        remap(&mut probe.selection, &columns);
        // The column of the nearest vertex: its mean is the mid-surface point.
        probe.reduction = ProbeReduction::Mean;
    }
    let fields = std::mem::take(&mut spec.rest_fields)
        .into_iter()
        .map(|r: RestFieldSpec| RestFieldScript {
            time_dependent: r.curvature.iter().any(|c| c.2.is_time_dependent()),
            curvature: r.curvature,
            frame: r.curvature_frame,
            timing: r.timing,
        })
        .collect();
    let model = VolumeModel {
        columns,
        triangles: corners.elements.clone(),
        rest: volume.rest_positions.clone(),
        points: volume.point_positions.clone(),
        rest_curvature: volume.rest_curvature.clone(),
        fields,
        applied: false,
        n_elements: slab_grid.mesh.n_elements(),
    };
    Ok((
        System {
            potential: volume.potential,
            shells: vec![layout],
        },
        model,
        spec,
    ))
}

impl VolumeModel {
    /// Number of tetrahedra.
    pub fn n_elements(&self) -> usize {
        self.n_elements
    }

    /// Sets the rest curvature of every element for the step from `t` to `t + dt` (once for fields that
    /// do not depend on time). Entries of several rest-field tables add up.
    pub fn apply(&mut self, t: f64, dt: f64) {
        if self.fields.is_empty() || (self.applied && !self.fields.iter().any(|f| f.time_dependent)) {
            return;
        }
        let fields = &self.fields;
        let points = &self.points;
        self.rest_curvature.set(|p| {
            let x = &points[p];
            let mut total = Matrix3::zeros();
            for f in fields {
                let tau = match f.timing {
                    Timing::StartOfStep => t,
                    Timing::EndOfStep => t + dt,
                };
                let mut m = Matrix3::zeros();
                for (i, j, value) in &f.curvature {
                    m[(*i, *j)] += value.eval(x, tau);
                }
                total += f.frame.map_or(m, |q| q.transpose() * m * q);
            }
            total
        });
        self.applied = true;
    }

    /// The frame of a state: the mid-surface grid with column means of displacement, velocity,
    /// directors and angular velocity.
    pub fn frame(&self, state: &SystemState, t: f64) -> VtuFrame {
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

//! Building the incremental potential of a micropolar solid on a Tet4 mesh: rest data per element,
//! lumped masses, inertia and loads, and the rest-curvature handle for scripts.
//!
//! Displacement node `i` and rotation node `i` are the same mesh node. The potential holds no shells:
//! the volumetric term is inserted into it ([`VolumeSystem::volume_term`]), so boundary conditions,
//! loads and the Newton solvers of the shell system apply unchanged.

use crate::density::strain_hessian;
use crate::error::{BuildError, MeshError};
use crate::material::MicropolarModuli;
use crate::mesh::TetMesh;
use crate::term::{RestCurvature, Tet4Volume, VolumeDiscretization};
use crate::tet4::{VolumePoint, tet4_point};
use cosserat_assembly::{
    DofLayout, IncrementalPotential, NodalMasses, PotentialParts, SystemOptions, SystemState, TermHandle,
};
use cosserat_material::ContinuumParameters;
use nalgebra::Vector3;

/// A micropolar solid to build.
#[derive(Debug, Clone)]
pub struct VolumeInput {
    /// The rest mesh.
    pub mesh: TetMesh,
    /// The material.
    pub material: ContinuumParameters,
    /// Mass-proportional damping `d` on translations \[1/s\]. Finite and non-negative.
    pub damping: f64,
    /// Rotational inertia density `ρ_θ` \[kg/m\]: nodal rotational inertia `ρ_θ V/4` per adjacent element
    /// of rest volume `V`. Finite and non-negative; zero (the reference's choice) requires the energy to
    /// determine the rotations (see [`BuildError::IllPosedRotations`]).
    pub angular_inertia_density: f64,
}

/// A built volumetric system: the potential and what scripts and post-processing need.
pub struct VolumeSystem {
    /// The incremental potential (no shells).
    pub potential: IncrementalPotential,
    /// The volume term in the potential.
    pub volume_term: TermHandle<Tet4Volume>,
    /// Rest node positions \[m\] (displacement node `i` = rotation node `i`).
    pub rest_positions: Vec<Vector3<f64>>,
    /// Rest positions of the quadrature points (element centroids) \[m\], in element order.
    pub point_positions: Vec<Vector3<f64>>,
    /// Rest volume of each element \[m³\].
    pub element_volumes: Vec<f64>,
    /// The prescribed rest curvature per point, shared with the volume term.
    pub rest_curvature: RestCurvature,
}

impl VolumeSystem {
    /// Total rest volume \[m³\].
    pub fn volume(&self) -> f64 {
        self.element_volumes.iter().sum()
    }
}

/// Builds the incremental potential of a micropolar solid.
///
/// # Errors
/// - [`BuildError::Material`] for an invalid material;
/// - [`BuildError::Mesh`] for an invalid mesh (naming the element or node);
/// - [`BuildError::InvalidInput`] for a negative or non-finite damping or inertia density;
/// - [`BuildError::IllPosedRotations`] when no rotational inertia is present (a quasi-static system or
///   `angular_inertia_density = 0`) and the energy alone does not determine the rotations: this needs
///   `μ_c > 0` (otherwise a uniform rotation of all nodes changes the stretch only at fourth order, and
///   the Hessian is singular at rest) and `L_c > 0` with `b₁, b₂ > 0` (otherwise rotation fields whose
///   element means vanish, or whose gradient is purely skew or purely symmetric, are not penalised).
pub fn build_volume_system(input: &VolumeInput, options: &SystemOptions) -> Result<VolumeSystem, BuildError> {
    let moduli = MicropolarModuli::of(&input.material)?;
    check_input(input, options, &moduli)?;
    let mesh = &input.mesh;
    mesh.validate()?;
    let (points, point_positions) = quadrature_points(mesh)?;
    let n = mesh.n_nodes();
    let layout = DofLayout {
        n_disp_nodes: n,
        n_rot_nodes: n,
    };
    let element_volumes: Vec<f64> = points.iter().map(|p| p.weight).collect();
    let nodal = lumped_masses(input, &element_volumes);
    let rest_curvature = RestCurvature::zeros(points.len());
    let disc = VolumeDiscretization {
        points,
        disp_elements: mesh.elements.clone(),
        rot_elements: mesh.elements.clone(),
        first_point: 0,
        moduli,
        strain_hessian: strain_hessian(&moduli),
    };
    let term = Tet4Volume::new(disc, layout, rest_curvature.clone());
    let state = SystemState::at_rest(mesh.nodes.clone(), n, mesh.n_elements());
    let parts = PotentialParts::with_inertia_and_loads(layout, state, Vec::new(), nodal, options);
    let mut potential = IncrementalPotential::new(parts);
    let volume_term = potential.insert(term);
    Ok(VolumeSystem {
        potential,
        volume_term,
        rest_positions: mesh.nodes.clone(),
        point_positions,
        element_volumes,
        rest_curvature,
    })
}

/// Damping and rotational inertia must be finite and non-negative; without rotational inertia the
/// energy alone must determine the rotations (`μ_c > 0` for their uniform mode, `L_c, b₁, b₂ > 0` for
/// their gradients).
fn check_input(input: &VolumeInput, options: &SystemOptions, moduli: &MicropolarModuli) -> Result<(), BuildError> {
    let nonnegative = |name: &'static str, value: f64| {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(BuildError::InvalidInput {
                name,
                value,
                reason: "must be finite and non-negative",
            })
        }
    };
    nonnegative("damping", input.damping)?;
    nonnegative("angular_inertia_density", input.angular_inertia_density)?;
    let rotational_inertia_present = options.dynamic && input.angular_inertia_density > 0.0;
    if !rotational_inertia_present {
        let [b1, b2, _] = moduli.curvature_coefficients;
        if moduli.mu_c <= 0.0 {
            return Err(BuildError::IllPosedRotations {
                reason: "mu_c = 0 leaves the uniform rotation mode undetermined",
            });
        }
        if moduli.length_scale <= 0.0 || b1 <= 0.0 || b2 <= 0.0 {
            return Err(BuildError::IllPosedRotations {
                reason: "L_c = 0 or b1 = 0 or b2 = 0 leaves rotation gradients undetermined",
            });
        }
    }
    Ok(())
}

/// One quadrature point per tetrahedron (at its centroid), and the points' rest positions.
fn quadrature_points(mesh: &TetMesh) -> Result<(Vec<VolumePoint<4>>, Vec<Vector3<f64>>), BuildError> {
    let mut points = Vec::with_capacity(mesh.n_elements());
    let mut point_positions = Vec::with_capacity(mesh.n_elements());
    for e in 0..mesh.n_elements() {
        let x = mesh.element_positions(e);
        let point = tet4_point(&x).ok_or(MeshError::DegenerateElement {
            elem_idx: e,
            volume: crate::mesh::signed_volume(&x),
            relative: 0.0,
        })?;
        points.push(point);
        point_positions.push((x[0] + x[1] + x[2] + x[3]) * 0.25);
    }
    Ok((points, point_positions))
}

/// Masses and rotational inertias lumped to the nodes, a quarter of each element's per node.
fn lumped_masses(input: &VolumeInput, element_volumes: &[f64]) -> NodalMasses {
    let n = input.mesh.n_nodes();
    let mut masses = vec![0.0; n];
    let mut rotational_inertia = vec![0.0; n];
    for (el, v) in input.mesh.elements.iter().zip(element_volumes) {
        for &i in el {
            masses[i] += input.material.density * v / 4.0;
            rotational_inertia[i] += input.angular_inertia_density * v / 4.0;
        }
    }
    NodalMasses {
        masses,
        rotational_inertia,
        damping: vec![input.damping; n],
    }
}

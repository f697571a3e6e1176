//! Building a system of shells: global numbering of nodes and quadrature points, rest states, masses,
//! and the incremental potential with its pattern.
//!
//! Each shell contributes its displacement nodes, its rotation nodes and its quadrature points as
//! consecutive ranges of the global arrays. Boundary conditions and loads are added to the returned
//! potential's parts afterwards (they act on diagonal blocks and never change the pattern).

use crate::dofs::DofLayout;
use crate::potential::{IncrementalPotential, NodalMasses, PotentialParts, ShellEnergy};
use crate::shell::{ShellDiscretization, ShellTerm};
use crate::state::SystemState;
use cosserat_fem::mesh::{MeshElement, NewNode, Tri3Mesh, Tri6Mesh};
use cosserat_fem::{ElementKind, MeshError, QuadratureRule, TriMesh};
use cosserat_material::rest::{RestOptions, shell_rest};
use cosserat_material::{MaterialParameters, RestStateError, StrainInterpolation};
use nalgebra::Vector3;
use std::ops::Range;
use thiserror::Error;

/// The displacement/rotation element pair of a shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementPair {
    /// Linear displacements and rotations.
    Tri3Tri3,
    /// Quadratic displacements, linear rotations on the corner nodes (the paper's choice).
    Tri6Tri3,
    /// Quadratic displacements and rotations.
    Tri6Tri6,
}

impl ElementPair {
    /// The displacement element.
    pub fn displacement(self) -> ElementKind {
        match self {
            ElementPair::Tri3Tri3 => ElementKind::Tri3,
            ElementPair::Tri6Tri3 | ElementPair::Tri6Tri6 => ElementKind::Tri6,
        }
    }

    /// The rotation element.
    pub fn rotation(self) -> ElementKind {
        match self {
            ElementPair::Tri3Tri3 | ElementPair::Tri6Tri3 => ElementKind::Tri3,
            ElementPair::Tri6Tri6 => ElementKind::Tri6,
        }
    }

    /// The lowest quadrature degree that leaves no spurious zero-energy mode: with it and every
    /// higher degree a free patch has only the six rigid-body modes; the one-point rule leaves
    /// quadratic displacement fields free to deform without energy (checked in the tests of this
    /// crate).
    pub fn min_quadrature_degree(self) -> usize {
        match self.displacement() {
            ElementKind::Tri3 => 1,
            _ => 2,
        }
    }

    /// The quadrature rule of this pair with `interpolation` when none is chosen: the model's pairing
    /// ([`QuadratureRule::for_element_pair`]), except quadratic rotations with Regge membrane strains
    /// and stabilised shear and drilling, which take the 3-point rule their strains are built for (its
    /// points are the interior tying points; the six-point rule costs 1.6 times as much per element
    /// for the same accuracy, docs/model-notes.md).
    pub fn default_quadrature(self, interpolation: StrainInterpolation) -> QuadratureRule {
        match (self, interpolation) {
            (ElementPair::Tri6Tri6, StrainInterpolation::ReggeStabilized) => QuadratureRule::interior_p2(),
            _ => QuadratureRule::for_element_pair(self.displacement(), self.rotation()),
        }
    }
}

/// The rest mesh of a shell: its Tri3 corner mesh and, for quadratic displacements, the Tri6 mesh whose
/// corner nodes are the Tri3 vertices (node `corner_nodes[k]` of the Tri6 mesh is vertex `k`).
#[derive(Debug, Clone, PartialEq)]
pub struct ShellMesh {
    /// The corner (Tri3) mesh.
    pub corners: Tri3Mesh,
    /// The Tri6 mesh, if any.
    pub tri6: Option<Tri6Mesh>,
    /// For each corner vertex, its Tri6 node.
    pub corner_nodes: Vec<usize>,
}

impl ShellMesh {
    /// A shell mesh for `pair` from a Tri3 mesh; new Tri6 nodes are placed by `place` (chord midpoints
    /// with `cosserat_fem::mesh::chord_placement`, or on an exact surface).
    pub fn from_tri3(corners: Tri3Mesh, pair: ElementPair, place: impl FnMut(NewNode) -> Vector3<f64>) -> Self {
        let tri6 = (pair.displacement() == ElementKind::Tri6).then(|| corners.to_tri6_with(place));
        let corner_nodes = (0..corners.n_nodes()).collect();
        Self {
            corners,
            tri6,
            corner_nodes,
        }
    }

    /// A shell mesh from a Tri6 mesh (e.g. read from a file); its corner mesh is extracted.
    pub fn from_tri6(tri6: Tri6Mesh) -> Self {
        let (corners, corner_nodes) = tri6.corner_mesh();
        Self {
            corners,
            tri6: Some(tri6),
            corner_nodes,
        }
    }
}

/// One shell of a system.
#[derive(Debug, Clone)]
pub struct ShellInput {
    /// A name for summaries and errors.
    pub name: String,
    /// The rest mesh.
    pub mesh: ShellMesh,
    /// The element pair.
    pub pair: ElementPair,
    /// The material.
    pub material: MaterialParameters,
    /// Model and rest-curvature options.
    pub rest: RestOptions,
    /// Quadrature rule; `None` uses the pair's default with the rest options' strain interpolation
    /// ([`ElementPair::default_quadrature`]).
    pub quadrature: Option<QuadratureRule>,
    /// Mass-proportional damping `d` \[1/s\].
    pub damping: f64,
    /// Angular inertia density `ρ_θ` [kg/m]: nodal rotational inertia `ρ_θ h A_k`.
    pub angular_inertia_density: f64,
}

/// Where a shell sits in the global arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellLayout {
    /// The shell's name.
    pub name: String,
    /// The element pair.
    pub pair: ElementPair,
    /// Its displacement nodes.
    pub disp_nodes: Range<usize>,
    /// Its rotation nodes.
    pub rot_nodes: Range<usize>,
    /// Its quadrature points.
    pub points: Range<usize>,
    /// Displacement elements in global node indices (3 or 6 nodes each, element order).
    pub disp_elements: Vec<Vec<usize>>,
    /// Rotation elements in global rotation-node indices.
    pub rot_elements: Vec<Vec<usize>>,
    /// Rest positions of the displacement nodes (local order).
    pub rest_disp_positions: Vec<Vector3<f64>>,
    /// Rest positions of the rotation nodes (local order).
    pub rest_rot_positions: Vec<Vector3<f64>>,
    /// Rest positions of the quadrature points (local order).
    pub rest_point_positions: Vec<Vector3<f64>>,
    /// For each local rotation node, its local displacement node at the same place.
    pub rot_to_disp: Vec<usize>,
    /// Rest area of each element \[m²\].
    pub element_areas: Vec<f64>,
    /// Active energy terms of the shell.
    pub active_terms: Vec<String>,
    /// Number of quadrature points with curved rest geometry.
    pub n_curved_points: usize,
}

impl ShellLayout {
    /// Total rest area \[m²\].
    pub fn area(&self) -> f64 {
        self.element_areas.iter().sum()
    }
}

/// Options of a system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SystemOptions {
    /// Gravitational acceleration \[m/s²\].
    pub gravity: Vector3<f64>,
    /// Include inertia (dynamics); `false` for quasi-static runs.
    pub dynamic: bool,
}

/// A failure to build a system.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum BuildError {
    /// A shell's rest state could not be computed.
    #[error("shell `{shell}`: {source}")]
    Rest {
        /// The shell's name.
        shell: String,
        /// The cause.
        source: RestStateError,
    },
    /// A shell's mesh is invalid.
    #[error("shell `{shell}`: {source}")]
    Mesh {
        /// The shell's name.
        shell: String,
        /// The cause.
        source: MeshError,
    },
    /// The mesh does not fit the element pair.
    #[error("shell `{shell}`: element pair {pair:?} needs a Tri6 mesh")]
    MissingTri6 {
        /// The shell's name.
        shell: String,
        /// The pair.
        pair: ElementPair,
    },
}

/// A built system: the potential and where each shell sits in it.
pub struct System {
    /// The incremental potential.
    pub potential: IncrementalPotential,
    /// The shells.
    pub shells: Vec<ShellLayout>,
}

struct Counts {
    disp: usize,
    rot: usize,
    points: usize,
}

/// A shell turned into an energy term plus its layout and per-node data.
struct BuiltShell {
    energy: Box<dyn ShellEnergy>,
    layout: ShellLayout,
    masses: Vec<f64>,
    rotational_inertia: Vec<f64>,
    damping: f64,
}

fn build_pair<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize>(
    input: &ShellInput,
    disp: &TriMesh<NU>,
    rot: &TriMesh<NR>,
    rot_to_disp: Vec<usize>,
    offsets: &Counts,
    layout_of: &DofLayout,
) -> Result<BuiltShell, BuildError>
where
    TriMesh<NU>: MeshElement<NU>,
    TriMesh<NR>: MeshElement<NR>,
{
    let rule = input
        .quadrature
        .unwrap_or_else(|| input.pair.default_quadrature(input.rest.interpolation));
    let moduli = input.material.moduli().map_err(|e| BuildError::Rest {
        shell: input.name.clone(),
        source: e.into(),
    })?;
    let rest =
        shell_rest(disp, rot, &input.mesh.corners, &rule, &input.rest, &moduli).map_err(|e| BuildError::Rest {
            shell: input.name.clone(),
            source: e,
        })?;
    let disp_elements: Vec<[usize; NU]> = disp.elements.iter().map(|el| el.map(|i| i + offsets.disp)).collect();
    let rot_elements: Vec<[usize; NR]> = rot.elements.iter().map(|el| el.map(|k| k + offsets.rot)).collect();
    let areal_density = input.material.density * input.material.thickness;
    let mut masses = vec![0.0; disp.n_nodes()];
    let mut rotational_inertia = vec![0.0; rot.n_nodes()];
    let inertia_density = input.angular_inertia_density * input.material.thickness;
    for (e, area) in rest.element_areas.iter().enumerate() {
        for &i in &disp.elements[e] {
            masses[i] += areal_density * area / NU as f64;
        }
        for &k in &rot.elements[e] {
            rotational_inertia[k] += inertia_density * area / NR as f64;
        }
    }
    let layout = ShellLayout {
        name: input.name.clone(),
        pair: input.pair,
        disp_nodes: offsets.disp..offsets.disp + disp.n_nodes(),
        rot_nodes: offsets.rot..offsets.rot + rot.n_nodes(),
        points: offsets.points..offsets.points + rest.shapes.len(),
        disp_elements: disp_elements.iter().map(|e| e.to_vec()).collect(),
        rot_elements: rot_elements.iter().map(|e| e.to_vec()).collect(),
        rest_disp_positions: disp.nodes.clone(),
        rest_rot_positions: rot.nodes.clone(),
        rest_point_positions: rest.point_positions.clone(),
        rot_to_disp,
        element_areas: rest.element_areas.clone(),
        active_terms: rest.active_terms.clone(),
        n_curved_points: rest.n_curved_points,
    };
    let volume = rest.nonlinear_volume.then_some(moduli);
    let disc = ShellDiscretization {
        rest,
        disp_elements,
        rot_elements,
        first_point: offsets.points,
        volume,
        axl: input.rest.model.axl,
    };
    let energy: Box<dyn ShellEnergy> = Box::new(ShellTerm::<NU, NR, NL, NE, NB>::new(disc, *layout_of));
    Ok(BuiltShell {
        energy,
        layout,
        masses,
        rotational_inertia,
        damping: input.damping,
    })
}

fn node_counts(input: &ShellInput) -> Result<(usize, usize), BuildError> {
    let n_corner = input.mesh.corners.n_nodes();
    match input.pair {
        ElementPair::Tri3Tri3 => Ok((n_corner, n_corner)),
        ElementPair::Tri6Tri3 | ElementPair::Tri6Tri6 => {
            let tri6 = input.mesh.tri6.as_ref().ok_or_else(|| BuildError::MissingTri6 {
                shell: input.name.clone(),
                pair: input.pair,
            })?;
            let n_rot = if input.pair == ElementPair::Tri6Tri3 {
                n_corner
            } else {
                tri6.n_nodes()
            };
            Ok((tri6.n_nodes(), n_rot))
        }
    }
}

/// Builds the system of the given shells; further terms (e.g. contact) are inserted into its potential
/// afterwards ([`IncrementalPotential::insert`]).
///
/// # Errors
/// Invalid meshes (degenerate or malformed elements, named by shell and index) and invalid materials.
pub fn build_system(inputs: &[ShellInput], options: &SystemOptions) -> Result<System, BuildError> {
    // First pass: global counts, so every term knows the final layout.
    let mut n_disp = 0;
    let mut n_rot = 0;
    for input in inputs {
        input.mesh.corners.validate().map_err(|e| BuildError::Mesh {
            shell: input.name.clone(),
            source: e,
        })?;
        if let Some(t6) = &input.mesh.tri6 {
            t6.validate().map_err(|e| BuildError::Mesh {
                shell: input.name.clone(),
                source: e,
            })?;
        }
        let (d, r) = node_counts(input)?;
        n_disp += d;
        n_rot += r;
    }
    let layout = DofLayout {
        n_disp_nodes: n_disp,
        n_rot_nodes: n_rot,
    };
    let mut counts = Counts {
        disp: 0,
        rot: 0,
        points: 0,
    };
    let mut built = Vec::with_capacity(inputs.len());
    for input in inputs {
        let b = match input.pair {
            ElementPair::Tri3Tri3 => {
                let m = &input.mesh.corners;
                build_pair::<3, 3, 15, 18, 6>(input, m, m, (0..m.n_nodes()).collect(), &counts, &layout)?
            }
            ElementPair::Tri6Tri3 => {
                let t6 = input.mesh.tri6.as_ref().expect("checked in node_counts");
                build_pair::<6, 3, 15, 27, 9>(
                    input,
                    t6,
                    &input.mesh.corners,
                    input.mesh.corner_nodes.clone(),
                    &counts,
                    &layout,
                )?
            }
            ElementPair::Tri6Tri6 => {
                let t6 = input.mesh.tri6.as_ref().expect("checked in node_counts");
                build_pair::<6, 6, 24, 36, 12>(input, t6, t6, (0..t6.n_nodes()).collect(), &counts, &layout)?
            }
        };
        counts.disp = b.layout.disp_nodes.end;
        counts.rot = b.layout.rot_nodes.end;
        counts.points = b.layout.points.end;
        built.push(b);
    }
    let mut x = Vec::with_capacity(n_disp);
    let mut nodal = NodalMasses::default();
    let mut shells = Vec::with_capacity(built.len());
    let mut layouts = Vec::with_capacity(built.len());
    for b in built {
        x.extend_from_slice(&b.layout.rest_disp_positions);
        nodal.masses.extend_from_slice(&b.masses);
        nodal.rotational_inertia.extend_from_slice(&b.rotational_inertia);
        nodal.damping.extend(std::iter::repeat_n(b.damping, b.masses.len()));
        shells.push(b.energy);
        layouts.push(b.layout);
    }
    let state = SystemState::at_rest(x, n_rot, counts.points);
    let parts = PotentialParts::with_inertia_and_loads(layout, state, shells, nodal, options);
    Ok(System {
        potential: IncrementalPotential::new(parts),
        shells: layouts,
    })
}

//! Building the incremental potential of a Kirchhoff–Love shell: the elastic term, lumped inertia and
//! loads, on the unknowns of `cosserat-assembly` (vertex velocities only, no rotation nodes).
//!
//! The result is an ordinary [`IncrementalPotential`], so the Cosserat solvers (time stepping, quasi-static
//! loading) run it unchanged, and boundary conditions are added to its parts as for a Cosserat shell
//! (exact position constraints, penalties, nodal forces; moments through a [`crate::ForceCouple`]
//! inserted into the potential).

use crate::error::{KlError, check_parameter};
use crate::material::KlMaterial;
use crate::term::KirchhoffLoveTerm;
use crate::thickness::ThicknessRule;
use cosserat_assembly::{
    AssemblyError, DofLayout, IncrementalPotential, NodalMasses, PotentialParts, SystemOptions, SystemState, TermHandle,
};
use cosserat_fem::Tri3Mesh;
use nalgebra::Vector3;

/// The physical description of a Kirchhoff–Love shell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KlShell {
    /// The material.
    pub material: KlMaterial,
    /// Thickness `h` \[m\]. Finite and positive.
    pub thickness: f64,
    /// Volumetric mass density `ρ` \[kg/m³\]. Finite and positive.
    pub density: f64,
    /// Mass-proportional damping `d` \[1/s\]. Finite and non-negative.
    pub damping: f64,
    /// The rule through the thickness.
    pub thickness_rule: ThicknessRule,
}

impl KlShell {
    /// A shell without damping, with the default 3-point thickness rule.
    pub fn new(material: KlMaterial, thickness: f64, density: f64) -> Self {
        Self {
            material,
            thickness,
            density,
            damping: 0.0,
            thickness_rule: ThicknessRule::default(),
        }
    }
}

/// A built Kirchhoff–Love system.
pub struct KlSystem {
    /// The incremental potential.
    pub potential: IncrementalPotential,
    /// The elastic term in the potential.
    pub elastic: TermHandle<KirchhoffLoveTerm>,
    /// Rest positions of the vertices \[m\] (vertex `i` is displacement node `i`).
    pub rest_positions: Vec<Vector3<f64>>,
    /// Lumped vertex masses `ρ h A / 3` summed over the adjacent faces \[kg\].
    pub masses: Vec<f64>,
    /// Names of the active terms.
    pub active_terms: Vec<String>,
}

/// Builds the incremental potential of a Kirchhoff–Love shell on `mesh` (its rest state), with lumped
/// masses (a third of each face's mass per corner), gravity, zero nodal forces and, if
/// `options.dynamic`, inertia with the shell's damping. Further terms that couple vertices (a
/// [`crate::ForceCouple`]) are inserted into the potential afterwards.
///
/// # Errors
/// Invalid shell parameters, mesh or rest state (see [`KlError`]).
pub fn build_kl_system(mesh: &Tri3Mesh, shell: &KlShell, options: &SystemOptions) -> Result<KlSystem, KlError> {
    check_parameter(
        "density",
        shell.density,
        shell.density > 0.0,
        "must be finite and positive",
    )?;
    check_parameter(
        "damping",
        shell.damping,
        shell.damping >= 0.0,
        "must be finite and non-negative",
    )?;
    for (c, g) in options.gravity.iter().enumerate() {
        check_parameter(["gravity.x", "gravity.y", "gravity.z"][c], *g, true, "must be finite")?;
    }
    let n = mesh.n_nodes();
    let layout = DofLayout {
        n_disp_nodes: n,
        n_rot_nodes: 0,
    };
    let term = KirchhoffLoveTerm::try_new(mesh, &shell.material, shell.thickness, shell.thickness_rule, layout)?;
    let areal_density = shell.density * shell.thickness;
    let mut masses = vec![0.0; n];
    for (s, r) in term.stencils().iter().zip(term.rest()) {
        for &v in &s.face {
            masses[v] += areal_density * r.area() / 3.0;
        }
    }
    let nodal = NodalMasses {
        masses: masses.clone(),
        rotational_inertia: Vec::new(),
        damping: vec![shell.damping; n],
    };
    let state = SystemState::at_rest(mesh.nodes.clone(), 0, 0);
    let parts = PotentialParts::with_inertia_and_loads(layout, state, Vec::new(), nodal, options);
    let mut potential = IncrementalPotential::new(parts);
    let elastic = potential.insert(term);
    let active_terms = potential.active_terms();
    Ok(KlSystem {
        potential,
        elastic,
        rest_positions: mesh.nodes.clone(),
        masses,
        active_terms,
    })
}

impl KlSystem {
    /// The elastic energy \[J\] of the shell in the start-of-step state (no motion over the step).
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] naming the first face with a non-finite energy.
    pub fn elastic_energy(&mut self) -> Result<f64, AssemblyError> {
        self.potential.elastic_energy()
    }
}

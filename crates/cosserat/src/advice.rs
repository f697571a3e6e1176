//! Warnings about settings a scene can run with but whose results physics or the discretisation
//! limits: the combinations `cargo xtask stability` found (docs/stability.md) and the stabilised
//! projection's softness in the plane (docs/model-notes.md), each with its remedy.
//!
//! The checks look only at the scene (material, thickness, mesh), before anything is built, so a user
//! sees them before a long run. They never stop a run: a scene may mean it (a locking study, say).

use cosserat_assembly::ElementPair;
use cosserat_material::StrainInterpolation;
use cosserat_scene::spec::{ModelKind, SceneSpec, ShellSpec};

/// Element length over thickness above which linear (Tri3) displacements lock in bending: measured on
/// the Sze end-shear cantilever, Tri3/Tri3 is 6 % too stiff at ℓ/h = 0.5 and four times too stiff at
/// ℓ/h = 3 (docs/stability.md, locking table).
const TRI3_LOCKING_RATIO: f64 = 1.0;

/// Element length over thickness above which quadratic (Tri6) displacements lose more than a few per
/// cent to locking: 4 % at ℓ/h = 50 and 24 % at ℓ/h = 100 on the same benchmark.
const TRI6_LOCKING_RATIO: f64 = 50.0;

/// The warnings for a scene, one line each, naming the shell, the setting and the remedy.
pub fn advise(spec: &SceneSpec) -> Vec<String> {
    spec.shells.iter().flat_map(advise_shell).collect()
}

fn advise_shell(shell: &ShellSpec) -> Vec<String> {
    let mut out = Vec::new();
    // The measured limits are the Cosserat shell's; the comparison models have their own
    // discretisations (docs/kirchhoff-love.md, docs/micropolar-volume.md).
    if !matches!(shell.model, ModelKind::Cosserat) {
        return out;
    }
    let m = &shell.material;
    if m.mu_c_factor == 0.0 && m.length_scale == 0.0 {
        out.push(format!(
            "shell `{}`: with material.mu_c_factor = 0 and material.length_scale = 0 the drilling rotation \
             (about the normal) has no stiffness and is not determined by the energy; Newton needs many more \
             iterations and may stall. Remedy: any length_scale > 0 (1e-3 × thickness changes the bending \
             stiffness by a relative 1.2e-5) or mu_c_factor > 0",
            shell.name
        ));
    }
    let Some(length) = median_edge_length(&shell.mesh.corners.nodes, &shell.mesh.corners.elements) else {
        return out;
    };
    if let Some(beta) = stabilized_membrane_share(shell, length) {
        out.push(format!(
            "shell `{}`: the stabilised projection keeps {:.1} % of the membrane-strain variation inside \
             elements of {length:.3e} m at h = {:.3e} m, so in-plane bending and membrane-dominated regions \
             are too flexible on this mesh, by up to 1/β (a strip one element wide bent in its plane, \
             β = 1/101: 101 times; docs/model-notes.md). Remedy: material.strain_interpolation = \"paper\" or \"regge\" where \
             the shell carries in-plane loads, or compare with a finer mesh",
            shell.name,
            100.0 * beta,
            m.thickness
        ));
    }
    let ratio = length / m.thickness;
    if frees_the_thin_limit(shell) {
        return out;
    }
    let (limit, element) = match shell.pair {
        ElementPair::Tri3Tri3 => (TRI3_LOCKING_RATIO, "tri3"),
        ElementPair::Tri6Tri3 | ElementPair::Tri6Tri6 => (TRI6_LOCKING_RATIO, "tri6"),
    };
    if ratio > limit {
        let remedy = match shell.pair {
            ElementPair::Tri3Tri3 => {
                "use quadratic displacements (mesh.element = \"tri6\", the paper's Tri6/Tri3 pair)"
            }
            _ => {
                "leave mesh.rotation_element and material.strain_interpolation unset (the default, Tri6/Tri6 \
                 with \"regge_stabilized\" strains, does not lock; docs/model-notes.md), or refine the mesh \
                 towards elements of about ten thicknesses and compare with a finer mesh"
            }
        };
        out.push(format!(
            "shell `{}`: {element} elements {ratio:.3} times longer than the thickness (median edge {length:.3e} m, \
             h = {:.3e} m) are expected to lock in bending, i.e. to be too stiff (docs/stability.md, \
             locking). Remedy: {remedy}",
            shell.name, m.thickness
        ));
    }
    out
}

/// Whether the shell's strain interpolation keeps the thin cantilever free on coarse quadratic meshes
/// (Sze 3.1 on 20 × 2 quads within 0.1 % from h/L = 1e-3 down: docs/model-notes.md), so that the
/// locking limits measured for the paper's interpolation do not apply.
fn frees_the_thin_limit(shell: &ShellSpec) -> bool {
    !matches!(shell.pair, ElementPair::Tri3Tri3)
        && matches!(
            shell.rest.interpolation,
            StrainInterpolation::Stabilized | StrainInterpolation::ReggeStabilized
        )
}

/// Below this share `β` of the membrane-strain variation inside an element that the stabilised
/// projection keeps, in-plane bending on a coarse mesh is more than about twice too flexible (a strip
/// of one element across carries it by that variation alone).
const STABILIZED_MEMBRANE_SHARE: f64 = 0.5;

/// The share `β = h² / (h² + c ℓ²)` of the membrane-strain variation the stabilised projection keeps
/// on elements of length `length`, where it is below [`STABILIZED_MEMBRANE_SHARE`].
fn stabilized_membrane_share(shell: &ShellSpec, length: f64) -> Option<f64> {
    if shell.rest.interpolation != StrainInterpolation::Stabilized {
        return None;
    }
    let h2 = shell.material.thickness * shell.material.thickness;
    let beta = h2 / (h2 + shell.rest.stabilization.membrane * length * length);
    (beta < STABILIZED_MEMBRANE_SHARE).then_some(beta)
}

/// Median edge length over the triangles of a corner mesh (`None` without elements).
fn median_edge_length(nodes: &[nalgebra::Vector3<f64>], elements: &[[usize; 3]]) -> Option<f64> {
    let mut lengths: Vec<f64> = elements
        .iter()
        .flat_map(|e| (0..3).map(move |k| (e[k], e[(k + 1) % 3])))
        .filter_map(|(a, b)| Some((nodes.get(a)? - nodes.get(b)?).norm()))
        .filter(|l| l.is_finite())
        .collect();
    if lengths.is_empty() {
        return None;
    }
    let mid = lengths.len() / 2;
    let (_, median, _) = lengths.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*median)
}

#[cfg(test)]
mod tests {
    use super::median_edge_length;
    use nalgebra::Vector3;

    #[test]
    fn median_edge_of_a_right_triangle_is_its_middle_edge() {
        let nodes = [
            Vector3::zeros(),
            Vector3::new(3.0, 0.0, 0.0),
            Vector3::new(0.0, 4.0, 0.0),
        ];
        assert_eq!(median_edge_length(&nodes, &[[0, 1, 2]]), Some(4.0));
        assert_eq!(median_edge_length(&nodes, &[]), None);
    }
}

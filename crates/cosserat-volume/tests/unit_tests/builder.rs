//! The system builder: masses, layout, input errors and the well-posedness of the rotations without
//! rotational inertia.

use super::common::{dense, material, small_system};
use cosserat_assembly::SystemOptions;
use cosserat_volume::mesh::{TetMesh, slab};
use cosserat_volume::{BuildError, ContinuumParameters, MeshError, VolumeInput, build_volume_system};
use nalgebra::{DMatrix, Vector3};

fn input(material: ContinuumParameters, angular_inertia_density: f64) -> VolumeInput {
    VolumeInput {
        mesh: slab([0.1, 0.04, 0.02], [2, 1, 1]).unwrap().mesh,
        material,
        damping: 0.0,
        angular_inertia_density,
    }
}

fn options(dynamic: bool) -> SystemOptions {
    SystemOptions {
        gravity: Vector3::zeros(),
        dynamic,
    }
}

#[test]
fn masses_and_rotational_inertia_are_lumped_volume_quarters() {
    let sys = small_system([3, 2, 2], material(), true, 0.02);
    let volume = 0.1 * 0.04 * 0.02;
    assert!((sys.volume() - volume).abs() < 1e-15);
    let inertia = sys.potential.parts.inertia.as_ref().unwrap();
    let mass: f64 = inertia.masses.iter().sum();
    assert!((mass - 1000.0 * volume).abs() < 1e-12 * mass);
    let rot: f64 = inertia.rotational_inertia.iter().sum();
    assert!((rot - 0.02 * volume).abs() < 1e-12 * rot);
    let layout = sys.potential.parts.layout;
    assert_eq!(layout.n_disp_nodes, sys.rest_positions.len());
    assert_eq!(layout.n_rot_nodes, sys.rest_positions.len());
    assert_eq!(sys.point_positions.len(), 6 * 3 * 2 * 2);
    assert!(sys.potential.parts.shells.is_empty());
    assert_eq!(sys.potential.parts.state.q_points.len(), sys.point_positions.len());
}

#[test]
fn invalid_inputs_are_rejected_by_name() {
    let mut bad = material();
    bad.poisson_ratio = 0.5;
    assert!(matches!(
        build_volume_system(&input(bad, 0.0), &options(true)),
        Err(BuildError::Material(_))
    ));
    let mut i = input(material(), 0.0);
    i.damping = f64::NAN;
    assert!(matches!(
        build_volume_system(&i, &options(true)),
        Err(BuildError::InvalidInput { name: "damping", .. })
    ));
    let mut i = input(material(), 0.0);
    i.mesh = TetMesh {
        nodes: vec![
            Vector3::zeros(),
            Vector3::x(),
            Vector3::y(),
            Vector3::new(1.0, 1.0, 0.0),
        ],
        elements: vec![[0, 1, 2, 3]],
    };
    assert!(matches!(
        build_volume_system(&i, &options(true)),
        Err(BuildError::Mesh(MeshError::DegenerateElement { elem_idx: 0, .. }))
    ));
}

#[test]
fn rotations_need_mu_c_and_l_c_unless_there_is_rotational_inertia() {
    let mut no_mu_c = material();
    no_mu_c.mu_c_factor = 0.0;
    let mut no_lc = material();
    no_lc.length_scale = 0.0;
    for m in [no_mu_c, no_lc] {
        assert!(matches!(
            build_volume_system(&input(m, 0.0), &options(true)),
            Err(BuildError::IllPosedRotations { .. })
        ));
        assert!(matches!(
            build_volume_system(&input(m, 0.1), &options(false)),
            Err(BuildError::IllPosedRotations { .. })
        ));
        build_volume_system(&input(m, 0.1), &options(true)).unwrap();
    }
}

/// Eigenvalues of the rotation block of the Hessian at rest (no rotational inertia), relative to the
/// largest.
fn relative_rotation_spectrum(m: ContinuumParameters) -> Vec<f64> {
    // Build with rotational inertia (accepted for any moduli), then remove it.
    let mut sys = build_volume_system(&input(m, 1.0), &options(true)).unwrap();
    let inertia = sys.potential.parts.inertia.as_mut().unwrap();
    inertia.rotational_inertia.iter_mut().for_each(|i| *i = 0.0);
    let p = &mut sys.potential;
    let n = p.n_dofs();
    let (mut g, mut values) = (vec![0.0; n], vec![0.0; p.pattern().nnz()]);
    p.hessian(&vec![0.0; n], &mut g, &mut values).unwrap();
    let h = dense(p.pattern(), &values);
    let half = n / 2;
    let rot: DMatrix<f64> = h.view((half, half), (half, half)).into_owned();
    let eig = rot.symmetric_eigen().eigenvalues;
    let largest = eig.amax();
    let mut rel: Vec<f64> = eig.iter().map(|l| l / largest).collect();
    rel.sort_by(f64::total_cmp);
    rel
}

#[test]
fn the_rotation_block_is_singular_exactly_when_the_builder_says_so() {
    // μ_c > 0 and L_c > 0: positive definite.
    let good = relative_rotation_spectrum(material());
    assert!(good[0] > 1e-8, "smallest relative eigenvalue {}", good[0]);
    // μ_c = 0: the uniform rotation changes the stretch only at fourth order; one zero per axis.
    let mut m = material();
    m.mu_c_factor = 0.0;
    let s = relative_rotation_spectrum(m);
    assert!(s[2].abs() < 1e-12 && s[3] > 1e-8, "{:?}", &s[..4]);
    // L_c = 0: only the element means of the nodal angular velocities are seen (12 nodes, 12
    // elements here, but the means are dependent), so the block is singular too.
    let mut m = material();
    m.length_scale = 0.0;
    let s = relative_rotation_spectrum(m);
    assert!(s[0].abs() < 1e-12, "{:?}", &s[..4]);
}

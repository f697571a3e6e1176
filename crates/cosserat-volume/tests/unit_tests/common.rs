//! Seeded random data for the tests.

use cosserat_geometry::rotation::{exp_map, quaternion_from_matrix};
use cosserat_volume::ContinuumParameters;
use nalgebra::{Matrix3, Quaternion, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    rand::SeedableRng::seed_from_u64(seed)
}

pub fn vec3(rng: &mut ChaCha8Rng, scale: f64) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.random_range(-scale..scale))
}

pub fn mat3(rng: &mut ChaCha8Rng, scale: f64) -> Matrix3<f64> {
    Matrix3::from_fn(|_, _| rng.random_range(-scale..scale))
}

pub fn quaternion(rng: &mut ChaCha8Rng, angle: f64) -> Quaternion<f64> {
    quaternion_from_matrix(&exp_map(&vec3(rng, angle)))
}

/// A well-shaped tetrahedron of size about 0.1 m: a regular one, perturbed.
pub fn tet(rng: &mut ChaCha8Rng) -> [Vector3<f64>; 4] {
    let base = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(0.05, 0.0866, 0.0),
        Vector3::new(0.05, 0.0289, 0.0816),
    ];
    base.map(|x| x + vec3(rng, 0.01))
}

/// A material exercising every modulus (μ_c ≠ μ, all three curvature coefficients).
pub fn material() -> ContinuumParameters {
    let mut m = ContinuumParameters::new(1e6, 0.3, 1000.0, 0.05);
    m.mu_c_factor = 0.7;
    m.curvature_coefficients = [1.0, 0.6, 0.3];
    m
}

/// Largest absolute entry of a slice.
pub fn amax(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// A small slab system (1 dm × 4 cm × 2 cm) with gravity.
pub fn small_system(
    cells: [usize; 3],
    material: ContinuumParameters,
    dynamic: bool,
    angular_inertia_density: f64,
) -> cosserat_volume::VolumeSystem {
    let grid = cosserat_volume::mesh::slab([0.1, 0.04, 0.02], cells).unwrap();
    let input = cosserat_volume::VolumeInput {
        mesh: grid.mesh,
        material,
        damping: 0.3,
        angular_inertia_density,
    };
    let options = cosserat_assembly::SystemOptions {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        dynamic,
    };
    let mut system = cosserat_volume::build_volume_system(&input, &options).unwrap();
    system.potential.set_time_step(0.01);
    system
}

/// Puts a system into a general start-of-step state: displaced, rotated nodes and points, moving.
pub fn perturb_state(system: &mut cosserat_volume::VolumeSystem, seed: u64) {
    let mut r = rng(seed);
    let st = &mut system.potential.parts.state;
    for x in &mut st.x {
        *x += vec3(&mut r, 0.003);
    }
    for v in &mut st.v {
        *v = vec3(&mut r, 0.1);
    }
    for q in &mut st.q {
        *q = quaternion(&mut r, 0.3);
    }
    for q in &mut st.q_points {
        *q = quaternion(&mut r, 0.3);
    }
    for w in &mut st.omega {
        *w = vec3(&mut r, 1.0);
    }
}

/// `n` random unknowns (velocities and angular velocities) of magnitude up to 0.5.
pub fn random_unknowns(n: usize, seed: u64) -> Vec<f64> {
    let mut r = rng(seed);
    (0..n).map(|_| vec3(&mut r, 0.5).x).collect()
}

/// The dense symmetric matrix of upper-triangular values in `pattern`.
pub fn dense(pattern: &cosserat_assembly::SparsityPattern, values: &[f64]) -> nalgebra::DMatrix<f64> {
    let n = pattern.n_dofs();
    nalgebra::DMatrix::from_fn(n, n, |i, j| {
        let (a, b) = if i <= j { (i, j) } else { (j, i) };
        pattern.entry(a, b).map_or(0.0, |k| values[k])
    })
}

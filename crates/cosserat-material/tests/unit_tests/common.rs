//! Random inputs for the kernel tests (seeded).

use cosserat_geometry::rotation::{exp_map, quaternion_from_matrix};
use cosserat_material::MaterialParameters;
use cosserat_material::kernel::PointShape;
use cosserat_material::strain_space::{StrainVector, strain_offset};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

pub fn vec3(rng: &mut ChaCha8Rng, scale: f64) -> Vector3<f64> {
    Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    ) * scale
}

pub fn rotation(rng: &mut ChaCha8Rng, max_angle: f64) -> Matrix3<f64> {
    let v = vec3(rng, 1.0);
    exp_map(&(v.normalize() * rng.random_range(0.0..max_angle)))
}

pub fn quaternion(rng: &mut ChaCha8Rng, max_angle: f64) -> Quaternion<f64> {
    quaternion_from_matrix(&rotation(rng, max_angle))
}

/// A random point shape: arbitrary frame, shape gradients of size ~1/h_e, rotation values summing to 1.
pub fn shape<const NU: usize, const NR: usize>(rng: &mut ChaCha8Rng, h_e: f64) -> PointShape<NU, NR> {
    let mut m = SVector::<f64, NR>::from_fn(|_, _| rng.random_range(0.05..1.0));
    m /= m.sum();
    PointShape {
        disp_grad: SMatrix::<f64, 2, NU>::from_fn(|_, _| rng.random_range(-1.0..1.0) / h_e),
        rot_values: m,
        rot_grad: SMatrix::<f64, 2, NR>::from_fn(|_, _| rng.random_range(-1.0..1.0) / h_e),
        frame: rotation(rng, 3.0),
        weight: rng.random_range(0.1..1.0) * h_e * h_e,
    }
}

/// A random symmetric tangential `b` in the given frame.
pub fn curvature_tensor(rng: &mut ChaCha8Rng, frame: &Matrix3<f64>, scale: f64) -> Matrix3<f64> {
    let (b11, b12, b22) = (
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let local = Matrix3::new(b11, b12, 0.0, b12, b22, 0.0, 0.0, 0.0, 0.0) * scale;
    frame * local * frame.transpose()
}

/// A random strain offset with growth and rest curvature.
pub fn offset(rng: &mut ChaCha8Rng, frame: &Matrix3<f64>) -> StrainVector {
    let growth = 1.0 + rng.random_range(-0.2..0.2);
    let n = frame.column(2).into_owned();
    let a = (Matrix3::identity() - n * n.transpose()) * growth;
    let g = Matrix3::from_fn(|_, _| rng.random_range(-2.0..2.0));
    strain_offset(frame, Some(&a), Some(&g))
}

/// Relative maximum-entry error.
pub fn rel_err<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1e-300)
}

/// Runs `f` on a thread with a large stack: second-order dual numbers in 24 directions are 4.6 KB each,
/// and a whole point energy holds hundreds of them at once.
pub fn with_big_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

/// The largest difference of `got` and `expected` in the scale of the rows and columns of `got`
/// (velocity and angular-velocity blocks differ by orders of magnitude), so that a wrong small block
/// cannot hide behind a large one.
pub fn scaled_max_error<const N: usize>(got: &SMatrix<f64, N, N>, expected: &SMatrix<f64, N, N>) -> f64 {
    let row_max: Vec<f64> = (0..N).map(|i| got.row(i).amax()).collect();
    let mut e: f64 = 0.0;
    for i in 0..N {
        for j in 0..N {
            let scale = (row_max[i] * row_max[j]).sqrt().max(1e-300);
            e = e.max((got[(i, j)] - expected[(i, j)]).abs() / scale);
        }
    }
    e
}

/// A material with every curvature coefficient and the micropolar coupling active.
pub fn material() -> MaterialParameters {
    let mut m = MaterialParameters::new(0.01, 1e6, 0.3, 1000.0, 0.02);
    m.curvature_coefficients = [1.0, 0.7, 0.2];
    m.mu_c_factor = 0.8;
    m
}

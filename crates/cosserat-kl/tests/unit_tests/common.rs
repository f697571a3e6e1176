//! Shared fixtures: stencils of flat and curved meshes, seeded random states, finite differences.

use cosserat_fem::Tri3Mesh;
use cosserat_fem::mesh::procedural;
use cosserat_kl::{HyperelasticModel, KlMaterial, MaterialConstants, StencilRest, ThicknessRule, build_stencils};
use nalgebra::{DMatrix, DVector, Rotation3, SVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A material with `E = 1`, `ν = 0.3` (energies are linear in `E`).
pub fn constants(model: HyperelasticModel) -> MaterialConstants {
    KlMaterial::new(model, 1.0, 0.3).constants().unwrap()
}

pub const MODELS: [HyperelasticModel; 2] = [HyperelasticModel::StVenantKirchhoff, HyperelasticModel::NeoHookean];

/// A stencil of a mesh: its rest coordinates, its rest data and its vertex slots.
pub struct StencilCase {
    pub name: &'static str,
    pub x: SVector<f64, 18>,
    pub rest: StencilRest,
    /// A characteristic edge length \[m\].
    pub length: f64,
}

pub fn stencil_case(name: &'static str, mesh: &Tri3Mesh, face: usize, thickness: f64) -> StencilCase {
    let stencils = build_stencils(mesh).unwrap();
    let s = stencils[face];
    let mut x = SVector::<f64, 18>::zeros();
    for (k, v) in s.vertices().iter().enumerate() {
        if let Some(v) = v {
            x.fixed_rows_mut::<3>(3 * k).copy_from(&mesh.nodes[*v]);
        }
    }
    let rest = StencilRest::try_new(face, &x, s.present(), thickness, &ThicknessRule::default()).unwrap();
    let length = (mesh.nodes[s.face[1]] - mesh.nodes[s.face[0]]).norm();
    StencilCase { name, x, rest, length }
}

/// A flat interior face, a flat corner face (two boundary edges), a face of a sphere and of a cylinder.
pub fn cases() -> Vec<StencilCase> {
    let grid = procedural::rectangle_grid(1.0, 0.8, 5, 4).unwrap().mesh;
    // Quad (2, 2) is interior: its first triangle is face 2·(2·4 + 2).
    let interior = 2 * (2 * 4 + 2);
    let sphere = procedural::icosphere(1.0, 2).unwrap().mesh;
    let cylinder = procedural::cylinder(0.5, 1.0, 16, 4).unwrap().mesh;
    vec![
        stencil_case("flat interior", &grid, interior, 0.02),
        // Quad (4, 0) has an even diagonal: its first triangle has the right and bottom edges on the boundary.
        stencil_case("flat corner", &grid, 2 * (4 * 4), 0.02),
        stencil_case("sphere", &sphere, 7, 0.02),
        stencil_case("cylinder", &cylinder, 2 * 16 + 5, 0.02),
    ]
}

/// The rest coordinates displaced by uniform random numbers in `±amplitude · length` (absent slots too,
/// which the energy must ignore).
pub fn perturbed(case: &StencilCase, amplitude: f64, rng: &mut ChaCha8Rng) -> SVector<f64, 18> {
    case.x + SVector::<f64, 18>::from_fn(|_, _| rng.random_range(-1.0..1.0) * amplitude * case.length)
}

/// A random rotation (axis and angle up to π) and translation applied to every vertex.
pub fn rigidly_moved(x: &SVector<f64, 18>, rng: &mut ChaCha8Rng) -> SVector<f64, 18> {
    let axis = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let r = Rotation3::from_scaled_axis(axis.normalize() * rng.random_range(0.1..3.1));
    let t = Vector3::new(
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
    );
    let mut y = *x;
    for k in 0..6 {
        let v = r * Vector3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2]) + t;
        y.fixed_rows_mut::<3>(3 * k).copy_from(&v);
    }
    y
}

/// Central finite differences of a scalar function.
pub fn fd_gradient(f: impl Fn(&DVector<f64>) -> f64, x: &DVector<f64>, step: f64) -> DVector<f64> {
    DVector::from_fn(x.len(), |i, _| {
        let (mut p, mut m) = (x.clone(), x.clone());
        p[i] += step;
        m[i] -= step;
        (f(&p) - f(&m)) / (2.0 * step)
    })
}

/// Central finite differences of a gradient (column `j` = derivative along unknown `j`).
pub fn fd_jacobian(g: impl Fn(&DVector<f64>) -> DVector<f64>, x: &DVector<f64>, step: f64) -> DMatrix<f64> {
    let n = x.len();
    let mut out = DMatrix::zeros(n, n);
    for j in 0..n {
        let (mut p, mut m) = (x.clone(), x.clone());
        p[j] += step;
        m[j] -= step;
        out.set_column(j, &((g(&p) - g(&m)) / (2.0 * step)));
    }
    out
}

/// `max |a − b| / max |b|`.
pub fn relative_error(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

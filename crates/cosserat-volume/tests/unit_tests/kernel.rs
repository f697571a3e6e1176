//! The fast point kernel mapped to element unknowns, against the whole-element dual-number oracle,
//! central differences, symmetry and rigid motions.

use super::common::{amax, mat3, material, quaternion, rng, tet, vec3};
use cosserat_geometry::rotation::{RotationJet, cayley, rotation_matrix};
use cosserat_volume::MicropolarModuli;
use cosserat_volume::density::{StrainMatrix, strain_hessian};
use cosserat_volume::element::{ElementDerivatives, accumulate};
use cosserat_volume::kernel::{PointState, point_gradient, point_hessian, point_value};
use cosserat_volume::oracle::{ElementContext, element_energy};
use cosserat_volume::tet4::{VolumePoint, deformation_gradient, point_omega, tet4_point};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;

/// One element in a general state: deformed, rotated, moving, with a rest curvature.
pub struct Case {
    pub point: VolumePoint<4>,
    pub x_start: [Vector3<f64>; 4],
    pub q_point: Quaternion<f64>,
    pub q_nodes: [Quaternion<f64>; 4],
    pub dt: f64,
    pub rest: Matrix3<f64>,
    pub moduli: MicropolarModuli,
    pub d: StrainMatrix,
    pub v: [Vector3<f64>; 4],
    pub w: [Vector3<f64>; 4],
}

pub fn random_case(seed: u64) -> Case {
    let mut r = rng(seed);
    let x_rest = tet(&mut r);
    let point = tet4_point(&x_rest).unwrap();
    let moduli = MicropolarModuli::of(&material()).unwrap();
    Case {
        point,
        x_start: x_rest.map(|x| x + vec3(&mut r, 0.01)),
        q_point: quaternion(&mut r, 0.5),
        q_nodes: std::array::from_fn(|_| quaternion(&mut r, 0.5)),
        dt: 0.05,
        rest: mat3(&mut r, 5.0),
        moduli,
        d: strain_hessian(&moduli),
        v: std::array::from_fn(|_| vec3(&mut r, 0.2)),
        w: std::array::from_fn(|_| vec3(&mut r, 3.0)),
    }
}

fn context(c: &Case) -> ElementContext<'_, 4> {
    ElementContext {
        point: &c.point,
        x_start: c.x_start,
        point_quaternion: c.q_point,
        node_quaternions: c.q_nodes,
        dt: c.dt,
        rest_curvature: &c.rest,
        moduli: &c.moduli,
    }
}

fn unknowns(c: &Case) -> SVector<f64, 24> {
    SVector::from_fn(|i, _| {
        if i < 12 {
            c.v[i / 3][i % 3]
        } else {
            c.w[(i - 12) / 3][i % 3]
        }
    })
}

fn split<T: nalgebra::Scalar + Copy>(u: &SVector<T, 24>) -> ([Vector3<T>; 4], [Vector3<T>; 4]) {
    (
        std::array::from_fn(|i| Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2])),
        std::array::from_fn(|k| Vector3::new(u[12 + 3 * k], u[13 + 3 * k], u[14 + 3 * k])),
    )
}

fn oracle_value(c: &Case, u: &SVector<f64, 24>) -> f64 {
    let (v, w) = split(u);
    element_energy(&context(c), &v, &w)
}

fn fast(c: &Case, u: &SVector<f64, 24>) -> ElementDerivatives<24> {
    let (v, w) = split(u);
    let x: [Vector3<f64>; 4] = std::array::from_fn(|i| c.x_start[i] + v[i] * c.dt);
    let jets: [RotationJet; 4] = std::array::from_fn(|k| RotationJet::of_update(&c.q_nodes[k], &w[k], c.dt));
    let point_jet = RotationJet::of_update(&c.q_point, &point_omega(&c.point, &w), c.dt);
    let state = PointState {
        f: deformation_gradient(&c.point, &x),
        point_jet: &point_jet,
        node_jets: std::array::from_fn(|k| &jets[k]),
        rest_curvature: &c.rest,
    };
    let local = point_hessian::<4, 21>(&c.point, &state, &c.d);
    let (value, gradient) = point_gradient::<4, 21>(&c.point, &state, &c.d);
    assert_eq!(value, local.value);
    assert_eq!(gradient, local.gradient);
    let mut out = ElementDerivatives::zeros();
    accumulate(&c.point, &local, c.dt, c.point.weight, &mut out);
    out
}

#[test]
fn fast_hessian_equals_the_whole_element_dual_oracle() {
    for seed in 0..4 {
        let c = random_case(seed);
        let u = unknowns(&c);
        let fast = fast(&c, &u);
        let (value, gradient, hessian) = num_dual::hessian(
            |u: SVector<Dual2SVec64<24>, 24>| {
                let (v, w) = split(&u);
                element_energy(&context(&c), &v, &w)
            },
            &u,
        );
        // Both are exact up to round-off; the tolerance is a few hundred ulps of the largest entry.
        assert!(
            (fast.value - value).abs() <= 1e-12 * value.abs(),
            "value {} vs {value}",
            fast.value
        );
        let g_scale = amax(gradient.as_slice());
        assert!(
            amax((fast.gradient - gradient).as_slice()) <= 1e-11 * g_scale,
            "gradient, seed {seed}"
        );
        let h_scale = amax(hessian.as_slice());
        let err = amax((fast.hessian - hessian).as_slice());
        assert!(err <= 1e-11 * h_scale, "hessian error {err} of {h_scale}, seed {seed}");
    }
}

#[test]
fn f64_value_is_the_real_part_of_the_dual_evaluation() {
    let c = random_case(7);
    let u = unknowns(&c);
    let (v, w) = split(&u);
    let x: [Vector3<f64>; 4] = std::array::from_fn(|i| c.x_start[i] + v[i] * c.dt);
    let rp = rotation_matrix(&cosserat_geometry::rotation::quaternion_update(
        &c.q_point,
        &point_omega(&c.point, &w),
        c.dt,
    ));
    let node_r: [Matrix3<f64>; 4] = std::array::from_fn(|k| {
        rotation_matrix(&cosserat_geometry::rotation::quaternion_update(
            &c.q_nodes[k],
            &w[k],
            c.dt,
        ))
    });
    let f = deformation_gradient(&c.point, &x);
    let fast = c.point.weight * point_value(&c.point, &f, &rp, std::array::from_fn(|k| &node_r[k]), &c.rest, &c.d);
    let (dual, _, _) = num_dual::hessian(
        |u: SVector<Dual2SVec64<24>, 24>| {
            let (v, w) = split(&u);
            element_energy(&context(&c), &v, &w)
        },
        &u,
    );
    assert!((fast - oracle_value(&c, &u)).abs() <= 1e-12 * fast.abs());
    assert!((fast - dual).abs() <= 1e-12 * fast.abs());
}

#[test]
fn gradient_and_hessian_match_central_differences() {
    let c = random_case(11);
    let u = unknowns(&c);
    let d = fast(&c, &u);
    // Central differences have a truncation error O(h²) and a round-off error O(ε/h); with steps of
    // 1e-6 of the unknowns' scale both stay below 1e-6 of the largest entry.
    let h = 1e-6;
    let mut fd_grad = SVector::<f64, 24>::zeros();
    let mut fd_hess = SMatrix::<f64, 24, 24>::zeros();
    for i in 0..24 {
        let mut up = u;
        let mut um = u;
        up[i] += h;
        um[i] -= h;
        fd_grad[i] = (oracle_value(&c, &up) - oracle_value(&c, &um)) / (2.0 * h);
        let col = (fast(&c, &up).gradient - fast(&c, &um).gradient) / (2.0 * h);
        fd_hess.set_column(i, &col);
    }
    let g_err = amax((fd_grad - d.gradient).as_slice()) / amax(d.gradient.as_slice());
    let h_err = amax((fd_hess - d.hessian).as_slice()) / amax(d.hessian.as_slice());
    assert!(g_err < 1e-6, "gradient relative error {g_err}");
    assert!(h_err < 1e-6, "hessian relative error {h_err}");
}

#[test]
fn hessian_is_symmetric() {
    for seed in 20..24 {
        let c = random_case(seed);
        let h = fast(&c, &unknowns(&c)).hessian;
        let asym = amax((h - h.transpose()).as_slice());
        assert!(asym <= 1e-13 * amax(h.as_slice()), "asymmetry {asym}");
    }
}

#[test]
fn energy_and_gradient_vanish_at_rest_and_under_rigid_motion() {
    let mut r = rng(3);
    let x_rest = tet(&mut r);
    let point = tet4_point(&x_rest).unwrap();
    let moduli = MicropolarModuli::of(&material()).unwrap();
    let d = strain_hessian(&moduli);
    // Stress scale of the element: μ times volume over length.
    let scale = moduli.mu * point.weight / 0.1;
    for (q, omega, translation) in [
        (Quaternion::identity(), Vector3::zeros(), Vector3::zeros()),
        (quaternion(&mut r, 2.0), Vector3::zeros(), vec3(&mut r, 1.0)),
        (quaternion(&mut r, 2.0), vec3(&mut r, 5.0), vec3(&mut r, 1.0)),
    ] {
        let rot = rotation_matrix(&q);
        let dt = 0.05;
        let x_start = x_rest.map(|x| rot * x + translation);
        // A rigid rotation increment about the translated origin: x⁺ = cay(Δt ω) (x − c) + c.
        let inc = cayley(&(omega * dt));
        let v = x_start.map(|x| (inc * (x - translation) - (x - translation)) / dt);
        let c = Case {
            point,
            x_start,
            q_point: q,
            q_nodes: [q; 4],
            dt,
            rest: Matrix3::zeros(),
            moduli,
            d,
            v,
            w: [omega; 4],
        };
        let out = fast(&c, &unknowns(&c));
        assert!(out.value.abs() < 1e-20 * scale, "energy {}", out.value);
        assert!(
            amax(out.gradient.as_slice()) < 1e-10 * scale,
            "gradient {}",
            out.gradient
        );
    }
}

//! The fast kernel against the directly composed energy (dual-number oracle and finite differences),
//! rest and rigid-motion invariance, and frame indifference.

use super::common::{self, rel_err};
use cosserat_geometry::rotation::{RotationJet, quaternion_from_matrix, quaternion_product, rotation_matrix};
use cosserat_material::element::{ElementDerivatives, accumulate_upper, point_omega};
use cosserat_material::kernel::{PointInput, PointShape, point_gradient, point_hessian, point_value};
use cosserat_material::oracle::{PointContext, element_point_energy, local_energy};
use cosserat_material::strain_space::{DensityMatrix, StrainVector, local_geometry, strain_hessian, strain_offset};
use cosserat_material::{AxlVariant, CurvedTerms, ModelOptions, ShellModel, TermSet};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;
use rand_chacha::ChaCha8Rng;

/// A random point with its state: the inputs of both the kernel and the oracle.
#[derive(Clone, Copy)]
struct Case<const NU: usize, const NR: usize> {
    shape: PointShape<NU, NR>,
    b_world: Matrix3<f64>,
    offset: StrainVector,
    q_point: Quaternion<f64>,
    q_nodes: [Quaternion<f64>; NR],
    x_start: [Vector3<f64>; NU],
    velocity: [Vector3<f64>; NU],
    omega: [Vector3<f64>; NR],
    dt: f64,
}

impl<const NU: usize, const NR: usize> Case<NU, NR> {
    fn random(rng: &mut ChaCha8Rng, curved: bool) -> Self {
        let shape = common::shape::<NU, NR>(rng, 0.05);
        let b_world = if curved {
            common::curvature_tensor(rng, &shape.frame, 8.0)
        } else {
            Matrix3::zeros()
        };
        let offset = common::offset(rng, &shape.frame);
        Self {
            b_world,
            offset,
            q_point: common::quaternion(rng, 1.0),
            q_nodes: std::array::from_fn(|_| common::quaternion(rng, 1.0)),
            x_start: std::array::from_fn(|_| common::vec3(rng, 0.05)),
            velocity: std::array::from_fn(|_| common::vec3(rng, 0.2)),
            omega: std::array::from_fn(|_| common::vec3(rng, 3.0)),
            dt: 0.05,
            shape,
        }
    }

    fn positions(&self) -> [Vector3<f64>; NU] {
        std::array::from_fn(|i| self.x_start[i] + self.velocity[i] * self.dt)
    }

    /// The jets of the point rotation and of the nodal rotations at the end of the step.
    fn jets(&self) -> (RotationJet, [RotationJet; NR]) {
        let point = RotationJet::of_update(&self.q_point, &point_omega(&self.shape, &self.omega), self.dt);
        let nodes = std::array::from_fn(|k| RotationJet::of_update(&self.q_nodes[k], &self.omega[k], self.dt));
        (point, nodes)
    }

    /// The kernel's input at the case's state, from its [`Case::jets`].
    fn input<'a>(&'a self, point: &'a RotationJet, nodes: &'a [RotationJet; NR]) -> PointInput<'a, NR> {
        PointInput {
            f_hat: cosserat_material::element::f_hat(&self.shape, &self.positions()),
            point_jet: point,
            node_jets: std::array::from_fn(|k| &nodes[k]),
            offset: &self.offset,
        }
    }
}

fn terms_for(options: &ModelOptions, curved: bool) -> TermSet {
    TermSet::select(options, &common::material().moduli().unwrap(), curved).unwrap()
}

/// Fast kernel: local derivatives at the case's state, from the Hessian path and from the
/// gradient-only path (value and gradient).
fn fast<const NU: usize, const NR: usize, const NL: usize>(
    case: &Case<NU, NR>,
    terms: &TermSet,
    axl: AxlVariant,
) -> (cosserat_material::kernel::LocalDerivatives<NL>, (f64, SVector<f64, NL>)) {
    let moduli = common::material().moduli().unwrap();
    let geom = local_geometry(&case.shape.frame, &case.b_world);
    let d = DensityMatrix::new(strain_hessian(terms, &geom, &moduli));
    let (pj, nj) = case.jets();
    let input = case.input(&pj, &nj);
    (
        point_hessian::<NU, NR, NL>(&case.shape, &input, &d, axl),
        point_gradient::<NU, NR, NL>(&case.shape, &input, &d, axl),
    )
}

fn check_against_dual_oracle<const NU: usize, const NR: usize, const NL: usize>(
    seed: u64,
    options: ModelOptions,
    curved: bool,
) {
    let mut rng = common::rng(seed);
    let moduli = common::material().moduli().unwrap();
    for _ in 0..4 {
        let case = Case::<NU, NR>::random(&mut rng, curved);
        let terms = terms_for(&options, curved);
        let (got, (gradient_path_value, gradient_path)) = fast::<NU, NR, NL>(&case, &terms, options.axl);
        let geom = local_geometry(&case.shape.frame, &case.b_world);
        let ctx = PointContext {
            shape: &case.shape,
            point_quaternion: case.q_point,
            node_quaternions: case.q_nodes,
            dt: case.dt,
            offset: &case.offset,
            geometry: &geom,
            terms: &terms,
            moduli: &moduli,
            axl: options.axl,
        };
        let f = cosserat_material::element::f_hat(&case.shape, &case.positions());
        let x = SVector::<f64, NL>::from_fn(|i, _| {
            if i < 6 {
                f[i / 3][i % 3]
            } else {
                case.omega[(i - 6) / 3][(i - 6) % 3]
            }
        });
        let (value, gradient, hessian) = num_dual::hessian(
            |x: SVector<Dual2SVec64<NL>, NL>| {
                let f_hat = [Vector3::new(x[0], x[1], x[2]), Vector3::new(x[3], x[4], x[5])];
                let omega: [Vector3<Dual2SVec64<NL>>; NR] =
                    std::array::from_fn(|k| Vector3::new(x[6 + 3 * k], x[7 + 3 * k], x[8 + 3 * k]));
                local_energy(&ctx, &f_hat, &omega)
            },
            &x,
        );
        assert!(value > 0.0);
        // Both sides are exact; they differ only by round-off (about 1e-16 relative per operation,
        // accumulated over a few hundred operations).
        assert!(
            (got.value - value).abs() <= 1e-12 * value,
            "value {} vs {}",
            got.value,
            value
        );
        let eg = rel_err(&got.gradient, &gradient);
        let eh = rel_err(&got.hessian, &hessian);
        assert!(eg < 1e-11, "gradient relative error {eg:e}");
        // The gradient-only path (line searches, energy checks) against the oracle as well.
        assert!((gradient_path_value - value).abs() <= 1e-12 * value);
        let eg = rel_err(&gradient_path, &gradient);
        assert!(eg < 1e-11, "gradient-only path: gradient relative error {eg:e}");
        assert!(eh < 1e-11, "hessian relative error {eh:e}");
        assert!(
            rel_err(&got.hessian, &got.hessian.transpose()) < 1e-13,
            "hessian not symmetric"
        );
    }
}

fn shell(curved_terms: CurvedTerms, axl: AxlVariant) -> ModelOptions {
    ModelOptions {
        curved_terms,
        axl,
        ..ModelOptions::new(ShellModel::Shell)
    }
}

#[test]
fn plate_kernel_matches_dual_oracle_for_linear_and_quadratic_rotations() {
    common::with_big_stack(|| {
        check_against_dual_oracle::<3, 3, 15>(1, ModelOptions::new(ShellModel::Plate), false);
        check_against_dual_oracle::<6, 3, 15>(2, ModelOptions::new(ShellModel::Plate), false);
        check_against_dual_oracle::<6, 6, 24>(3, ModelOptions::new(ShellModel::Plate), false);
    });
}

#[test]
fn shell_kernel_matches_dual_oracle_on_curved_points() {
    common::with_big_stack(|| {
        check_against_dual_oracle::<6, 3, 15>(4, shell(CurvedTerms::Supplement, AxlVariant::SkewPart), true);
        check_against_dual_oracle::<6, 6, 24>(5, shell(CurvedTerms::Supplement, AxlVariant::SkewPart), true);
        let compat = shell(CurvedTerms::ReferenceCompatibility, AxlVariant::SkewPart);
        check_against_dual_oracle::<3, 3, 15>(6, compat, true);
    });
}

#[test]
fn upper_triangle_axl_variant_matches_dual_oracle() {
    common::with_big_stack(|| {
        let plate = ModelOptions {
            axl: AxlVariant::UpperTriangle,
            ..ModelOptions::new(ShellModel::Plate)
        };
        check_against_dual_oracle::<6, 3, 15>(7, plate, false);
        let shell = shell(CurvedTerms::Supplement, AxlVariant::UpperTriangle);
        check_against_dual_oracle::<6, 3, 15>(8, shell, true);
    });
}

/// Element energy (sum over one point) as a function of the element unknowns, in f64.
fn element_energy<const NU: usize, const NR: usize>(
    case: &Case<NU, NR>,
    terms: &TermSet,
    axl: AxlVariant,
    unknowns: &[f64],
) -> f64 {
    let moduli = common::material().moduli().unwrap();
    let geom = local_geometry(&case.shape.frame, &case.b_world);
    let ctx = PointContext {
        shape: &case.shape,
        point_quaternion: case.q_point,
        node_quaternions: case.q_nodes,
        dt: case.dt,
        offset: &case.offset,
        geometry: &geom,
        terms,
        moduli: &moduli,
        axl,
    };
    let v: [Vector3<f64>; NU] =
        std::array::from_fn(|i| Vector3::new(unknowns[3 * i], unknowns[3 * i + 1], unknowns[3 * i + 2]));
    let w: [Vector3<f64>; NR] = std::array::from_fn(|k| {
        let o = 3 * (NU + k);
        Vector3::new(unknowns[o], unknowns[o + 1], unknowns[o + 2])
    });
    element_point_energy(&ctx, &case.x_start, &v, &w)
}

fn element_fast<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    case: &Case<NU, NR>,
    terms: &TermSet,
    axl: AxlVariant,
) -> ElementDerivatives<NE> {
    let (local, _) = fast::<NU, NR, NL>(case, terms, axl);
    let mut out = ElementDerivatives::<NE>::zeros();
    accumulate_upper(&case.shape, &local, case.dt, case.shape.weight, &mut out);
    out.fill_lower_from_upper();
    out
}

fn check_element_finite_differences<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    seed: u64,
    options: ModelOptions,
    curved: bool,
) {
    let mut rng = common::rng(seed);
    let terms = terms_for(&options, curved);
    for _ in 0..2 {
        let case = Case::<NU, NR>::random(&mut rng, curved);
        let got = element_fast::<NU, NR, NL, NE>(&case, &terms, options.axl);
        let u0: Vec<f64> = (0..NE)
            .map(|i| {
                if i < 3 * NU {
                    case.velocity[i / 3][i % 3]
                } else {
                    case.omega[(i - 3 * NU) / 3][i % 3]
                }
            })
            .collect();
        let e0 = element_energy(&case, &terms, options.axl, &u0);
        assert!((got.value - e0).abs() <= 1e-12 * e0.abs());
        // Central differences with step 1e-6 (unknowns are O(1)): truncation ~1e-12 |f'''|, round-off
        // ~1e-16 |f| / 1e-6; both far below the 1e-6 relative tolerance.
        let step = 1e-6;
        let mut fd_grad = SVector::<f64, NE>::zeros();
        for i in 0..NE {
            let (mut up, mut um) = (u0.clone(), u0.clone());
            up[i] += step;
            um[i] -= step;
            fd_grad[i] = (element_energy(&case, &terms, options.axl, &up)
                - element_energy(&case, &terms, options.axl, &um))
                / (2.0 * step);
        }
        let eg = rel_err(&got.gradient, &fd_grad);
        assert!(eg < 1e-6, "gradient vs central differences: {eg:e}");
        // Hessian column i: central differences of the exact gradient along unknown i.
        let mut fd_hess = SMatrix::<f64, NE, NE>::zeros();
        for i in 0..NE {
            let shifted = |delta: f64| {
                let mut c = case;
                if i < 3 * NU {
                    c.velocity[i / 3][i % 3] += delta;
                } else {
                    c.omega[(i - 3 * NU) / 3][i % 3] += delta;
                }
                element_fast::<NU, NR, NL, NE>(&c, &terms, options.axl).gradient
            };
            let col = (shifted(step) - shifted(-step)) / (2.0 * step);
            fd_hess.set_column(i, &col);
        }
        let eh = common::scaled_max_error(&got.hessian, &fd_hess);
        assert!(eh < 1e-6, "hessian vs central differences: {eh:e}");
        assert!(rel_err(&got.hessian, &got.hessian.transpose()) < 1e-13);
    }
}

#[test]
fn element_derivatives_match_central_differences_for_every_element_pair() {
    let plate = ModelOptions::new(ShellModel::Plate);
    let sh = shell(CurvedTerms::Supplement, AxlVariant::SkewPart);
    check_element_finite_differences::<3, 3, 15, 18>(11, plate, false);
    check_element_finite_differences::<6, 3, 15, 27>(12, plate, false);
    check_element_finite_differences::<6, 6, 24, 36>(13, plate, false);
    check_element_finite_differences::<3, 3, 15, 18>(14, sh, true);
    check_element_finite_differences::<6, 3, 15, 27>(15, sh, true);
    check_element_finite_differences::<6, 6, 24, 36>(16, sh, true);
}

/// The rest state of a point in its frame: `F̂ = [t₁ t₂]`, identity rotations, default offset.
fn rest_case<const NU: usize, const NR: usize>(
    rng: &mut ChaCha8Rng,
) -> (PointShape<NU, NR>, Matrix3<f64>, StrainVector) {
    let shape = common::shape::<NU, NR>(rng, 0.05);
    let b = common::curvature_tensor(rng, &shape.frame, 8.0);
    let offset = strain_offset(&shape.frame, None, None);
    (shape, b, offset)
}

#[test]
fn rest_state_and_rigid_motions_have_zero_energy_and_gradient_for_the_curved_shell() {
    let mut rng = common::rng(21);
    let moduli = common::material().moduli().unwrap();
    let terms = terms_for(&shell(CurvedTerms::Supplement, AxlVariant::SkewPart), true);
    for _ in 0..5 {
        let (shape, b, offset) = rest_case::<6, 3>(&mut rng);
        let d = DensityMatrix::new(strain_hessian(&terms, &local_geometry(&shape.frame, &b), &moduli));
        // A rigid rotation q of everything, then a common angular velocity ω over a step of dt: the
        // point and all nodes turn by the same cay(dt ω) q, and so do the tangents.
        let q = common::quaternion(&mut rng, 3.0);
        let omega = common::vec3(&mut rng, 4.0);
        let dt = 0.1;
        for (q, omega) in [
            (Quaternion::identity(), Vector3::zeros()),
            (q, Vector3::zeros()),
            (q, omega),
        ] {
            let pj = RotationJet::of_update(&q, &omega, dt);
            let nj = [pj; 3];
            let t = shape.frame.fixed_columns::<2>(0);
            let f_hat = [pj.r * t.column(0), pj.r * t.column(1)];
            let input = PointInput {
                f_hat,
                point_jet: &pj,
                node_jets: [&nj[0], &nj[1], &nj[2]],
                offset: &offset,
            };
            let out = point_hessian::<6, 3, 15>(&shape, &input, &d, AxlVariant::SkewPart);
            assert!(out.value.abs() < 1e-20, "energy at a rigid motion: {:e}", out.value);
            let scale = d.matrix().amax();
            assert!(
                out.gradient.amax() < 1e-12 * scale,
                "gradient at a rigid motion: {:e}",
                out.gradient.amax()
            );
        }
    }
}

#[test]
fn energy_is_frame_indifferent() {
    let mut rng = common::rng(31);
    let moduli = common::material().moduli().unwrap();
    for curved in [false, true] {
        let options = if curved {
            shell(CurvedTerms::Supplement, AxlVariant::SkewPart)
        } else {
            ModelOptions::new(ShellModel::Plate)
        };
        let terms = terms_for(&options, curved);
        let case = Case::<6, 3>::random(&mut rng, curved);
        let d = DensityMatrix::new(strain_hessian(
            &terms,
            &local_geometry(&case.shape.frame, &case.b_world),
            &moduli,
        ));
        let value = |f_hat: [Vector3<f64>; 2], q_point: Quaternion<f64>, q_nodes: [Quaternion<f64>; 3]| {
            let r = rotation_matrix(&q_point);
            let rn = q_nodes.map(|q| rotation_matrix(&q));
            point_value(
                &case.shape,
                &f_hat,
                &r,
                [&rn[0], &rn[1], &rn[2]],
                &case.offset,
                &d,
                AxlVariant::SkewPart,
            )
        };
        let f = cosserat_material::element::f_hat(&case.shape, &case.positions());
        let e0 = value(f, case.q_point, case.q_nodes);
        let rot = common::rotation(&mut rng, 3.0);
        let qr = quaternion_from_matrix(&rot);
        let e1 = value(
            [rot * f[0], rot * f[1]],
            quaternion_product(&qr, &case.q_point),
            case.q_nodes.map(|q| quaternion_product(&qr, &q)),
        );
        assert!(e0 > 0.0);
        assert!((e1 - e0).abs() < 1e-12 * e0, "{e0} vs {e1}");
    }
}

/// The products over the density's nonzero entries are the dense products, to the last bit, for the
/// plate's sparse matrix and for the curved shell's denser ones.
#[test]
fn sparse_density_products_equal_the_dense_ones() {
    use cosserat_material::strain_space::VARIABLE_STRAINS;
    let mut rng = common::rng(31);
    let moduli = common::material().moduli().unwrap();
    let plate = terms_for(&ModelOptions::new(ShellModel::Plate), false);
    let curved = terms_for(&shell(CurvedTerms::Supplement, AxlVariant::SkewPart), true);
    for (terms, is_curved) in [(&plate, false), (&curved, true), (&curved, true)] {
        let (shape, b, _) = rest_case::<6, 3>(&mut rng);
        let b = if is_curved { b } else { Matrix3::zeros() };
        let d = DensityMatrix::new(strain_hessian(terms, &local_geometry(&shape.frame, &b), &moduli));
        let m = d.matrix();
        let variable = d.variable_entries();
        let nonzero = VARIABLE_STRAINS
            .iter()
            .flat_map(|&i| VARIABLE_STRAINS.iter().map(move |&j| (i, j)))
            .filter(|&(i, j)| m[(i, j)] != 0.0)
            .count();
        assert_eq!(variable.len(), nonzero);
        assert!(variable.len() < 144, "{} entries", variable.len());
        for e in variable {
            assert_eq!(
                e.value,
                m[(VARIABLE_STRAINS[e.row as usize], VARIABLE_STRAINS[e.col as usize])]
            );
        }
        for _ in 0..10 {
            let s = StrainVector::from_fn(|_, _| common::vec3(&mut rng, 1.0).x);
            assert_eq!(d.mul_vector(&s), m * s);
        }
    }
}

/// An element's first point may overwrite the upper block triangle instead of adding to it: the
/// result is the same, and the blocks below the block diagonal are neither read nor written.
#[test]
fn assigning_the_first_point_equals_adding_it_to_zero() {
    use cosserat_material::element::assign_upper;
    let mut rng = common::rng(41);
    let terms = terms_for(&ModelOptions::new(ShellModel::Plate), false);
    let first = Case::<6, 3>::random(&mut rng, false);
    let second = Case::<6, 3>::random(&mut rng, false);
    let (l1, _) = fast::<6, 3, 15>(&first, &terms, AxlVariant::SkewPart);
    let (l2, _) = fast::<6, 3, 15>(&second, &terms, AxlVariant::SkewPart);
    let mut added = ElementDerivatives::<27>::zeros();
    accumulate_upper(&first.shape, &l1, first.dt, 0.3, &mut added);
    accumulate_upper(&second.shape, &l2, second.dt, 0.7, &mut added);
    let mut assigned = ElementDerivatives::<27>::zeros();
    assigned.hessian.fill(f64::NAN);
    assign_upper(&first.shape, &l1, first.dt, 0.3, &mut assigned);
    accumulate_upper(&second.shape, &l2, second.dt, 0.7, &mut assigned);
    assert_eq!(assigned.value, added.value);
    assert_eq!(assigned.gradient, added.gradient);
    for c in 0..27 {
        for r in 0..27 {
            if r < 3 * (c / 3 + 1) {
                assert_eq!(assigned.hessian[(r, c)], added.hessian[(r, c)], "({r}, {c})");
            } else {
                assert!(assigned.hessian[(r, c)].is_nan(), "({r}, {c}) written");
            }
        }
    }
    assigned.clear_below_block_diagonal();
    added.clear_below_block_diagonal();
    assert_eq!(assigned, added);
}

/// The strains' linearisation of the mixed-integration-point Newton method is their derivative: against
/// central differences along a random change of velocities and angular velocities, for linear and
/// quadratic rotation elements on curved points.
#[test]
fn linearized_strains_are_the_derivative_of_the_strains() {
    check_linearized_strains::<6, 3>(41);
    check_linearized_strains::<6, 6>(42);
    check_linearized_strains::<3, 3>(43);
}

fn check_linearized_strains<const NU: usize, const NR: usize>(seed: u64) {
    use cosserat_geometry::rotation::quaternion_update;
    use cosserat_material::kernel::{linearized_membrane_strains, linearized_strains, strain_vector};
    let mut rng = common::rng(seed);
    for _ in 0..4 {
        let case = Case::<NU, NR>::random(&mut rng, true);
        let dv: [Vector3<f64>; NU] = std::array::from_fn(|_| common::vec3(&mut rng, 0.2));
        let dw: [Vector3<f64>; NR] = std::array::from_fn(|_| common::vec3(&mut rng, 3.0));
        let strains_at = |t: f64| {
            let mut c = case;
            for (v, d) in c.velocity.iter_mut().zip(&dv) {
                *v += d * t;
            }
            for (w, d) in c.omega.iter_mut().zip(&dw) {
                *w += d * t;
            }
            let r = rotation_matrix(&quaternion_update(&c.q_point, &point_omega(&c.shape, &c.omega), c.dt));
            let nodes: [Matrix3<f64>; NR] =
                std::array::from_fn(|k| rotation_matrix(&quaternion_update(&c.q_nodes[k], &c.omega[k], c.dt)));
            let f = cosserat_material::element::f_hat(&c.shape, &c.positions());
            strain_vector(
                &c.shape,
                &f,
                &r,
                std::array::from_fn(|k| &nodes[k]),
                &c.offset,
                AxlVariant::SkewPart,
            )
        };
        let (pj, nj) = case.jets();
        let input = case.input(&pj, &nj);
        let dx: [Vector3<f64>; NU] = std::array::from_fn(|i| dv[i] * case.dt);
        let d_f_hat = cosserat_material::element::f_hat(&case.shape, &dx);
        let (s, ds) = linearized_strains::<NU, NR>(&case.shape, &input, AxlVariant::SkewPart, &d_f_hat, &dw);
        assert!(rel_err(&s, &strains_at(0.0)) < 1e-14, "strains differ from the point's");
        // A tying point's linearisation: the same membrane strains and rates, nothing else.
        let (sm, dsm) = linearized_membrane_strains::<NU, NR>(&case.shape, &input, &d_f_hat, &dw);
        for i in 0..18 {
            let membrane = i < 6;
            assert_eq!(sm[i], if membrane { s[i] } else { 0.0 }, "membrane strain {i}");
            assert_eq!(dsm[i], if membrane { ds[i] } else { 0.0 }, "membrane rate {i}");
        }
        let eps = 1e-6;
        let fd = (strains_at(eps) - strains_at(-eps)) / (2.0 * eps);
        let err = rel_err(&ds, &fd);
        assert!(err < 1e-7, "linearised strains against central differences: {err:e}");
        assert!(ds.norm() > 1e-3, "a trivial direction");
    }
}

/// The mixed-integration-point Hessian weights only its second-order terms with the predicted strains:
/// with the point's own strains it is the exact Hessian, and it is affine in the predicted strains;
/// energy and gradient are the point's.
#[test]
fn predicted_strains_weight_only_the_second_order_terms() {
    use cosserat_material::kernel::{LocalDerivatives, point_hessian_deferred_into, point_hessian_predicted_into};
    let mut rng = common::rng(44);
    let options = shell(CurvedTerms::Supplement, AxlVariant::SkewPart);
    let terms = terms_for(&options, true);
    let moduli = common::material().moduli().unwrap();
    for _ in 0..4 {
        let case = Case::<6, 3>::random(&mut rng, true);
        let geom = local_geometry(&case.shape.frame, &case.b_world);
        let d = DensityMatrix::new(strain_hessian(&terms, &geom, &moduli));
        let (pj, nj) = case.jets();
        let input = case.input(&pj, &nj);
        let own = cosserat_material::kernel::strain_vector(
            &case.shape,
            &input.f_hat,
            &pj.r,
            std::array::from_fn(|k| &nj[k].r),
            &case.offset,
            AxlVariant::SkewPart,
        );
        let hessian = |predicted: Option<&StrainVector>| {
            let mut out = LocalDerivatives::<15>::zeros();
            let w = point_hessian_predicted_into(&case.shape, &input, &d, AxlVariant::SkewPart, predicted, &mut out);
            (out, w)
        };
        let mut exact = LocalDerivatives::<15>::zeros();
        let w_exact = point_hessian_deferred_into(&case.shape, &input, &d, AxlVariant::SkewPart, &mut exact);
        let (with_own, w_own) = hessian(Some(&own));
        assert!(rel_err(&with_own.hessian, &exact.hessian) < 1e-14);
        assert!(w_own.iter().zip(&w_exact).all(|(a, b)| rel_err(a, b) < 1e-14));
        let delta = StrainVector::from_fn(|i, _| {
            if [6, 7, 8, 15, 16, 17].contains(&i) {
                0.0
            } else {
                own.norm()
            }
        });
        let (one, _) = hessian(Some(&(own + delta)));
        let (two, _) = hessian(Some(&(own + delta * 2.0)));
        assert_eq!(one.value.to_bits(), exact.value.to_bits());
        assert_eq!(one.gradient, exact.gradient);
        let first = one.hessian - exact.hessian;
        assert!(
            first.norm() > 1e-6 * exact.hessian.norm(),
            "the prediction changes nothing"
        );
        assert!(rel_err(&(two.hessian - exact.hessian), &(first * 2.0)) < 1e-10);
    }
}

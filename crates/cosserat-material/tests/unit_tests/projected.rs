//! The stabilised strain projection's element kernel against an element energy composed directly
//! (dual-number oracle, with the projection written on the strain tensors) and against central
//! differences of its own gradient.

use super::common::{self, rel_err};
use cosserat_geometry::Real;
use cosserat_geometry::rotation::RotationJet;
use cosserat_material::coupled::Coupling;
use cosserat_material::element::{ElementDerivatives, point_omega};
use cosserat_material::kernel::{LocalDerivatives, PointInput, PointShape, add_node_second_derivatives};
use cosserat_material::oracle::{PointContext, f_hat_of, local_strains};
use cosserat_material::projected::{ElementPoint, ValuePoint};
use cosserat_material::strain_space::{DensityMatrix, StrainVector, local_geometry, strain_hessian};
use cosserat_material::{
    AxlVariant, MaterialParameters, ModelOptions, ShellModel, StrainProjection, TermSet, density::density,
};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;

const N_POINTS: usize = 3;

fn material() -> MaterialParameters {
    let mut m = MaterialParameters::new(0.01, 1e6, 0.3, 1000.0, 0.02);
    m.curvature_coefficients = [1.0, 0.7, 0.2];
    m.mu_c_factor = 0.8;
    m
}

/// An element of three random points sharing the nodal state.
struct Element<const NU: usize, const NR: usize> {
    shapes: [PointShape<NU, NR>; N_POINTS],
    b_world: [Matrix3<f64>; N_POINTS],
    /// Whether the points share one density matrix (flat elements, or [`Element::with_shared_density`]).
    shared_density: bool,
    offsets: [StrainVector; N_POINTS],
    q_points: [Quaternion<f64>; N_POINTS],
    q_nodes: [Quaternion<f64>; NR],
    x_start: [Vector3<f64>; NU],
    dt: f64,
    projection: StrainProjection,
    terms: TermSet,
}

impl<const NU: usize, const NR: usize> Element<NU, NR> {
    fn random(seed: u64, curved: bool) -> Self {
        let mut rng = common::rng(seed);
        let shapes: [PointShape<NU, NR>; N_POINTS] = std::array::from_fn(|_| common::shape(&mut rng, 0.05));
        let b_world = std::array::from_fn(|p| {
            if curved {
                common::curvature_tensor(&mut rng, &shapes[p].frame, 8.0)
            } else {
                Matrix3::zeros()
            }
        });
        let offsets = std::array::from_fn(|p| common::offset(&mut rng, &shapes[p].frame));
        let moduli = material().moduli().unwrap();
        Self {
            b_world,
            offsets,
            q_points: std::array::from_fn(|_| common::quaternion(&mut rng, 1.0)),
            q_nodes: std::array::from_fn(|_| common::quaternion(&mut rng, 1.0)),
            x_start: std::array::from_fn(|_| common::vec3(&mut rng, 0.05)),
            dt: 0.05,
            projection: StrainProjection {
                membrane: 0.3,
                drilling: 0.6,
                shear: 0.1,
            },
            terms: TermSet::select(&ModelOptions::new(ShellModel::Shell), &moduli, curved).unwrap(),
            shapes,
            shared_density: !curved,
        }
    }

    /// The same element with the frame and curvature of its first point at every point, so that its
    /// points share one density (which couples `Ê` to `Γ` where the element is curved).
    fn with_shared_density(mut self) -> Self {
        let (frame, b) = (self.shapes[0].frame, self.b_world[0]);
        for (shape, b_world) in self.shapes.iter_mut().zip(&mut self.b_world) {
            shape.frame = frame;
            *b_world = b;
        }
        self.shared_density = true;
        self
    }

    fn densities(&self) -> Vec<DensityMatrix> {
        let moduli = material().moduli().unwrap();
        (0..N_POINTS)
            .map(|p| {
                let geom = local_geometry(&self.shapes[p].frame, &self.b_world[p]);
                DensityMatrix::new(strain_hessian(&self.terms, &geom, &moduli))
            })
            .collect()
    }

    fn split(&self, u: &[f64]) -> ([Vector3<f64>; NU], [Vector3<f64>; NR]) {
        let x = std::array::from_fn(|i| self.x_start[i] + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]) * self.dt);
        let w = std::array::from_fn(|k| {
            let o = 3 * (NU + k);
            Vector3::new(u[o], u[o + 1], u[o + 2])
        });
        (x, w)
    }

    /// The fast kernels: energy, gradient and full Hessian in the element unknowns.
    fn fast<const NL: usize, const NE: usize>(&self, u: &[f64], with_hessian: bool) -> ElementDerivatives<NE> {
        let (x, omega) = self.split(u);
        let d = self.densities();
        let shared = self.shared_density;
        let node_jets: Vec<RotationJet> = (0..NR)
            .map(|k| RotationJet::of_update(&self.q_nodes[k], &omega[k], self.dt))
            .collect();
        let node_jets: [&RotationJet; NR] = std::array::from_fn(|k| &node_jets[k]);
        let jets: Vec<RotationJet> = (0..N_POINTS)
            .map(|p| RotationJet::of_update(&self.q_points[p], &point_omega(&self.shapes[p], &omega), self.dt))
            .collect();
        let points: Vec<ElementPoint<'_, NU, NR>> = (0..N_POINTS)
            .map(|p| ElementPoint {
                shape: &self.shapes[p],
                input: PointInput {
                    f_hat: cosserat_material::element::f_hat(&self.shapes[p], &x),
                    point_jet: &jets[p],
                    node_jets,
                    offset: &self.offsets[p],
                },
                // Points with equal densities share one, as in an assembled shell.
                density: if shared { &d[0] } else { &d[p] },
            })
            .collect();
        let mut out = ElementDerivatives::<NE>::zeros();
        if with_hessian {
            let mut local = LocalDerivatives::<NL>::zeros();
            let weights = Coupling::Projection(&self.projection).element_hessian(
                &points,
                AxlVariant::SkewPart,
                None,
                self.dt,
                &mut local,
                &mut out,
            );
            for (k, w) in weights.iter().enumerate() {
                add_node_second_derivatives(&mut out.hessian, 3 * (NU + k), node_jets[k], w);
            }
            out.fill_lower_from_upper();
        } else {
            Coupling::Projection(&self.projection).element_gradient::<NU, NR, NL, NE>(
                &points,
                AxlVariant::SkewPart,
                None,
                self.dt,
                &mut out,
            );
        }
        out
    }

    fn fast_value(&self, u: &[f64]) -> f64 {
        let (x, omega) = self.split(u);
        let d = self.densities();
        let node_r: Vec<Matrix3<f64>> = (0..NR)
            .map(|k| RotationJet::of_update(&self.q_nodes[k], &omega[k], self.dt).r)
            .collect();
        let points: Vec<ValuePoint<'_, NU, NR>> = (0..N_POINTS)
            .map(|p| ValuePoint {
                shape: &self.shapes[p],
                f_hat: cosserat_material::element::f_hat(&self.shapes[p], &x),
                r: RotationJet::of_update(&self.q_points[p], &point_omega(&self.shapes[p], &omega), self.dt).r,
                offset: &self.offsets[p],
                density: &d[p],
            })
            .collect();
        Coupling::Projection(&self.projection).element_value(
            &points,
            std::array::from_fn(|k| &node_r[k]),
            AxlVariant::SkewPart,
            None,
        )
    }

    /// The oracle: strains composed directly, projected on the strain tensors, densities term by term.
    fn oracle<T: Real>(&self, u: &[T]) -> T {
        let moduli = material().moduli().unwrap();
        let x: [Vector3<T>; NU] = std::array::from_fn(|i| {
            self.x_start[i].cast::<T>() + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]) * T::from(self.dt)
        });
        let w: [Vector3<T>; NR] = std::array::from_fn(|k| {
            let o = 3 * (NU + k);
            Vector3::new(u[o], u[o + 1], u[o + 2])
        });
        let geoms: Vec<_> = (0..N_POINTS)
            .map(|p| local_geometry(&self.shapes[p].frame, &self.b_world[p]))
            .collect();
        let strains: Vec<(Matrix3<T>, Matrix3<T>)> = (0..N_POINTS)
            .map(|p| {
                let ctx = PointContext {
                    shape: &self.shapes[p],
                    point_quaternion: self.q_points[p],
                    node_quaternions: self.q_nodes,
                    dt: self.dt,
                    offset: &self.offsets[p],
                    geometry: &geoms[p],
                    terms: &self.terms,
                    moduli: &moduli,
                    axl: AxlVariant::SkewPart,
                };
                local_strains(&ctx, &f_hat_of(&self.shapes[p], &x), &w)
            })
            .collect();
        let total: f64 = self.shapes.iter().map(|s| s.weight).sum();
        let mut mean = Matrix3::<T>::zeros();
        for (p, (e, _)) in strains.iter().enumerate() {
            mean += e * T::from(self.shapes[p].weight / total);
        }
        // The tangential block P E P splits into its symmetric (membrane) and skew (drilling) parts; the
        // normal row of the first two columns is the transverse shear; the rest is kept.
        let tangential = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0)).cast::<T>();
        let normal_row = Matrix3::from_fn(|r, c| if r == 2 && c < 2 { 1.0 } else { 0.0 });
        let scale = |m: &Matrix3<T>| {
            let t = tangential * m * tangential;
            let sym = (t + t.transpose()) * T::from(0.5);
            let skw = (t - t.transpose()) * T::from(0.5);
            let shear = m.component_mul(&normal_row.cast::<T>());
            sym * T::from(1.0 - self.projection.membrane)
                + skw * T::from(1.0 - self.projection.drilling)
                + shear * T::from(1.0 - self.projection.shear)
        };
        let mut energy = T::zero();
        for (p, (e, g)) in strains.iter().enumerate() {
            let projected = e - scale(&(e - mean));
            energy += density(&self.terms, &projected, g, &geoms[p], &moduli) * T::from(self.shapes[p].weight);
        }
        energy
    }
}

fn check<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    seed: u64,
    curved: bool,
    shared_density: bool,
    projection: StrainProjection,
) {
    let mut el = Element::<NU, NR>::random(seed, curved);
    if shared_density {
        el = el.with_shared_density();
    }
    el.projection = projection;
    let mut rng = common::rng(seed + 100);
    let u: Vec<f64> = (0..NE)
        .map(|i| common::vec3(&mut rng, if i < 3 * NU { 0.2 } else { 3.0 })[0])
        .collect();
    let got = el.fast::<NL, NE>(&u, true);
    let grad_only = el.fast::<NL, NE>(&u, false);
    assert!((got.value - el.fast_value(&u)).abs() <= 1e-12 * got.value.abs());
    assert!(rel_err(&grad_only.gradient, &got.gradient) < 1e-13);
    // Oracle: value, gradient and Hessian by second-order dual numbers, on a big stack.
    let uv = SVector::<f64, NE>::from_column_slice(&u);
    let (value, gradient, hessian) = num_dual::hessian(|v: SVector<Dual2SVec64<NE>, NE>| el.oracle(v.as_slice()), &uv);
    assert!(
        (got.value - value).abs() <= 1e-12 * value.abs(),
        "{} vs {value}",
        got.value
    );
    let eg = rel_err(&got.gradient, &gradient);
    assert!(eg < 1e-11, "gradient vs oracle: {eg:e}");
    let eh = rel_err(&got.hessian, &hessian);
    assert!(eh < 1e-10, "hessian vs oracle: {eh:e}");
    // Central differences of the fast gradient (step 1e-6 on O(1) unknowns).
    let step = 1e-6;
    let mut fd = SMatrix::<f64, NE, NE>::zeros();
    for i in 0..NE {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += step;
        um[i] -= step;
        let col = (el.fast::<NL, NE>(&up, false).gradient - el.fast::<NL, NE>(&um, false).gradient) / (2.0 * step);
        fd.set_column(i, &col);
    }
    let row_max: Vec<f64> = (0..NE).map(|i| got.hessian.row(i).amax()).collect();
    let mut e: f64 = 0.0;
    for i in 0..NE {
        for j in 0..NE {
            let scale = (row_max[i] * row_max[j]).sqrt().max(1e-300);
            e = e.max((got.hessian[(i, j)] - fd[(i, j)]).abs() / scale);
        }
    }
    assert!(e < 1e-6, "hessian vs central differences: {e:e}");
}

#[test]
fn projected_element_matches_the_dual_oracle_and_central_differences() {
    // Equal membrane and drilling factors make `P` diagonal (the default constants, whose densities
    // are scaled on the fly); unequal ones couple the tangential pair (formed densities).
    let diagonal = StrainProjection {
        membrane: 0.3,
        drilling: 0.3,
        shear: 0.1,
    };
    let coupled = StrainProjection {
        drilling: 0.6,
        ..diagonal
    };
    common::with_big_stack(move || {
        // Flat (one shared density without coupling of `Ê` to `Γ`), curved with a density per point,
        // and curved with one shared density.
        for projection in [diagonal, coupled] {
            check::<6, 3, 15, 27>(41, false, false, projection);
            check::<6, 3, 15, 27>(42, true, false, projection);
            check::<6, 3, 15, 27>(45, true, true, projection);
            check::<3, 3, 15, 18>(43, true, false, projection);
        }
    });
}

/// With every factor 1 the projection is the identity: the paper's element.
#[test]
fn unit_factors_give_the_paper_energy() {
    let mut el = Element::<6, 3>::random(44, true);
    el.projection = StrainProjection {
        membrane: 1.0,
        drilling: 1.0,
        shear: 1.0,
    };
    let u = vec![0.1; 27];
    let paper: f64 = {
        let (x, omega) = el.split(&u);
        let d = el.densities();
        let node_r: Vec<Matrix3<f64>> = (0..3)
            .map(|k| RotationJet::of_update(&el.q_nodes[k], &omega[k], el.dt).r)
            .collect();
        (0..N_POINTS)
            .map(|p| {
                let r = RotationJet::of_update(&el.q_points[p], &point_omega(&el.shapes[p], &omega), el.dt).r;
                let f = cosserat_material::element::f_hat(&el.shapes[p], &x);
                el.shapes[p].weight
                    * cosserat_material::kernel::point_value(
                        &el.shapes[p],
                        &f,
                        &r,
                        std::array::from_fn(|k| &node_r[k]),
                        &el.offsets[p],
                        &d[p],
                        AxlVariant::SkewPart,
                    )
            })
            .sum()
    };
    assert!((el.fast_value(&u) - paper).abs() <= 1e-14 * paper.abs());
}

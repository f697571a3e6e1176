//! A random element for the tests of the coupled element kernel (`cosserat_material::coupled`): points
//! sharing one nodal state, the fast kernels through a [`Coupling`], the points' strains composed
//! directly for an oracle, and the check of a kernel against its oracle (dual numbers) and against
//! central differences of its own gradient. The stabilised projection's and the assumed strains' tests
//! differ only in their coupling and in how their oracle combines the points' strains.

use super::common::{self, rel_err};
use cosserat_geometry::Real;
use cosserat_geometry::rotation::RotationJet;
use cosserat_material::coupled::Coupling;
use cosserat_material::density::{PointGeometry, density};
use cosserat_material::element::{ElementDerivatives, f_hat, point_omega};
use cosserat_material::kernel::{LocalDerivatives, PointInput, PointShape, add_node_second_derivatives};
use cosserat_material::oracle::{PointContext, f_hat_of, local_strains};
use cosserat_material::projected::{ElementPoint, ValuePoint};
use cosserat_material::strain_space::{DensityMatrix, StrainVector, local_geometry, strain_hessian};
use cosserat_material::{AxlVariant, ModelOptions, ShellModel, TermSet};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;
use rand_chacha::ChaCha8Rng;

/// Each point's strains `(Ê, Γ̂)`.
pub type PointStrains<T> = Vec<(Matrix3<T>, Matrix3<T>)>;

/// An element of random points sharing the nodal state.
pub struct CoupledElement<const NU: usize, const NR: usize> {
    pub shapes: Vec<PointShape<NU, NR>>,
    pub b_world: Vec<Matrix3<f64>>,
    pub offsets: Vec<StrainVector>,
    pub q_points: Vec<Quaternion<f64>>,
    pub q_nodes: [Quaternion<f64>; NR],
    pub x_start: [Vector3<f64>; NU],
    pub dt: f64,
    pub terms: TermSet,
    /// Whether the points share one density matrix (flat elements, or [`Self::with_shared_density`]),
    /// as they do in an assembled shell.
    pub shared_density: bool,
}

impl<const NU: usize, const NR: usize> CoupledElement<NU, NR> {
    /// `n_points` random points, curved or flat.
    pub fn random(rng: &mut ChaCha8Rng, n_points: usize, curved: bool) -> Self {
        let shapes: Vec<PointShape<NU, NR>> = (0..n_points).map(|_| common::shape(rng, 0.05)).collect();
        let b_world = shapes
            .iter()
            .map(|s| {
                if curved {
                    common::curvature_tensor(rng, &s.frame, 8.0)
                } else {
                    Matrix3::zeros()
                }
            })
            .collect();
        let offsets = shapes.iter().map(|s| common::offset(rng, &s.frame)).collect();
        let moduli = common::material().moduli().unwrap();
        Self {
            b_world,
            offsets,
            q_points: (0..n_points).map(|_| common::quaternion(rng, 1.0)).collect(),
            q_nodes: std::array::from_fn(|_| common::quaternion(rng, 1.0)),
            x_start: std::array::from_fn(|_| common::vec3(rng, 0.05)),
            dt: 0.05,
            terms: TermSet::select(&ModelOptions::new(ShellModel::Shell), &moduli, curved).unwrap(),
            shapes,
            shared_density: !curved,
        }
    }

    /// The same element with the frame and curvature of its first point at every point, so that its
    /// points share one density (which couples `Ê` to `Γ` where the element is curved).
    pub fn with_shared_density(mut self) -> Self {
        let (frame, b) = (self.shapes[0].frame, self.b_world[0]);
        for (shape, b_world) in self.shapes.iter_mut().zip(&mut self.b_world) {
            shape.frame = frame;
            *b_world = b;
        }
        self.shared_density = true;
        self
    }

    /// The density Hessian of each point.
    pub fn densities(&self) -> Vec<DensityMatrix> {
        let moduli = common::material().moduli().unwrap();
        self.shapes
            .iter()
            .zip(&self.b_world)
            .map(|(s, b)| DensityMatrix::new(strain_hessian(&self.terms, &local_geometry(&s.frame, b), &moduli)))
            .collect()
    }

    /// Node positions and rotation updates of the unknowns `u` (velocities and angular velocities).
    pub fn split(&self, u: &[f64]) -> ([Vector3<f64>; NU], [Vector3<f64>; NR]) {
        let x = std::array::from_fn(|i| self.x_start[i] + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]) * self.dt);
        let w = std::array::from_fn(|k| {
            let o = 3 * (NU + k);
            Vector3::new(u[o], u[o + 1], u[o + 2])
        });
        (x, w)
    }

    /// The fast kernels: energy, gradient and full Hessian in the element unknowns.
    pub fn fast<const NL: usize, const NE: usize>(
        &self,
        coupling: Coupling<'_>,
        u: &[f64],
        with_hessian: bool,
    ) -> ElementDerivatives<NE> {
        let (x, omega) = self.split(u);
        let d = self.densities();
        let node_jets: Vec<RotationJet> = (0..NR)
            .map(|k| RotationJet::of_update(&self.q_nodes[k], &omega[k], self.dt))
            .collect();
        let node_jets: [&RotationJet; NR] = std::array::from_fn(|k| &node_jets[k]);
        let jets: Vec<RotationJet> = self
            .shapes
            .iter()
            .zip(&self.q_points)
            .map(|(s, q)| RotationJet::of_update(q, &point_omega(s, &omega), self.dt))
            .collect();
        let points: Vec<ElementPoint<'_, NU, NR>> = (0..self.shapes.len())
            .map(|p| ElementPoint {
                shape: &self.shapes[p],
                input: PointInput {
                    f_hat: f_hat(&self.shapes[p], &x),
                    point_jet: &jets[p],
                    node_jets,
                    offset: &self.offsets[p],
                },
                density: if self.shared_density { &d[0] } else { &d[p] },
            })
            .collect();
        let mut out = ElementDerivatives::<NE>::zeros();
        if with_hessian {
            let mut local = LocalDerivatives::<NL>::zeros();
            let weights =
                coupling.element_hessian(&points, AxlVariant::SkewPart, None, self.dt, None, &mut local, &mut out);
            for (k, w) in weights.iter().enumerate() {
                add_node_second_derivatives(&mut out.hessian, 3 * (NU + k), node_jets[k], w);
            }
            out.fill_lower_from_upper();
        } else {
            coupling.element_gradient::<NU, NR, NL, NE>(&points, AxlVariant::SkewPart, None, self.dt, &mut out);
        }
        out
    }

    /// The fast energy alone.
    pub fn fast_value(&self, coupling: Coupling<'_>, u: &[f64]) -> f64 {
        let (x, omega) = self.split(u);
        let d = self.densities();
        let node_r: Vec<Matrix3<f64>> = (0..NR)
            .map(|k| RotationJet::of_update(&self.q_nodes[k], &omega[k], self.dt).r)
            .collect();
        let points: Vec<ValuePoint<'_, NU, NR>> = (0..self.shapes.len())
            .map(|p| ValuePoint {
                shape: &self.shapes[p],
                f_hat: f_hat(&self.shapes[p], &x),
                r: RotationJet::of_update(&self.q_points[p], &point_omega(&self.shapes[p], &omega), self.dt).r,
                offset: &self.offsets[p],
                density: &d[p],
            })
            .collect();
        coupling.element_value(&points, std::array::from_fn(|k| &node_r[k]), AxlVariant::SkewPart, None)
    }

    /// The oracle's part common to the couplings: each point's strains `(Ê, Γ̂)` composed directly from
    /// the unknowns, and its geometry.
    pub fn oracle_strains<T: Real>(&self, u: &[T]) -> (PointStrains<T>, Vec<PointGeometry>) {
        let moduli = common::material().moduli().unwrap();
        let x: [Vector3<T>; NU] = std::array::from_fn(|i| {
            self.x_start[i].cast::<T>() + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]) * T::from(self.dt)
        });
        let w: [Vector3<T>; NR] = std::array::from_fn(|k| {
            let o = 3 * (NU + k);
            Vector3::new(u[o], u[o + 1], u[o + 2])
        });
        let geoms: Vec<PointGeometry> = self
            .shapes
            .iter()
            .zip(&self.b_world)
            .map(|(s, b)| local_geometry(&s.frame, b))
            .collect();
        let strains = (0..self.shapes.len())
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
        (strains, geoms)
    }

    /// The energy density of the strains `(e, g)` at a point of geometry `geom`, term by term.
    pub fn oracle_density<T: Real>(&self, e: &Matrix3<T>, g: &Matrix3<T>, geom: &PointGeometry) -> T {
        density(&self.terms, e, g, geom, &common::material().moduli().unwrap())
    }
}

/// Checks the fast kernels of `coupling` on `el` at random unknowns (from `seed`): energy, gradient and
/// Hessian against the dual-number `oracle` (the element energy), the gradient-only path against the
/// Hessian path, and the Hessian against central differences of the fast gradient.
pub fn check<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    el: &CoupledElement<NU, NR>,
    coupling: Coupling<'_>,
    oracle: impl Fn(&[Dual2SVec64<NE>]) -> Dual2SVec64<NE>,
    seed: u64,
) {
    let mut rng = common::rng(seed + 100);
    let u: Vec<f64> = (0..NE)
        .map(|i| common::vec3(&mut rng, if i < 3 * NU { 0.2 } else { 3.0 })[0])
        .collect();
    let got = el.fast::<NL, NE>(coupling, &u, true);
    let grad_only = el.fast::<NL, NE>(coupling, &u, false);
    assert!((got.value - el.fast_value(coupling, &u)).abs() <= 1e-12 * got.value.abs());
    assert!(rel_err(&grad_only.gradient, &got.gradient) < 1e-13);
    let uv = SVector::<f64, NE>::from_column_slice(&u);
    let (value, gradient, hessian) = num_dual::hessian(|v: SVector<Dual2SVec64<NE>, NE>| oracle(v.as_slice()), &uv);
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
        let col = (el.fast::<NL, NE>(coupling, &up, false).gradient - el.fast::<NL, NE>(coupling, &um, false).gradient)
            / (2.0 * step);
        fd.set_column(i, &col);
    }
    let e = common::scaled_max_error(&got.hessian, &fd);
    assert!(e < 1e-6, "hessian vs central differences: {e:e}");
}

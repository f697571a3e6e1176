//! End moments through force couples: the way to load a shell without rotational unknowns by a moment.
//!
//! A moment `M` about a fixed unit axis `e` acts on a pair of vertices `(a, b)` (for a strip, one vertex
//! of the last column and its neighbour in the column before) through the potential `−M Δθ`, where `Δθ`
//! is the angle by which the pair's segment `d = x_b − x_a`, projected onto the plane normal to `e`,
//! turns about `e` over the step:
//!
//! ```text
//! Δθ = atan2(e · (d₀ × d), d₀ · d)      (d and d₀ projected; d₀ = the segment at the start of the step).
//! ```
//!
//! Its negative gradient is a pair of opposite forces normal to the segment with magnitude `M / |d|`:
//! a couple of moment exactly `M` that follows the segment as it turns, so a quasi-static end moment
//! sees the applied moment at every rotation (a dead couple would lose `cos θ` of it). The work is the
//! moment times the turned angle, like the torque term of the Cosserat loads. `Δθ` is unambiguous while a
//! pair turns by less than π within one step. Unknowns are velocities: `x = xⁿ + Δt v`.
//!
//! The term lives inside the potential as a `dyn PotentialTerm`, so scripts set its total moment through
//! a [`MomentHandle`] taken before the term is moved in.

use crate::error::{KlError, check_parameter};
use cosserat_assembly::scatter::GroupScatter;
use cosserat_assembly::term::{Evaluation, PotentialTerm};
use cosserat_assembly::{AssemblyError, SparsityPattern};
use cosserat_geometry::Real;
use cosserat_geometry::real::cst;
use nalgebra::{SVector, Vector3};
use num_dual::Dual2SVec64;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// The total moment of a [`ForceCouple`] \[N·m\], shared between the term (inside the potential) and
/// the script that sets it between steps. Cloning gives another handle to the same value.
#[derive(Debug, Clone, Default)]
pub struct MomentHandle(Arc<AtomicU64>);

impl MomentHandle {
    /// Sets the total moment \[N·m\].
    pub fn set(&self, moment: f64) {
        self.0.store(moment.to_bits(), Ordering::Relaxed);
    }

    /// The total moment \[N·m\].
    pub fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }
}

/// A moment about a fixed axis applied through force couples on vertex pairs.
#[derive(Debug, Clone)]
pub struct ForceCouple {
    label: String,
    pairs: Vec<[usize; 2]>,
    /// Share of the total moment per pair (non-negative, summing to one).
    shares: Vec<f64>,
    axis: Vector3<f64>,
    moment: MomentHandle,
    scatter: Option<GroupScatter<2>>,
}

/// The work potential `−M Δθ` of one pair as a function of its end-of-step positions `(x_a, x_b)`, with
/// the start-of-step segment `d0` and a unit `axis` (module docs).
pub fn pair_potential<T: Real>(x: &SVector<T, 6>, d0: &Vector3<f64>, axis: &Vector3<f64>, moment: f64) -> T {
    let d = Vector3::new(x[3] - x[0], x[4] - x[1], x[5] - x[2]);
    let e = axis.map(cst::<T>);
    let d = d - e * d.dot(&e);
    let d0 = d0 - axis * d0.dot(axis);
    let d0 = d0.map(cst::<T>);
    let sin = e.dot(&d0.cross(&d));
    let cos = d0.dot(&d);
    -sin.atan2(cos) * moment
}

impl ForceCouple {
    /// A couple about `axis` on vertex pairs `(a, b)` of a system with `n_vertices` displacement nodes.
    /// The total moment (zero initially, set through [`ForceCouple::handle`]) is split over the pairs in
    /// proportion to `weights` (for instance the trapezoidal weights of the pairs along a loaded edge).
    /// A positive moment turns `x_b − x_a` counter-clockwise about `axis`.
    ///
    /// # Errors
    /// [`KlError::InvalidPair`] for a pair that repeats a vertex or names one out of range, and
    /// [`KlError::InvalidParameter`] for a zero or non-finite axis, or weights that are not one finite
    /// non-negative number per pair with a positive sum.
    pub fn try_new(
        label: impl Into<String>,
        pairs: Vec<[usize; 2]>,
        weights: &[f64],
        axis: Vector3<f64>,
        n_vertices: usize,
    ) -> Result<Self, KlError> {
        let label = label.into();
        for (pair_idx, &[a, b]) in pairs.iter().enumerate() {
            if a == b || a >= n_vertices || b >= n_vertices {
                return Err(KlError::InvalidPair {
                    label,
                    pair_idx,
                    a,
                    b,
                    n_vertices,
                });
            }
        }
        let norm = axis.norm();
        check_parameter("axis", norm, norm > 0.0, "must be a finite, non-zero vector")?;
        check_parameter(
            "weights.len",
            weights.len() as f64,
            weights.len() == pairs.len(),
            "must equal the number of pairs",
        )?;
        for &w in weights {
            check_parameter("weights", w, w >= 0.0, "must be finite and non-negative")?;
        }
        let total: f64 = weights.iter().sum();
        check_parameter("weights.sum", total, total > 0.0, "must be positive")?;
        Ok(Self {
            label,
            pairs,
            shares: weights.iter().map(|w| w / total).collect(),
            axis: axis / norm,
            moment: MomentHandle::default(),
            scatter: None,
        })
    }

    /// The vertex pairs.
    pub fn pairs(&self) -> &[[usize; 2]] {
        &self.pairs
    }

    /// The unit axis.
    pub fn axis(&self) -> &Vector3<f64> {
        &self.axis
    }

    /// The share of the total moment carried by each pair (summing to one).
    pub fn shares(&self) -> &[f64] {
        &self.shares
    }

    /// A handle to the total moment, to set it between steps once the term is inside a potential.
    pub fn handle(&self) -> MomentHandle {
        self.moment.clone()
    }

    fn inputs(&self, p: usize, eval: &Evaluation<'_>) -> (SVector<f64, 6>, Vector3<f64>) {
        let [a, b] = self.pairs[p];
        let x = |i: usize| eval.state.x[i] + eval.layout.velocity(eval.u, i) * eval.dt;
        let (xa, xb) = (x(a), x(b));
        let d0 = eval.state.x[b] - eval.state.x[a];
        (SVector::from([xa.x, xa.y, xa.z, xb.x, xb.y, xb.z]), d0)
    }

    fn evaluate(
        &self,
        eval: &Evaluation<'_>,
        mut sink: impl FnMut(usize, &SVector<f64, 6>, &nalgebra::SMatrix<f64, 6, 6>),
        derivatives: bool,
    ) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        let moment = self.moment.get();
        for p in 0..self.pairs.len() {
            let m = moment * self.shares[p];
            if m == 0.0 {
                continue;
            }
            let (x, d0) = self.inputs(p, eval);
            let value = if derivatives {
                let (v, g, h) = num_dual::hessian(
                    |x: SVector<Dual2SVec64<6>, 6>| pair_potential(&x, &d0, &self.axis, m),
                    &x,
                );
                let ok = g.iter().chain(h.iter()).all(|v| v.is_finite());
                if ok {
                    sink(p, &(g * eval.dt), &(h * (eval.dt * eval.dt)));
                } else {
                    return Err(self.non_finite(p));
                }
                v
            } else {
                pair_potential(&x, &d0, &self.axis, m)
            };
            if !value.is_finite() {
                return Err(self.non_finite(p));
            }
            total += value;
        }
        Ok(total)
    }

    fn non_finite(&self, p: usize) -> AssemblyError {
        AssemblyError::NonFinite {
            term: self.name(),
            location: "pair",
            index: p,
        }
    }
}

impl PotentialTerm for ForceCouple {
    fn name(&self) -> String {
        format!("force_couple[{}]", self.label)
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        self.pairs.iter().map(|p| p.to_vec()).collect()
    }

    fn bind(&mut self, pattern: &SparsityPattern) {
        // Displacement node i is block i (`DofLayout::disp_block`).
        let blocks = self.pairs.iter().map(|&[a, b]| [Some(a), Some(b)]).collect();
        self.scatter = Some(GroupScatter::new(pattern, blocks));
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        self.evaluate(eval, |_, _, _| {}, false)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        let scatter = self.scatter.as_ref().expect("term used before bind()");
        self.evaluate(eval, |p, g, _| scatter.add_gradient(p, g, grad), true)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let scatter = self.scatter.as_ref().expect("term used before bind()");
        self.evaluate(
            eval,
            |p, g, h| {
                scatter.add_gradient(p, g, grad);
                scatter.add_hessian(p, h, pattern, values);
            },
            true,
        )
    }
}

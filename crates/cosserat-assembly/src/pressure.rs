//! Loads on surfaces: consistent nodal weights of a load per unit area, dead pressure, and follower
//! pressure as a term of the potential.
//!
//! All three integrate over the shell's displacement elements (Tri3 or Tri6, corners first) with the
//! element's own interpolation `x(ξ) = Σ N_a x_a` and its area-weighted normal
//! `n(ξ) = x,₁ × x,₂` (so `n dξ` is the vector area element, oriented by the node order):
//!
//! - a load per unit area `t` \[N/m²\] on the rest surface gives node `a` the force `t ∫ N_a |n₀| dξ`
//!   ([`area_weights`]); for a Tri6 the corners get nothing and the mid-edge nodes a third of the area
//!   each (on a flat element), which is what the consistent weights are;
//! - dead pressure `p` keeps the rest normal: node `a` gets `p ∫ N_a n₀ dξ` ([`normal_weights`]);
//! - follower pressure ([`FollowerPressure`]) acts along the current normal: `f_a = p ∫ N_a n dξ`.
//!
//! # Follower pressure: work, Hessian, and open surfaces
//!
//! The work of a pressure on a closed surface is `p V`, with the enclosed volume
//! `V = ⅓ ∫ x · n dξ`; its gradient is exactly the follower force and its Hessian is symmetric. The
//! term's energy is `−p V` in that form, for any surface.
//!
//! On an open surface the follower load is not conservative: `∂V/∂x_a` differs from `∫ N_a n dξ` by
//! terms on the boundary edges only (inside they cancel between the two triangles of an edge), and the
//! load's stiffness `K_ab = ∂f_a/∂x_b` has a skew-symmetric part that lives on boundary edges. The
//! potential's Hessian is symmetric, so the term assembles the symmetric part `½ (K + Kᵀ)`. Where the
//! boundary is held (clamped or hinged rims, the usual case for domes and pipes), the boundary rows and
//! columns drop out and the assembled Hessian is the exact Jacobian. Where a free edge moves under
//! pressure, the gradient (the residual Newton drives to zero) is still the exact follower force, but
//! the energy is no longer its potential and the skew part of the stiffness is missing: the line search
//! then compares energies that do not match the force, and Newton stalls (docs/scenes.md has the
//! measurement). Scenes with free edges use dead pressure.

use crate::error::AssemblyError;
use crate::inertia::add3;
use crate::pattern::SparsityPattern;
use crate::scatter::ElementScatter;
use crate::term::{Evaluation, PotentialTerm, finite};
use cosserat_fem::element::{ShapeFunctions, Tri3, Tri6};
use cosserat_fem::quadrature::QuadratureRule;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The quadrature rule that integrates `N_a n` and `x · n` exactly on an element of `N` nodes (degree
/// 1 for Tri3, 4 for Tri6).
fn rule<const N: usize>() -> QuadratureRule {
    if N == 3 {
        QuadratureRule::centroid()
    } else {
        QuadratureRule::dunavant_p4()
    }
}

/// Values and gradients of the element of `N` nodes (3 or 6).
///
/// # Panics
/// For any other `N` (a programmer error: surfaces are Tri3 or Tri6).
#[track_caller]
fn shape<const N: usize>(xi: [f64; 2]) -> (SVector<f64, N>, SMatrix<f64, 2, N>) {
    match N {
        3 => (
            Tri3::values(xi).fixed_rows::<N>(0).into_owned(),
            Tri3::gradients(xi).fixed_columns::<N>(0).into_owned(),
        ),
        6 => (
            Tri6::values(xi).fixed_rows::<N>(0).into_owned(),
            Tri6::gradients(xi).fixed_columns::<N>(0).into_owned(),
        ),
        _ => panic!("surface loads integrate over Tri3 or Tri6 elements, not {N}-node ones"),
    }
}

/// The covariant basis `(x,₁, x,₂)` at a point.
fn tangents<const N: usize>(x: &[Vector3<f64>; N], grad: &SMatrix<f64, 2, N>) -> (Vector3<f64>, Vector3<f64>) {
    let mut g = (Vector3::zeros(), Vector3::zeros());
    for (b, xb) in x.iter().enumerate() {
        g.0 += xb * grad[(0, b)];
        g.1 += xb * grad[(1, b)];
    }
    g
}

/// `∫ N_a n dξ` per node of one element: the vector-area weights of node `a`.
fn element_normal_weights<const N: usize>(x: &[Vector3<f64>; N]) -> [Vector3<f64>; N] {
    let mut out = [Vector3::zeros(); N];
    for (xi, w) in rule::<N>().iter() {
        let (values, grad) = shape::<N>(xi);
        let (g1, g2) = tangents(x, &grad);
        let n = g1.cross(&g2) * w;
        for (a, o) in out.iter_mut().enumerate() {
            *o += n * values[a];
        }
    }
    out
}

fn gather<const N: usize>(el: &[usize], x: &dyn Fn(usize) -> Vector3<f64>) -> [Vector3<f64>; N] {
    std::array::from_fn(|a| x(el[a]))
}

/// Consistent nodal weights `∫ N_a dA` of a load per unit area over `elements` (3 or 6 nodes each,
/// corners first) with node positions `x`; returns `(node, weight [m²])` sorted by node, one entry per
/// node that any element touches.
///
/// # Panics
/// If an element has neither 3 nor 6 nodes.
#[track_caller]
pub fn area_weights(elements: &[Vec<usize>], x: &dyn Fn(usize) -> Vector3<f64>) -> Vec<(usize, f64)> {
    weights_of(elements, x, None)
}

/// Consistent nodal weights `∫ N_a f dA` of a load per unit area whose intensity varies as
/// `profile` (a function of the position on the surface at `x`, evaluated at the points of a
/// degree-4 rule: exact for profiles of degree 3 on Tri3 and 2 on Tri6); otherwise as
/// [`area_weights`].
///
/// # Panics
/// If an element has neither 3 nor 6 nodes.
#[track_caller]
pub fn profiled_area_weights(
    elements: &[Vec<usize>],
    x: &dyn Fn(usize) -> Vector3<f64>,
    profile: &dyn Fn(&Vector3<f64>) -> f64,
) -> Vec<(usize, f64)> {
    weights_of(elements, x, Some(profile))
}

/// A load's intensity as a function of the position on the surface.
type Profile<'a> = dyn Fn(&Vector3<f64>) -> f64 + 'a;

#[track_caller]
fn weights_of(
    elements: &[Vec<usize>],
    x: &dyn Fn(usize) -> Vector3<f64>,
    profile: Option<&Profile<'_>>,
) -> Vec<(usize, f64)> {
    accumulate(elements, |el, out| {
        let mut add = |nodes: &[usize], weights: &[f64]| nodes.iter().zip(weights).for_each(|(&i, &w)| out(i, w));
        match el.len() {
            3 => add(el, &scalar_weights::<3>(&gather(el, x), profile)),
            6 => add(el, &scalar_weights::<6>(&gather(el, x), profile)),
            n => panic!("surface loads integrate over Tri3 or Tri6 elements, not {n}-node ones"),
        }
    })
}

fn scalar_weights<const N: usize>(x: &[Vector3<f64>; N], profile: Option<&Profile<'_>>) -> [f64; N] {
    let mut out = [0.0; N];
    let rule = if profile.is_some() {
        QuadratureRule::dunavant_p4()
    } else {
        rule::<N>()
    };
    for (xi, w) in rule.iter() {
        let (values, grad) = shape::<N>(xi);
        let (g1, g2) = tangents(x, &grad);
        let f = profile.map_or(1.0, |f| f(&x.iter().zip(values.iter()).map(|(p, v)| p * *v).sum()));
        let da = g1.cross(&g2).norm() * w * f;
        for (a, o) in out.iter_mut().enumerate() {
            *o += da * values[a];
        }
    }
    out
}

/// Consistent nodal vector areas `∫ N_a n dξ` over `elements` (the nodal forces of a unit dead
/// pressure on the surface at positions `x`, along the normal of the node order); returns
/// `(node, vector [m²])` sorted by node.
///
/// # Panics
/// If an element has neither 3 nor 6 nodes.
#[track_caller]
pub fn normal_weights(elements: &[Vec<usize>], x: &dyn Fn(usize) -> Vector3<f64>) -> Vec<(usize, Vector3<f64>)> {
    accumulate(elements, |el, out| match el.len() {
        3 => element_normal_weights::<3>(&gather(el, x))
            .iter()
            .enumerate()
            .for_each(|(a, w)| out(el[a], *w)),
        6 => element_normal_weights::<6>(&gather(el, x))
            .iter()
            .enumerate()
            .for_each(|(a, w)| out(el[a], *w)),
        n => panic!("surface loads integrate over Tri3 or Tri6 elements, not {n}-node ones"),
    })
}

/// Sums per-element contributions per node, sorted by node.
fn accumulate<W: Copy + std::ops::AddAssign>(
    elements: &[Vec<usize>],
    mut element: impl FnMut(&[usize], &mut dyn FnMut(usize, W)),
) -> Vec<(usize, W)> {
    let mut sums: std::collections::BTreeMap<usize, W> = std::collections::BTreeMap::new();
    for el in elements {
        element(el, &mut |i, w| {
            sums.entry(i).and_modify(|s| *s += w).or_insert(w);
        });
    }
    sums.into_iter().collect()
}

/// A pressure that follows the current surface: `f_a = p ∫ N_a n dξ` on displacement nodes, with the
/// energy `−p V` (module docs: what that means for open surfaces). Elements have `N` = 3 or 6 nodes
/// (system displacement nodes, corners first).
#[derive(Debug, Clone)]
pub struct FollowerPressure<const N: usize> {
    /// A name for summaries (the scene's load name).
    pub label: String,
    /// The loaded elements, by system displacement node.
    pub elements: Vec<[usize; N]>,
    /// The pressure \[Pa\], positive along the normal of the node order (scripts set it every step).
    pub pressure: f64,
    scatter: Option<ElementScatter<N>>,
}

/// Value, force and stiffness of one element at end-of-step positions `x`.
struct ElementLoad<const N: usize> {
    /// `⅓ ∫ x · n dξ`.
    volume: f64,
    /// `∫ N_a n dξ` per node.
    force: [Vector3<f64>; N],
    /// `∂(∫ N_a n dξ)/∂x_b`, block `(a, b)`.
    stiffness: [[Matrix3<f64>; N]; N],
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

fn element_load<const N: usize>(x: &[Vector3<f64>; N], with_stiffness: bool) -> ElementLoad<N> {
    let mut out = ElementLoad {
        volume: 0.0,
        force: [Vector3::zeros(); N],
        stiffness: [[Matrix3::zeros(); N]; N],
    };
    for (xi, w) in rule::<N>().iter() {
        let (values, grad) = shape::<N>(xi);
        let (g1, g2) = tangents(x, &grad);
        let n = g1.cross(&g2);
        let pos = x
            .iter()
            .zip(values.iter())
            .fold(Vector3::zeros(), |acc, (xb, nb)| acc + xb * *nb);
        out.volume += w * pos.dot(&n) / 3.0;
        for a in 0..N {
            out.force[a] += n * (w * values[a]);
        }
        if with_stiffness {
            // δn = δx,₁ × x,₂ + x,₁ × δx,₂ = (∂₂N_b [x,₁]× − ∂₁N_b [x,₂]×) δx_b.
            let (s1, s2) = (skew(&g1), skew(&g2));
            for b in 0..N {
                let dn = s1 * grad[(1, b)] - s2 * grad[(0, b)];
                for a in 0..N {
                    out.stiffness[a][b] += dn * (w * values[a]);
                }
            }
        }
    }
    out
}

impl<const N: usize> FollowerPressure<N> {
    /// A follower pressure on `elements` (system displacement nodes), zero until set.
    pub fn new(label: impl Into<String>, elements: Vec<[usize; N]>) -> Self {
        Self {
            label: label.into(),
            elements,
            pressure: 0.0,
            scatter: None,
        }
    }

    /// End-of-step positions of an element's nodes.
    fn positions(&self, eval: &Evaluation<'_>, e: usize) -> [Vector3<f64>; N] {
        let el = &self.elements[e];
        std::array::from_fn(|a| eval.state.x[el[a]] + eval.layout.velocity(eval.u, el[a]) * eval.dt)
    }

    /// The volume `⅓ ∫ x · n dξ` under the surface at the end-of-step positions of `eval` (the enclosed
    /// volume for a closed surface oriented outwards) \[m³\].
    pub fn volume(&self, eval: &Evaluation<'_>) -> f64 {
        (0..self.elements.len())
            .map(|e| element_load(&self.positions(eval, e), false).volume)
            .sum()
    }

    fn energy(&self, load: &ElementLoad<N>, e: usize) -> Result<f64, AssemblyError> {
        finite(-self.pressure * load.volume, &|| self.name(), "element", e)
    }

    /// Adds element `e`'s gradient `−Δt p f` with respect to the velocities to `grad`.
    fn add_gradient(&self, load: &ElementLoad<N>, e: usize, eval: &Evaluation<'_>, grad: &mut [f64]) {
        for (a, &i) in self.elements[e].iter().enumerate() {
            add3(
                grad,
                eval.layout.disp_block(i),
                &(load.force[a] * (-eval.dt * self.pressure)),
            );
        }
    }
}

impl<const N: usize> PotentialTerm for FollowerPressure<N> {
    fn name(&self) -> String {
        "follower_pressure".into()
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        self.elements.iter().map(|el| el.to_vec()).collect()
    }

    fn bind(&mut self, pattern: &SparsityPattern) {
        self.scatter = Some(ElementScatter::new(pattern, self.elements.clone()));
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        (0..self.elements.len()).try_fold(0.0, |acc, e| {
            let load = element_load(&self.positions(eval, e), false);
            Ok(acc + self.energy(&load, e)?)
        })
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        for e in 0..self.elements.len() {
            let load = element_load(&self.positions(eval, e), false);
            total += self.energy(&load, e)?;
            self.add_gradient(&load, e, eval, grad);
        }
        Ok(total)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let scatter = self
            .scatter
            .as_ref()
            .expect("the potential binds every term before evaluating it");
        let mut total = 0.0;
        let scale = -eval.dt * eval.dt * self.pressure * 0.5;
        for e in 0..self.elements.len() {
            let load = element_load(&self.positions(eval, e), true);
            total += self.energy(&load, e)?;
            self.add_gradient(&load, e, eval, grad);
            let h = SMatrix::<f64, 18, 18>::from_fn(|r, c| {
                let (a, b) = (r / 3, c / 3);
                if a >= N || b >= N {
                    return 0.0;
                }
                // The symmetric part of the load stiffness (module docs).
                scale * (load.stiffness[a][b][(r % 3, c % 3)] + load.stiffness[b][a][(c % 3, r % 3)])
            });
            add_element_hessian::<N>(scatter, e, &h, pattern, values);
        }
        Ok(total)
    }

    fn active_energy_terms(&self) -> Vec<String> {
        vec![format!("follower_pressure[{}]", self.label)]
    }
}

/// Adds the leading `3N × 3N` block of `h` through the scatter.
fn add_element_hessian<const N: usize>(
    scatter: &ElementScatter<N>,
    e: usize,
    h: &SMatrix<f64, 18, 18>,
    pattern: &SparsityPattern,
    values: &mut [f64],
) {
    match N {
        3 => {
            let h3: SMatrix<f64, 9, 9> = h.fixed_view::<9, 9>(0, 0).into_owned();
            scatter_as(scatter, e, &h3, pattern, values);
        }
        _ => scatter_as(scatter, e, h, pattern, values),
    }
}

fn scatter_as<const N: usize, const NE: usize>(
    scatter: &ElementScatter<N>,
    e: usize,
    h: &SMatrix<f64, NE, NE>,
    pattern: &SparsityPattern,
    values: &mut [f64],
) {
    scatter.add_hessian(e, h, pattern, values);
}

//! The drilling hourglass of quadratic rotations on the 3-point rule, held by the stabilised drilling
//! stiffness.
//!
//! Under [`StrainInterpolation::ReggeStabilized`](crate::StrainInterpolation::ReggeStabilized) a
//! point's drilling strain is its element's mean plus the fraction `α` of its own fluctuation, read at
//! the quadrature points. Quadratic rotations (Tri6) give each element six nodal turns about the
//! normal, and the three points of the degree-2 rule see only three of their patterns: a drilling
//! field that vanishes at the three points (an hourglass) has neither mean nor fluctuation there, so
//! only the curvature energy holds it, at the bending's scale, far below the `α² K` that holds any
//! other fluctuation. The stresses of a thin shell bent far soften such turns below that hold: the
//! equilibria of the Sze cantilever at h/L = 1e-5 (cells of 5000 thicknesses) from a quarter of its
//! load on, and of the slit annular plate on its coarsest mesh, had negative modes of the turns alone
//! (docs/model-notes.md). Newton's iterations then start at indefinite matrices, and a descent method
//! leaves the equilibrium. The six-point rule sees the hourglass and has no such modes.
//!
//! So on the 3-point rule each element adds the energy `Σ_t ½ c g_t²` over its six edge tying points
//! (evaluated anyway for the Regge membrane), where `g_t` is the drilling strain at `t` less the linear
//! interpolation of the three quadrature points' drilling strains to `t`, and `c = α² k A / 6` (`k`
//! the drilling stiffness of the density, `A` the element's area): the hourglass is held by the
//! stiffness of the stabilised fluctuations, which the six-point rule gives it too. A drilling field
//! that is linear inside the element has `g_t = 0`: the patch tests, the element's mean and its linear
//! fluctuations are untouched.

use crate::assumed::{FIRST_INTERIOR, N_TIED, N_TYING, TIED, TyingMap, TyingTwins, tying_points};
use crate::strain_space::{DensityMatrix, StrainVector};
use nalgebra::{SMatrix, SVector};
use std::sync::LazyLock;

/// The edge tying points: the two Gauss points of each edge, first among the tying points.
const N_EDGE: usize = 6;

/// The entries of `Ê` (0–5, (a, γ) at 3γ + a) whose difference is the drilling strain
/// `½ (Ê₁₂ − Ê₂₁)`: `½ (Ê[PLUS] − Ê[MINUS])`.
const PLUS: usize = 3;
const MINUS: usize = 1;

/// The drilling strain of a tying point's tied entries.
fn drilling(tied: &[f64]) -> f64 {
    0.5 * (tied[PLUS] - tied[MINUS])
}

/// The hourglass strain of each edge tying point: the weights of the drilling strains of the edge
/// point itself (1) and of the three interior points (minus the linear interpolation through them,
/// (1/6, 1/6), (2/3, 1/6), (1/6, 2/3), at the edge point).
static STENCILS: LazyLock<[[(usize, f64); 4]; N_EDGE]> = LazyLock::new(|| {
    let points = tying_points();
    std::array::from_fn(|t| {
        let [r, s] = points[t];
        let (l1, l2) = (2.0 * r - 1.0 / 3.0, 2.0 * s - 1.0 / 3.0);
        [
            (t, 1.0),
            (FIRST_INTERIOR, -(1.0 - l1 - l2)),
            (FIRST_INTERIOR + 1, -l1),
            (FIRST_INTERIOR + 2, -l2),
        ]
    })
});

/// The hourglass strain of each edge tying point for the element's tied strains `z`.
fn hourglass_strains(z: &SVector<f64, N_TIED>) -> [f64; N_EDGE] {
    STENCILS.map(|stencil| {
        stencil
            .iter()
            .map(|&(p, w)| w * drilling(&z.as_slice()[TIED * p..TIED * (p + 1)]))
            .sum()
    })
}

/// The hourglass term of one element: `c` of `Σ_t ½ c g_t²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DrillingHourglass {
    stiffness: f64,
}

impl DrillingHourglass {
    /// The term of an element with `maps` at its quadrature points (weights and densities), or `None`
    /// where it has no hourglass to hold: linear rotations, a rule whose points are not the interior
    /// tying points, or a drilling strain that is not stabilised (its point values, or assumed).
    pub(crate) fn of<'a>(
        quadratic_rotations: bool,
        points: impl Iterator<Item = (f64, &'a DensityMatrix)>,
        maps: &[TyingMap],
        twins: &TyingTwins,
    ) -> Option<Self> {
        let on_interior_points = (FIRST_INTERIOR..N_TYING).all(|t| twins.is_twin(t));
        if !quadratic_rotations || !on_interior_points {
            return None;
        }
        // `u` with `u · Ê = 2 × drilling`: the own map keeps the fraction α of it.
        let mut u = StrainVector::zeros();
        (u[PLUS], u[MINUS]) = (1.0, -1.0);
        let own = maps.first()?.own;
        let alpha = 0.5 * u.fixed_rows::<TIED>(0).dot(&(own * u.fixed_rows::<TIED>(0)));
        if !(alpha > 0.0 && alpha < 1.0) {
            return None;
        }
        // A drilling strain `d` is `Ê = d u`, of energy density `½ d² uᵀ D u`.
        let weighted_stiffness: f64 = points.map(|(w, d)| w * u.dot(&d.mul_vector(&u))).sum();
        Some(Self {
            stiffness: alpha * alpha * weighted_stiffness / N_EDGE as f64,
        })
    }

    /// The energy for the element's tied strains `z`.
    pub(crate) fn energy(&self, z: &SVector<f64, N_TIED>) -> f64 {
        hourglass_strains(z).iter().map(|g| 0.5 * self.stiffness * g * g).sum()
    }

    /// Adds the energy's derivative with respect to `z` to `tied_stress`; returns the energy.
    pub(crate) fn add_stress(&self, z: &SVector<f64, N_TIED>, tied_stress: &mut SVector<f64, N_TIED>) -> f64 {
        let mut energy = 0.0;
        for (g, stencil) in hourglass_strains(z).iter().zip(STENCILS.iter()) {
            energy += 0.5 * self.stiffness * g * g;
            for &(p, w) in stencil {
                let half = 0.5 * self.stiffness * g * w;
                tied_stress[TIED * p + PLUS] += half;
                tied_stress[TIED * p + MINUS] -= half;
            }
        }
        energy
    }

    /// Adds `c Σ_t (J g_t)(J g_t)ᵀ` to the upper block triangle of `h`, with `jacobian(t)` the columns
    /// of `Ê` of tying point `t`'s strain Jacobian in the element's unknowns (transposed).
    pub(crate) fn add_first_order<'a, const NE: usize>(
        &self,
        jacobian: impl Fn(usize) -> &'a SMatrix<f64, NE, TIED>,
        h: &mut SMatrix<f64, NE, NE>,
    ) {
        // `J g_t`: the drilling strain's Jacobian `½ (J[PLUS] − J[MINUS])` of each point of the stencil,
        // weighted (the scaling by ½ is exact, so folding it into the weight changes no bit).
        let mut hourglass = [SVector::<f64, NE>::zeros(); N_EDGE];
        for (v, stencil) in hourglass.iter_mut().zip(STENCILS.iter()) {
            for &(p, w) in stencil {
                let j = jacobian(p).as_slice();
                let (plus, minus) = (&j[NE * PLUS..NE * (PLUS + 1)], &j[NE * MINUS..NE * (MINUS + 1)]);
                let half = 0.5 * w;
                for (o, (a, b)) in v.as_mut_slice().iter_mut().zip(plus.iter().zip(minus)) {
                    *o += half * (a - b);
                }
            }
        }
        add_rank_update(self.stiffness, &hourglass, h);
    }
}

/// `h += k Σ_t v_t v_tᵀ` on the upper block triangle.
fn add_rank_update<const NE: usize>(k: f64, vectors: &[SVector<f64, NE>; N_EDGE], h: &mut SMatrix<f64, NE, NE>) {
    for (c, column) in h.as_mut_slice().chunks_exact_mut(NE).enumerate() {
        let rows = (3 * (c / 3) + 3).min(NE);
        for v in vectors {
            let vc = k * v[c];
            for (o, x) in column[..rows].iter_mut().zip(&v.as_slice()[..rows]) {
                *o += x * vc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strain_space::StrainMatrix;

    /// Tied strains whose drilling strain at each tying point is `field(r, s)` (other entries zero).
    fn tied_drilling(field: impl Fn(f64, f64) -> f64) -> SVector<f64, N_TIED> {
        let mut z = SVector::zeros();
        for (t, [r, s]) in tying_points().into_iter().enumerate() {
            z[TIED * t + PLUS] = field(r, s);
            z[TIED * t + MINUS] = -field(r, s);
        }
        z
    }

    fn term() -> DrillingHourglass {
        let density = DensityMatrix::new(StrainMatrix::identity() * 3.0);
        let maps = [TyingMap {
            values: SMatrix::zeros(),
            own: SMatrix::identity() * 0.3,
        }];
        let interior = [
            tying_points()[FIRST_INTERIOR],
            tying_points()[FIRST_INTERIOR + 1],
            tying_points()[FIRST_INTERIOR + 2],
        ];
        let twins = TyingTwins::of_rule(&interior);
        DrillingHourglass::of(true, [(0.5, &density)].into_iter(), &maps, &twins).expect("an hourglass term")
    }

    #[test]
    fn linear_drilling_fields_have_no_hourglass_energy() {
        let z = tied_drilling(|r, s| 0.7 - 1.3 * r + 2.1 * s);
        assert!(term().energy(&z).abs() < 1e-28, "{}", term().energy(&z));
    }

    #[test]
    fn a_field_that_vanishes_at_the_three_points_has_hourglass_energy() {
        // Zero at (1/6, 1/6), (2/3, 1/6) and (1/6, 2/3): its linear interpolation from the three points
        // vanishes, so its hourglass strain at each edge Gauss point is its value there.
        let field = |r: f64, s: f64| (r - 1.0 / 6.0) * (s - 1.0 / 6.0);
        let z = tied_drilling(field);
        let edge: Vec<f64> = tying_points()[..N_EDGE].iter().map(|&[r, s]| field(r, s)).collect();
        assert!(edge.iter().all(|g| g.abs() > 1e-3), "{edge:?}");
        for (g, e) in hourglass_strains(&z).iter().zip(&edge) {
            assert!((g - e).abs() <= 1e-15, "{g} against {e}");
        }
        // c = α² k A / 6 with α = 0.3, k = uᵀ D u = 3 · 2, A = 0.5.
        let c = 0.09 * 6.0 * 0.5 / 6.0;
        let expected: f64 = edge.iter().map(|g| 0.5 * c * g * g).sum();
        assert!(
            (term().energy(&z) - expected).abs() <= 1e-14 * expected,
            "{} against {expected}",
            term().energy(&z)
        );
    }

    #[test]
    fn the_stress_and_the_first_order_term_are_the_energys_derivatives() {
        let hourglass = term();
        let z = SVector::<f64, N_TIED>::from_fn(|i, _| ((i * 7 + 3) % 11) as f64 / 11.0 - 0.4);
        let mut stress = SVector::zeros();
        let energy = hourglass.add_stress(&z, &mut stress);
        assert!((energy - hourglass.energy(&z)).abs() <= 1e-15 * energy);
        let step = 1e-6;
        for i in 0..N_TIED {
            let mut e = SVector::<f64, N_TIED>::zeros();
            e[i] = step;
            let central = (hourglass.energy(&(z + e)) - hourglass.energy(&(z - e))) / (2.0 * step);
            assert!(
                (central - stress[i]).abs() <= 1e-8,
                "entry {i}: {central} against {}",
                stress[i]
            );
        }
        // With the tied strains as the unknowns (each point's Jacobian selects its block) the first-order
        // term is the energy's Hessian, a constant: the central differences of the stress.
        let selection: Vec<SMatrix<f64, N_TIED, TIED>> = (0..N_TYING)
            .map(|t| SMatrix::from_fn(|r, c| f64::from(u8::from(r == TIED * t + c))))
            .collect();
        let mut h = SMatrix::<f64, N_TIED, N_TIED>::zeros();
        hourglass.add_first_order(|t| &selection[t], &mut h);
        for j in 0..N_TIED {
            let mut e = SVector::<f64, N_TIED>::zeros();
            e[j] = step;
            let (mut plus, mut minus) = (SVector::zeros(), SVector::zeros());
            hourglass.add_stress(&(z + e), &mut plus);
            hourglass.add_stress(&(z - e), &mut minus);
            for i in 0..(3 * (j / 3) + 3).min(N_TIED) {
                let central = (plus[i] - minus[i]) / (2.0 * step);
                assert!(
                    (central - h[(i, j)]).abs() <= 1e-8,
                    "({i}, {j}): {central} against {}",
                    h[(i, j)]
                );
            }
        }
    }

    #[test]
    fn no_term_without_an_hourglass_to_hold() {
        let density = DensityMatrix::new(StrainMatrix::identity());
        let maps = |alpha: f64| {
            [TyingMap {
                values: SMatrix::zeros(),
                own: SMatrix::identity() * alpha,
            }]
        };
        let interior = [
            tying_points()[FIRST_INTERIOR],
            tying_points()[FIRST_INTERIOR + 1],
            tying_points()[FIRST_INTERIOR + 2],
        ];
        let three = TyingTwins::of_rule(&interior);
        let of = |quadratic, alpha, twins: &TyingTwins| {
            DrillingHourglass::of(quadratic, [(1.0, &density)].into_iter(), &maps(alpha), twins)
        };
        assert!(of(true, 0.3, &three).is_some());
        assert!(of(false, 0.3, &three).is_none(), "linear rotations");
        assert!(
            of(true, 0.3, &TyingTwins::NONE).is_none(),
            "a rule whose points are not the interior tying points"
        );
        assert!(of(true, 1.0, &three).is_none(), "drilling at its point values");
        assert!(of(true, 0.0, &three).is_none(), "assumed drilling");
    }
}

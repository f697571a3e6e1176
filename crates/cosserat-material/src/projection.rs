//! Strain interpolation: which strains of an element's quadrature points enter the energy.
//!
//! The paper's discretisation ([`StrainInterpolation::Paper`]) evaluates the energy density at every
//! quadrature point with that point's own strains. On thin elements (element size `h_e` many
//! thicknesses `h`) the membrane and transverse-shear parts of `E` are constraints that the
//! displacement and rotation spaces cannot satisfy point by point: the shell locks.
//!
//! [`StrainInterpolation::Stabilized`] replaces, in each element, the membrane, drilling and
//! transverse-shear strains of a point by their element mean plus a scaled fluctuation,
//!
//! `s̃_p = s̄ + α (s_p − s̄)`, with `s̄ = Σ_q w_q s_q / Σ_q w_q` and `α = √β`, `β = h² / (h² + c h_e²)`,
//!
//! per part (`c` per part, [`StabilizationConstants`]); the curvature strains `Γ` and the constant
//! strains are untouched. The energy is the paper's density of the projected strains,
//! `Σ_p w_p Ψ(s̃_p)`: constant strain states are represented exactly (membrane and shear patch tests),
//! the mean carries the full stiffness, and only the fluctuation, which is what locks, is softened to
//! the bending scale `h²/h_e²`. As the mesh is refined (`h_e → 0`) `β → 1` and the paper's
//! discretisation is recovered.

use crate::strain_space::StrainVector;

/// How the strains of an element's points enter its energy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum StrainInterpolation {
    /// Every point's own strains (the paper's discretisation).
    #[default]
    Paper,
    /// Element means plus a fluctuation scaled by `√β` for the membrane, drilling and transverse-shear
    /// strains (module documentation).
    Stabilized,
    /// Assumed covariant membrane, drilling and transverse-shear strains interpolated from tying points
    /// (MITC6-style, [`crate::assumed`]).
    Assumed,
    /// The membrane strains interpolated into the linear Regge space by their edge-tangential and
    /// interior moments; drilling, transverse shear and curvature keep their point values
    /// ([`crate::assumed`]).
    Regge,
    /// Regge membrane strains ([`Self::Regge`]) with the transverse-shear and drilling strains of
    /// [`Self::Stabilized`] (element means plus fluctuations scaled by `√β`, with the constants of
    /// [`StabilizationConstants::regge_stabilized`]); curvature at the points
    /// ([`crate::assumed::stabilize_shear_and_drilling`]).
    ReggeStabilized,
}

impl StrainInterpolation {
    /// The scene's name of the interpolation (`material.strain_interpolation`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Stabilized => "stabilized",
            Self::Assumed => "assumed",
            Self::Regge => "regge",
            Self::ReggeStabilized => "regge_stabilized",
        }
    }
}

/// The constants `c` of `β = h² / (h² + c h_e²)`, per strain part; `f64::INFINITY` keeps a part's
/// point strains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilizationConstants {
    /// In-plane stretch and shear: the symmetric tangential block of `E`.
    pub membrane: f64,
    /// Drilling: the skew tangential block of `E`.
    pub drilling: f64,
    /// Transverse shear: the normal row of `E`.
    pub shear: f64,
}

impl StabilizationConstants {
    /// The constants of [`StrainInterpolation::Stabilized`].
    pub const DEFAULT: Self = Self {
        membrane: 1.0,
        drilling: 1.0,
        shear: 1.0,
    };

    /// The shear and drilling constant of [`StrainInterpolation::ReggeStabilized`] with quadratic
    /// (six-node) rotations and the pair's degree-4 rule. Quadratic rotations leave the shear less
    /// parasitic variation inside an element than linear ones, so the same `c = 1` softens it too much
    /// (the pinched cylinder's point loads are carried by shear and come out far too flexible); `c` was
    /// chosen on the shell obstacle course as the value whose worst error relative to its goal is
    /// smallest over the six goal meshes (docs/model-notes.md has the sweep). The drilling strain takes
    /// the same constant: a larger one changes no course result by more than a few tenths of a percent
    /// but leaves the drilling fluctuations so soft that a sheet in tension loses stability (the
    /// membrane strain falls at second order in the rotations, and only the stabilised shear and
    /// drilling stiffness holds them).
    pub const QUADRATIC_ROTATION: f64 = 0.15;

    /// The same constant with the 3-point rule (`mesh.quadrature_degree = 2`), chosen the same way:
    /// three points sample the shear's fluctuation at fewer places than six, which constrains it less,
    /// so the constant that balances the course is smaller.
    pub const QUADRATIC_ROTATION_THREE_POINTS: f64 = 0.08;

    /// The constants of [`StrainInterpolation::ReggeStabilized`] for rotation elements of
    /// `rotation_nodes` nodes and a rule of `quadrature_points` points (the membrane constant is unused
    /// there: the membrane strain takes its Regge interpolant).
    pub fn regge_stabilized(rotation_nodes: usize, quadrature_points: usize) -> Self {
        let c = match (rotation_nodes, quadrature_points) {
            (6, 3) => Self::QUADRATIC_ROTATION_THREE_POINTS,
            (6, _) => Self::QUADRATIC_ROTATION,
            _ => return Self::DEFAULT,
        };
        Self {
            drilling: c,
            shear: c,
            ..Self::DEFAULT
        }
    }
}

/// The projection of one element: the factors `α = √β` of the fluctuations of its parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrainProjection {
    /// Membrane (symmetric tangential block of `E`).
    pub membrane: f64,
    /// Drilling (skew tangential block of `E`).
    pub drilling: f64,
    /// Transverse shear (normal row of `E`).
    pub shear: f64,
}

impl StrainProjection {
    /// The projection of an element of size `h_e` (longest edge) and thickness `h`.
    pub fn new(constants: &StabilizationConstants, thickness: f64, element_size: f64) -> Self {
        let alpha = |c: f64| {
            if c.is_infinite() {
                1.0
            } else {
                let h2 = thickness * thickness;
                (h2 / (h2 + c * element_size * element_size)).sqrt()
            }
        };
        Self {
            membrane: alpha(constants.membrane),
            drilling: alpha(constants.drilling),
            shear: alpha(constants.shear),
        }
    }

    /// `B v = (I − P) v`: the part of `v` that the projection removes from a point's strains,
    /// `s̃_p = s_p − B (s_p − s̄)`. `B` is symmetric and zero outside the entries 0–5 (the variable
    /// columns of `Ê`).
    #[inline]
    pub fn removed(&self, v: &StrainVector) -> StrainVector {
        let mut out = StrainVector::zeros();
        let (bm, bd, bs) = (1.0 - self.membrane, 1.0 - self.drilling, 1.0 - self.shear);
        // Ê column-major: (a, γ) at 3γ + a; rows 0, 1 tangential, row 2 normal.
        out[0] = bm * v[0];
        out[4] = bm * v[4];
        let sym = 0.5 * (v[1] + v[3]);
        let skw = 0.5 * (v[3] - v[1]);
        out[1] = bm * sym - bd * skw;
        out[3] = bm * sym + bd * skw;
        out[2] = bs * v[2];
        out[5] = bs * v[5];
        out
    }

    /// The block of `B` on the strain entries 0–5 (the variable columns of `Ê`), outside which `B` is
    /// zero.
    pub fn removed_block(&self) -> nalgebra::Matrix6<f64> {
        let (bm, bd, bs) = (1.0 - self.membrane, 1.0 - self.drilling, 1.0 - self.shear);
        // Entries 1 and 3 are the off-diagonal tangential pair: their symmetric part is scaled by
        // `bm`, their skew part by `bd` (as in `removed`).
        let (same, cross) = (0.5 * (bm + bd), 0.5 * (bm - bd));
        let mut b = nalgebra::Matrix6::zeros();
        b[(0, 0)] = bm;
        b[(4, 4)] = bm;
        b[(2, 2)] = bs;
        b[(5, 5)] = bs;
        b[(1, 1)] = same;
        b[(3, 3)] = same;
        b[(1, 3)] = cross;
        b[(3, 1)] = cross;
        b
    }

    /// The diagonal of `P = I − B` on the strain entries 0–5 when `P` is diagonal there (equal membrane
    /// and drilling factors, as with the default constants), so that `P D P` is `D` with its entries
    /// scaled; `None` when `P` couples the off-diagonal tangential pair.
    pub fn kept_diagonal(&self) -> Option<[f64; 6]> {
        let b = self.removed_block();
        (b[(1, 3)] == 0.0).then(|| std::array::from_fn(|i| 1.0 - b[(i, i)]))
    }

    /// `P D P` with `P = I − B`: the density of the projected strains' point-local part.
    pub fn kept_density(&self, d: &crate::strain_space::StrainMatrix) -> crate::strain_space::StrainMatrix {
        let p = nalgebra::Matrix6::identity() - self.removed_block();
        let mut out = *d;
        let rows = p * d.fixed_rows::<6>(0);
        out.fixed_rows_mut::<6>(0).copy_from(&rows);
        let cols = out.fixed_columns::<6>(0) * p;
        out.fixed_columns_mut::<6>(0).copy_from(&cols);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_is_symmetric_and_identity_when_factors_are_one() {
        let p = StrainProjection {
            membrane: 0.3,
            drilling: 0.7,
            shear: 0.1,
        };
        let b = nalgebra::SMatrix::<f64, 18, 18>::from_fn(|r, c| {
            p.removed(&StrainVector::from_fn(|i, _| f64::from(u8::from(i == c))))[r]
        });
        assert!((b - b.transpose()).norm() < 1e-15);
        let one = StrainProjection {
            membrane: 1.0,
            drilling: 1.0,
            shear: 1.0,
        };
        let v = StrainVector::from_fn(|i, _| i as f64 + 1.0);
        assert_eq!(one.removed(&v), StrainVector::zeros());
        // The block is `removed` on the entries 0–5, and `removed` is zero outside them.
        let block = p.removed_block();
        for r in 0..18 {
            for c in 0..18 {
                let expected = if r < 6 && c < 6 { block[(r, c)] } else { 0.0 };
                assert!(
                    (b[(r, c)] - expected).abs() < 1e-15,
                    "B[{r}, {c}] = {} vs {expected}",
                    b[(r, c)]
                );
            }
        }
        // `P` is diagonal only where membrane and drilling share their factor.
        assert_eq!(p.kept_diagonal(), None);
        let equal = StrainProjection { drilling: 0.3, ..p };
        let keep = nalgebra::Matrix6::identity() - equal.removed_block();
        let diagonal = equal.kept_diagonal().expect("equal factors give a diagonal P");
        assert_eq!(keep, nalgebra::Matrix6::from_diagonal(&diagonal.into()));
        assert_eq!(diagonal, [0.3, 0.3, 0.1, 0.3, 0.3, 0.1].map(|a: f64| 1.0 - (1.0 - a)));
    }
}

//! The moduli of the isotropic micropolar continuum, and the closed forms of a slab that the tests and
//! studies compare with.
//!
//! The material is the shell's [`ContinuumParameters`] (what a user sets, in SI units; the volume has
//! no thickness or bending correction), so both models accept and reject the same values with the
//! same messages. [`MicropolarModuli`] can only be obtained through [`MicropolarModuli::of`], which
//! validates every field, so a kernel never sees `ν = 0.5` (an infinite `λ`) or a negative length
//! scale.

use crate::error::MaterialError;
use cosserat_material::{ContinuumParameters, MaterialParameters};

/// The moduli of the micropolar energy density (Löschner et al. 2023, eqs. 9–11 in the notation of
/// the shell's supplement eqs. 6–7), derived from validated [`ContinuumParameters`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicropolarModuli {
    /// Shear modulus `μ = E / (2 (1 + ν))` \[Pa\].
    pub mu: f64,
    /// Lamé's first parameter `λ = E ν / ((1 + ν)(1 − 2ν))` \[Pa\].
    pub lambda: f64,
    /// Cosserat couple modulus `μ_c` \[Pa\].
    pub mu_c: f64,
    /// Internal length `L_c` \[m\].
    pub length_scale: f64,
    /// `(b₁, b₂, b₃)` of the curvature energy
    /// `μ L_c² (b₁ |sym Γ|² + b₂ |skew Γ|² + b₃ (tr Γ)²)`.
    pub curvature_coefficients: [f64; 3],
}

impl MicropolarModuli {
    /// The moduli of a material, after validation.
    ///
    /// # Errors
    /// [`MaterialError::InvalidParameter`] naming the first offending field.
    pub fn of(material: &ContinuumParameters) -> Result<Self, MaterialError> {
        material.validate()?;
        let mu = material.shear_modulus();
        Ok(Self {
            mu,
            lambda: material.lame_lambda(),
            mu_c: material.mu_c_factor * mu,
            length_scale: material.length_scale,
            curvature_coefficients: material.curvature_coefficients,
        })
    }
}

/// A slab of a micropolar material bent about its width axis: the closed forms its numerical
/// solutions converge to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slab {
    /// The material.
    pub material: ContinuumParameters,
    /// The thickness `h` \[m\].
    pub thickness: f64,
}

impl Slab {
    /// The shell of the slab's thickness and material, whose stiffnesses per unit width are the slab's.
    fn as_shell(&self) -> MaterialParameters {
        MaterialParameters::with_continuum(self.thickness, self.material)
    }

    /// The bending stiffness per unit width in cylindrical bending that is prevented from anticlastic
    /// curvature (plane strain across the width), `D = E h³ / (12 (1 − ν²))` \[N·m\].
    pub fn plate_bending_stiffness(&self) -> f64 {
        self.as_shell().plate_bending_stiffness()
    }

    /// The curvature stiffness per unit width, `C = h μ L_c² (b₁ + b₂)` \[N·m\]: a uniform
    /// `Γ = k e_y ⊗ e_x` has `|sym Γ|² = |skew Γ|² = k²/2`, so the curvature energy per unit area is
    /// `½ C k²`.
    pub fn curvature_stiffness(&self) -> f64 {
        self.as_shell().curvature_stiffness()
    }

    /// The curvature the free slab takes under a uniform prescribed rest curvature
    /// `Γ_rest = κ e_y ⊗ e_x` (rotation about y accumulating along x) [1/m]: `k = κ C / (C + D)` with
    /// [`curvature_stiffness`](Self::curvature_stiffness) `C` and
    /// [`plate_bending_stiffness`](Self::plate_bending_stiffness) `D`.
    ///
    /// Derivation: with the microrotation following the bent mid-surface, the energy per unit area is
    /// `½ D k² + ½ C (k − κ)²` (the stretch energy of the bent slab is the plate bending energy, the
    /// curvature energy penalises the mismatch with `Γ_rest`); its minimum is at `k = κ C/(C + D)`.
    /// Unlike the shell, whose bending term also measures `Γ − Γ_rest`, the volumetric slab curls to
    /// the prescribed curvature only as `D/C = h² / (6 (1 − ν) L_c² (b₁ + b₂)) → 0`.
    pub fn curvature_under_rest_curvature(&self, kappa: f64) -> f64 {
        let c = self.curvature_stiffness();
        let d = self.plate_bending_stiffness();
        kappa * c / (c + d)
    }
}

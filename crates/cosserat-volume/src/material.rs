//! Material parameters of the isotropic micropolar continuum and the moduli derived from them.
//!
//! [`MicropolarMaterial`] is what a user sets, in SI units; [`MicropolarModuli`] can only be obtained
//! through [`MicropolarMaterial::moduli`], which validates every field, so a kernel never sees
//! `ν = 0.5` (an infinite `λ`) or a negative length scale.

use crate::error::MaterialError;
use cosserat_material::ContinuumParameters;

/// An isotropic micropolar material (Löschner et al. 2023, eqs. 9–11 in the notation of the shell's
/// supplement eqs. 6–7), in SI units.
///
/// There is no `Default`: materials have no physical default. [`MicropolarMaterial::new`] sets the
/// required values and the optional ones to the shell's defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicropolarMaterial {
    /// Young's modulus `E` \[Pa\]. Finite and positive.
    pub youngs_modulus: f64,
    /// Poisson ratio `ν`, in (−1, 0.5).
    pub poisson_ratio: f64,
    /// Mass density `ρ` \[kg/m³\]. Finite and positive.
    pub density: f64,
    /// Cosserat couple modulus factor: `μ_c = mu_c_factor · μ`. Finite and non-negative; default 1.
    pub mu_c_factor: f64,
    /// Internal length `L_c` \[m\] of the curvature energy. Finite and non-negative.
    pub length_scale: f64,
    /// `(b₁, b₂, b₃)` of the curvature energy `μ L_c² (b₁ |sym Γ|² + b₂ |skew Γ|² + b₃ (tr Γ)²)`.
    /// Default `(1, 1, 0)`, the shell's `W_curv` default (`μ L_c² |Γ|²`). Each finite and non-negative.
    pub curvature_coefficients: [f64; 3],
}

impl MicropolarMaterial {
    /// A material with the given required values, `μ_c = μ` and `(b₁, b₂, b₃) = (1, 1, 0)`.
    pub fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64, length_scale: f64) -> Self {
        Self {
            youngs_modulus,
            poisson_ratio,
            density,
            mu_c_factor: 1.0,
            length_scale,
            curvature_coefficients: [1.0, 1.0, 0.0],
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`MaterialError::InvalidParameter`] naming the first offending field.
    pub fn validate(&self) -> Result<(), MaterialError> {
        self.continuum().validate()
    }

    /// The parameters this material shares with the shell's, whose validation it uses.
    pub fn continuum(&self) -> ContinuumParameters {
        ContinuumParameters {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
            mu_c_factor: self.mu_c_factor,
            length_scale: self.length_scale,
            curvature_coefficients: self.curvature_coefficients,
        }
    }

    /// The moduli of the energy density, after validation.
    ///
    /// # Errors
    /// As [`MicropolarMaterial::validate`].
    pub fn moduli(&self) -> Result<MicropolarModuli, MaterialError> {
        self.validate()?;
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let mu = e / (2.0 * (1.0 + nu));
        Ok(MicropolarModuli {
            mu,
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            mu_c: self.mu_c_factor * mu,
            length_scale: self.length_scale,
            curvature_coefficients: self.curvature_coefficients,
        })
    }

    /// The bending stiffness per unit width of a slab of thickness `h` in cylindrical bending that is
    /// prevented from anticlastic curvature (plane strain across the width),
    /// `D = E h³ / (12 (1 − ν²))` \[N·m\].
    pub fn plate_bending_stiffness(&self, thickness: f64) -> f64 {
        let h = thickness;
        self.youngs_modulus * h * h * h / (12.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }

    /// The curvature stiffness per unit width of a slab of thickness `h` bent about its width axis,
    /// `C = h μ L_c² (b₁ + b₂)` \[N·m\]: a uniform `Γ = k e_y ⊗ e_x` has `|sym Γ|² = |skew Γ|² = k²/2`, so
    /// the curvature energy per unit area is `½ C k²`.
    pub fn curvature_stiffness(&self, thickness: f64) -> f64 {
        let mu = self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio));
        let [b1, b2, _] = self.curvature_coefficients;
        thickness * mu * self.length_scale * self.length_scale * (b1 + b2)
    }

    /// The curvature a free slab of thickness `h` takes under a uniform prescribed rest curvature
    /// `Γ_rest = κ e_y ⊗ e_x` (rotation about y accumulating along x) [1/m]:
    /// `k = κ C / (C + D)` with [`curvature_stiffness`](Self::curvature_stiffness) `C` and
    /// [`plate_bending_stiffness`](Self::plate_bending_stiffness) `D`.
    ///
    /// Derivation: with the microrotation following the bent mid-surface, the energy per unit area is
    /// `½ D k² + ½ C (k − κ)²` (the stretch energy of the bent slab is the plate bending energy, the
    /// curvature energy penalises the mismatch with `Γ_rest`); its minimum is at `k = κ C/(C + D)`.
    /// Unlike the shell, whose bending term also measures `Γ − Γ_rest`, the volumetric slab curls to
    /// the prescribed curvature only as `D/C = h² / (6 (1 − ν) L_c² (b₁ + b₂)) → 0`.
    pub fn slab_curvature_under_rest_curvature(&self, thickness: f64, kappa: f64) -> f64 {
        let c = self.curvature_stiffness(thickness);
        let d = self.plate_bending_stiffness(thickness);
        kappa * c / (c + d)
    }
}

/// The moduli of the micropolar energy density, derived from a validated [`MicropolarMaterial`].
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
    /// `(b₁, b₂, b₃)` of the curvature energy.
    pub curvature_coefficients: [f64; 3],
}

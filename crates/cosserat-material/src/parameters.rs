//! Material parameters of a Cosserat shell and the moduli derived from them.
//!
//! [`MaterialParameters`] holds what a user sets, in SI units. [`Moduli`] can only be built from
//! validated parameters ([`MaterialParameters::moduli`]), so a kernel never sees a Poisson ratio of 0.5
//! (an infinite λ) or a negative thickness.

use crate::error::MaterialError;

/// The material of a shell, in SI units (model.md §3.1).
///
/// There is no `Default`: materials have no physical default. Use [`MaterialParameters::new`] for the
/// required values and set the optional ones on the result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialParameters {
    /// Shell thickness `h` \[m\]. Finite and positive.
    pub thickness: f64,
    /// Young's modulus `E` \[Pa\]. Finite and positive.
    pub youngs_modulus: f64,
    /// Poisson ratio `ν`, in (−1, 0.5).
    pub poisson_ratio: f64,
    /// Volumetric mass density `ρ` \[kg/m³\]. Finite and positive (unused by quasi-static runs).
    pub density: f64,
    /// Cosserat couple modulus factor: `μ_c = mu_c_factor · μ`. Finite and non-negative; the paper uses 1.
    pub mu_c_factor: f64,
    /// Internal length scale `L_c` \[m\] of the curvature energy. Finite and non-negative.
    pub length_scale: f64,
    /// The coefficients `(b₁, b₂, b₃)` of the curvature energy
    /// `W_curv(A) = μ L_c² (b₁ |sym A|² + b₂ |skew A|² + b₃ (tr A)²)` (supplement eq. 7).
    ///
    /// Default `(1, 1, 0)`, i.e. `W_curv(A) = μ L_c² |A|²`: this is what the paper's reference code
    /// evaluates, so `L_c` values carry over from the paper's scenes. Each must be finite and
    /// non-negative.
    pub curvature_coefficients: [f64; 3],
    /// Factor `κ_b` on the flat bending term `h³/12 W_m(cΓ)` of the plate model. Default 1.
    pub bending_correction: f64,
}

impl MaterialParameters {
    /// Parameters with the given required values, `μ_c = μ`, `(b₁, b₂, b₃) = (1, 1, 0)`, `κ_b = 1`.
    pub fn new(thickness: f64, youngs_modulus: f64, poisson_ratio: f64, density: f64, length_scale: f64) -> Self {
        Self::with_continuum(
            thickness,
            ContinuumParameters::new(youngs_modulus, poisson_ratio, density, length_scale),
        )
    }

    /// A shell of the given thickness made of `material`, with `κ_b = 1`.
    pub fn with_continuum(thickness: f64, material: ContinuumParameters) -> Self {
        Self {
            thickness,
            youngs_modulus: material.youngs_modulus,
            poisson_ratio: material.poisson_ratio,
            density: material.density,
            mu_c_factor: material.mu_c_factor,
            length_scale: material.length_scale,
            curvature_coefficients: material.curvature_coefficients,
            bending_correction: 1.0,
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`MaterialError::InvalidParameter`] naming the first offending parameter.
    pub fn validate(&self) -> Result<(), MaterialError> {
        check(
            "thickness",
            self.thickness,
            self.thickness > 0.0,
            "must be finite and positive",
        )?;
        self.continuum().validate()?;
        check(
            "bending_correction",
            self.bending_correction,
            self.bending_correction >= 0.0,
            "must be finite and non-negative",
        )?;
        Ok(())
    }

    /// The parameters the shell shares with the other isotropic Cosserat materials.
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

    /// The moduli the energy needs, after validation.
    ///
    /// # Errors
    /// As [`MaterialParameters::validate`].
    pub fn moduli(&self) -> Result<Moduli, MaterialError> {
        self.validate()?;
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let continuum = self.continuum();
        let mu = continuum.shear_modulus();
        Ok(Moduli {
            mu,
            lambda: continuum.lame_lambda(),
            mu_c: self.mu_c_factor * mu,
            // λμ/(λ + 2μ) written without λ, so it stays exact near ν = 0.5.
            plane_lambda: e * nu / (2.0 * (1.0 - nu * nu)),
            thickness: self.thickness,
            length_scale: self.length_scale,
            curvature_coefficients: self.curvature_coefficients,
            bending_correction: self.bending_correction,
        })
    }

    /// The plate bending stiffness `D = E h³ / (12 (1 − ν²))` \[N·m\].
    pub fn plate_bending_stiffness(&self) -> f64 {
        let h = self.thickness;
        self.youngs_modulus * h * h * h / (12.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }

    /// The bending stiffness per unit width of a strip in cylindrical bending in this model [N·m]:
    /// `B = κ_b D + h μ L_c² (b₁ + b₂)`.
    ///
    /// Derivation (docs/model-notes.md): a strip bent about the width axis with curvature `κ` has
    /// `cΓ = κ e₁ ⊗ e₁` and `Γ = κ e₂ ⊗ e₁`, so the bending term gives `κ_b h³/12 (μ + λμ/(λ+2μ)) κ² = ½ κ_b D κ²`
    /// and the curvature term `h μ L_c² (b₁ + b₂) κ²/2`; the energy per area is `½ B κ²`.
    pub fn strip_bending_stiffness(&self) -> f64 {
        self.bending_correction * self.plate_bending_stiffness() + self.curvature_stiffness()
    }

    /// The curvature stiffness per unit width of a strip bent about its width axis,
    /// `C = h μ L_c² (b₁ + b₂)` \[N·m\]: a uniform `Γ = k e₂ ⊗ e₁` has `|sym Γ|² = |skew Γ|² = k²/2`, so
    /// the curvature energy per unit area is `½ C k²`.
    pub fn curvature_stiffness(&self) -> f64 {
        let mu = self.continuum().shear_modulus();
        let [b1, b2, _] = self.curvature_coefficients;
        self.thickness * mu * self.length_scale * self.length_scale * (b1 + b2)
    }
}

/// The parameters of an isotropic Cosserat material that do not depend on how the body is discretised:
/// those of [`MaterialParameters`] without the shell's thickness and bending correction. The
/// volumetric micropolar model has the same ones and validates them here, so that both models accept
/// the same values and reject the others with the same message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuumParameters {
    /// Young's modulus `E` \[Pa\]. Finite and positive.
    pub youngs_modulus: f64,
    /// Poisson ratio `ν`, in (−1, 0.5).
    pub poisson_ratio: f64,
    /// Volumetric mass density `ρ` \[kg/m³\]. Finite and positive.
    pub density: f64,
    /// Cosserat couple modulus factor: `μ_c = mu_c_factor · μ`. Finite and non-negative.
    pub mu_c_factor: f64,
    /// Internal length scale `L_c` \[m\] of the curvature energy. Finite and non-negative.
    pub length_scale: f64,
    /// `(b₁, b₂, b₃)` of the curvature energy. Each finite and non-negative.
    pub curvature_coefficients: [f64; 3],
}

impl ContinuumParameters {
    /// Parameters with the given required values, `μ_c = μ` and `(b₁, b₂, b₃) = (1, 1, 0)` (the
    /// defaults of both models: the paper's).
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

    /// The shear modulus `μ = E / (2 (1 + ν))` \[Pa\].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Lamé's first parameter `λ = E ν / ((1 + ν)(1 − 2ν))` \[Pa\] (infinite at `ν = 0.5`, which
    /// validation rejects).
    pub fn lame_lambda(&self) -> f64 {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`MaterialError::InvalidParameter`] naming the first offending parameter by its field name.
    pub fn validate(&self) -> Result<(), MaterialError> {
        check(
            "youngs_modulus",
            self.youngs_modulus,
            self.youngs_modulus > 0.0,
            "must be finite and positive",
        )?;
        if let Some(reason) = poisson_ratio_problem(self.poisson_ratio) {
            return Err(MaterialError::InvalidParameter {
                name: "poisson_ratio",
                value: self.poisson_ratio,
                reason,
            });
        }
        check(
            "density",
            self.density,
            self.density > 0.0,
            "must be finite and positive",
        )?;
        check(
            "mu_c_factor",
            self.mu_c_factor,
            self.mu_c_factor >= 0.0,
            "must be finite and non-negative",
        )?;
        check(
            "length_scale",
            self.length_scale,
            self.length_scale >= 0.0,
            "must be finite and non-negative",
        )?;
        let names = [
            "curvature_coefficients[0]",
            "curvature_coefficients[1]",
            "curvature_coefficients[2]",
        ];
        for (name, &b) in names.into_iter().zip(&self.curvature_coefficients) {
            check(name, b, b >= 0.0, "must be finite and non-negative")?;
        }
        Ok(())
    }
}

/// `Ok` if `value` is finite and `ok`, else the error naming the parameter.
fn check(name: &'static str, value: f64, ok: bool, reason: &'static str) -> Result<(), MaterialError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(MaterialError::InvalidParameter { name, value, reason })
    }
}

/// The moduli of the energy density, derived from validated [`MaterialParameters`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moduli {
    /// Shear modulus `μ = E / (2 (1 + ν))` \[Pa\].
    pub mu: f64,
    /// Lamé's first parameter `λ = E ν / ((1 + ν)(1 − 2ν))` \[Pa\].
    pub lambda: f64,
    /// Cosserat couple modulus `μ_c` \[Pa\].
    pub mu_c: f64,
    /// The plane-stress combination `λμ/(λ + 2μ) = E ν / (2 (1 − ν²))` \[Pa\].
    pub plane_lambda: f64,
    /// Thickness `h` \[m\].
    pub thickness: f64,
    /// Internal length `L_c` \[m\].
    pub length_scale: f64,
    /// `(b₁, b₂, b₃)` of the curvature energy.
    pub curvature_coefficients: [f64; 3],
    /// `κ_b`.
    pub bending_correction: f64,
}

/// Why a Poisson ratio cannot be used by an isotropic linear material, or `None` if it can: it must be
/// finite and lie in (−1, 0.5). Each bound says which modulus it would make infinite.
pub fn poisson_ratio_problem(nu: f64) -> Option<&'static str> {
    if !nu.is_finite() {
        Some("must be finite")
    } else if nu >= 0.5 {
        Some("must be below 0.5; 0.5 would make the Lamé parameter λ = Eν/((1 + ν)(1 − 2ν)) infinite")
    } else if nu <= -1.0 {
        Some("must be above −1; −1 would make the shear modulus μ = E/(2(1 + ν)) infinite")
    } else {
        None
    }
}

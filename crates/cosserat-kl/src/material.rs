//! Hyperelastic materials and their plane-stress energy densities.
//!
//! The shell's energy integrates a 3D density `W(C)` through the thickness. Kirchhoff–Love kinematics
//! keep the normal a unit normal, so the 3D right Cauchy–Green tensor at a thickness point is
//! block-diagonal in the convected frame: the in-plane block is the mixed tensor `M = ḡ⁻¹ g` (the
//! current over the rest metric of the shifted surface) and the transverse entry `c₃₃` is free. Plane
//! stress (`S₃₃ = 0`) eliminates `c₃₃`; for both materials here this has a closed form, so the
//! condensed density `W_ps(M) = W(M, c₃₃(M))` is an ordinary function of `M` that num-dual can
//! differentiate (Wen & Barbič 2023 solve the condition numerically for general materials).
//!
//! - St. Venant–Kirchhoff, `W = λ/2 (tr E)² + μ |E|²` with `E = ½ (C − I)`: `S₃₃ = 0` gives
//!   `E₃₃ = −λ tr E₂ / (λ + 2μ)`, hence `W_ps = μ |E₂|² + λμ/(λ + 2μ) (tr E₂)²` with `E₂ = ½ (M − I)`.
//! - Compressible neo-Hookean, `W = μ/2 (I₁ − 3) − μ ln J + λ/2 (J − 1)²` (Ciarlet's `(J − 1)²` volume
//!   term rather than `(ln J)²`, chosen because its plane-stress condition is a quadratic): with
//!   `d = det M`, `c₃₃ = s²` and `J = √d s`, `∂W/∂c₃₃ = 0` reads `(μ + λ d) s² − λ √d s − μ = 0`, whose
//!   positive root is `s = (λ √d + √(λ² d + 4μ (μ + λ d))) / (2 (μ + λ d))`. It exists while
//!   `μ + λ d > 0`, always for `ν ≥ 0`; an auxetic material (`λ < 0`) has none beyond `d = μ/|λ|`.
//!
//! Both densities have the linear moduli `λ`, `μ` at small strains, so they agree to second order.

use crate::error::{KlError, check_parameter};
use cosserat_geometry::Real;
use nalgebra::Matrix2;

/// The 3D hyperelastic energy density that is integrated through the thickness.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HyperelasticModel {
    /// St. Venant–Kirchhoff: `W = λ/2 (tr E)² + μ |E|²`, `E = ½ (C − I)`.
    StVenantKirchhoff,
    /// Compressible neo-Hookean: `W = μ/2 (tr C − 3) − μ ln J + λ/2 (J − 1)²`, `J = √det C`.
    NeoHookean,
}

impl HyperelasticModel {
    /// A short name for summaries (`stvk`, `neo_hookean`).
    pub fn name(self) -> &'static str {
        match self {
            HyperelasticModel::StVenantKirchhoff => "stvk",
            HyperelasticModel::NeoHookean => "neo_hookean",
        }
    }
}

/// The material of a Kirchhoff–Love shell, in SI units. There is no `Default`: materials have no
/// physical default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KlMaterial {
    /// The 3D energy density.
    pub model: HyperelasticModel,
    /// Young's modulus `E` \[Pa\]. Finite and positive.
    pub youngs_modulus: f64,
    /// Poisson ratio `ν`, in (−1, 0.5).
    pub poisson_ratio: f64,
}

impl KlMaterial {
    /// A material of the given model with Young's modulus `E` \[Pa\] and Poisson ratio `ν`.
    pub fn new(model: HyperelasticModel, youngs_modulus: f64, poisson_ratio: f64) -> Self {
        Self {
            model,
            youngs_modulus,
            poisson_ratio,
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`KlError::InvalidParameter`] naming the offending parameter.
    pub fn validate(&self) -> Result<(), KlError> {
        check_parameter(
            "youngs_modulus",
            self.youngs_modulus,
            self.youngs_modulus > 0.0,
            "must be finite and positive",
        )?;
        let problem = cosserat_material::poisson_ratio_problem(self.poisson_ratio);
        check_parameter(
            "poisson_ratio",
            self.poisson_ratio,
            problem.is_none(),
            problem.unwrap_or_default(),
        )
    }

    /// The constants the densities use, after validation.
    ///
    /// # Errors
    /// As [`KlMaterial::validate`].
    pub fn constants(&self) -> Result<MaterialConstants, KlError> {
        self.validate()?;
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        Ok(MaterialConstants {
            model: self.model,
            mu: e / (2.0 * (1.0 + nu)),
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            // λμ/(λ + 2μ) written without λ, so it stays exact near ν = 0.5.
            plane_lambda: e * nu / (2.0 * (1.0 - nu * nu)),
        })
    }

    /// The plate bending stiffness `D = E h³ / (12 (1 − ν²))` of a shell of thickness `h` \[N·m\]: the
    /// small-curvature bending stiffness per unit width of both densities.
    pub fn plate_bending_stiffness(&self, thickness: f64) -> f64 {
        let h = thickness;
        self.youngs_modulus * h * h * h / (12.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }
}

/// Validated material constants: only [`KlMaterial::constants`] builds them, so a density never sees
/// `ν = 0.5` or a negative modulus.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialConstants {
    model: HyperelasticModel,
    mu: f64,
    lambda: f64,
    plane_lambda: f64,
}

impl MaterialConstants {
    /// The 3D density.
    pub fn model(&self) -> HyperelasticModel {
        self.model
    }

    /// Shear modulus `μ = E / (2 (1 + ν))` \[Pa\].
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Lamé's first parameter `λ = E ν / ((1 + ν)(1 − 2ν))` \[Pa\].
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The plane-stress combination `λμ/(λ + 2μ) = E ν / (2 (1 − ν²))` \[Pa\].
    pub fn plane_lambda(&self) -> f64 {
        self.plane_lambda
    }
}

/// The 3D density `W(C)` \[J/m³\] of a right Cauchy–Green tensor that is block-diagonal in the convected
/// frame: in-plane mixed block `m = ḡ⁻¹ g` and transverse entry `c33`. Used to check the plane-stress
/// condensation; the shell energy uses [`plane_stress_density`].
///
/// Returns `+∞` for the neo-Hookean density when `det C ≤ 0`.
pub fn density_3d<T: Real>(m: &Matrix2<T>, c33: T, c: &MaterialConstants) -> T {
    match c.model {
        HyperelasticModel::StVenantKirchhoff => {
            let d = m - Matrix2::identity();
            let e33 = (c33 - T::one()) * 0.5;
            let tr_e = d.trace() * 0.5 + e33;
            let norm2 = (d * d).trace() * 0.25 + e33 * e33;
            tr_e * tr_e * (0.5 * c.lambda) + norm2 * c.mu
        }
        HyperelasticModel::NeoHookean => {
            let det = m.determinant() * c33;
            if det.re() <= 0.0 {
                return T::from(f64::INFINITY);
            }
            let j = det.sqrt();
            let jm1 = j - T::one();
            (m.trace() + c33 - T::from(3.0)) * (0.5 * c.mu) - j.ln() * c.mu + jm1 * jm1 * (0.5 * c.lambda)
        }
    }
}

/// The transverse entry `c₃₃` of `C` that makes `S₃₃ = 0` for the in-plane block `m` (module docs), or
/// `None` where the neo-Hookean condition has no positive root (`det m ≤ 0`, or an auxetic material
/// stretched past `det m = μ/|λ|`).
pub fn plane_stress_c33<T: Real>(m: &Matrix2<T>, c: &MaterialConstants) -> Option<T> {
    match c.model {
        HyperelasticModel::StVenantKirchhoff => {
            let tr_e2 = (m.trace() - T::from(2.0)) * 0.5;
            let e33 = -tr_e2 * (c.lambda / (c.lambda + 2.0 * c.mu));
            Some(e33 * 2.0 + T::one())
        }
        HyperelasticModel::NeoHookean => neo_hookean_stretch(m.determinant(), c).map(|s| s * s),
    }
}

/// The transverse stretch `s = √c₃₃` of the neo-Hookean plane-stress condition for `d = det M`: the
/// positive root of `(μ + λd) s² − λ√d s − μ = 0`, written without cancellation for either sign of `λ`.
fn neo_hookean_stretch<T: Real>(d: T, c: &MaterialConstants) -> Option<T> {
    let (mu, lambda) = (c.mu, c.lambda);
    // A positive root exists exactly when μ + λd > 0 (always for λ ≥ 0).
    let a = d * lambda + mu;
    if d.re() <= 0.0 || a.re() <= 0.0 {
        return None;
    }
    let sqrt_d = d.sqrt();
    let root = (d * (lambda * lambda) + a * (4.0 * mu)).sqrt();
    Some(if lambda >= 0.0 {
        (sqrt_d * lambda + root) / (a * 2.0)
    } else {
        (root - sqrt_d * lambda).recip() * (2.0 * mu)
    })
}

/// The plane-stress density `W_ps(M)` \[J/m³\] of the in-plane mixed tensor `m = ḡ⁻¹ g` (module docs).
///
/// Returns `+∞` where the neo-Hookean plane-stress condition has no solution (an inverted or
/// degenerate element), so callers detect it as a non-finite energy instead of a NaN.
pub fn plane_stress_density<T: Real>(m: &Matrix2<T>, c: &MaterialConstants) -> T {
    match c.model {
        HyperelasticModel::StVenantKirchhoff => {
            let d = m - Matrix2::identity();
            let tr = d.trace();
            (d * d).trace() * (0.25 * c.mu) + tr * tr * (0.25 * c.plane_lambda)
        }
        HyperelasticModel::NeoHookean => {
            let det = m.determinant();
            let Some(s) = neo_hookean_stretch(det, c) else {
                return T::from(f64::INFINITY);
            };
            let j = det.sqrt() * s;
            let ln_j = det.ln() * 0.5 + s.ln();
            let jm1 = j - T::one();
            (m.trace() + s * s - T::from(3.0)) * (0.5 * c.mu) - ln_j * c.mu + jm1 * jm1 * (0.5 * c.lambda)
        }
    }
}

//! IPC's smoothed, lagged Coulomb friction (Li et al. 2020, eqs. 14–16).
//!
//! For a contact pair with lagged normal force `λ` \[N\], friction coefficient `μ` and tangent basis `T`
//! (3×2, orthonormal columns spanning the plane normal to the contact direction at the start of the
//! step), the relative tangential displacement over the step is `z = Tᵀ Σᵢ βᵢ Δxᵢ ∈ ℝ²` with the
//! closest-point weights `β` of the lagged configuration. The dissipation potential is
//!
//! ```text
//! D(z) = μ λ f₀(|z|),   f₀' = f₁,   f₁(y) = 2 y/ε − y²/ε²  for y < ε,   1 otherwise,
//! f₀(y) = −y³/(3ε²) + y²/ε + ε/3   for y < ε,   y otherwise,
//! ```
//!
//! with `ε = ε_v Δt` \[m\] for the stick–slide velocity threshold `ε_v` \[m/s\]. Its gradient is the
//! friction force `μ λ f₁(|z|) ẑ` — exactly Coulomb's `μ λ` opposite the slip once `|z| ≥ ε` and a
//! stiff spring (stick) below. `f₁` is C¹, so `D` is C². The Hessian in `z` is positive semi-definite
//! everywhere (`f₁(y)/y ≥ 0` and `f₁'(y) ≥ 0`), so friction needs no projection. `D` has units
//! N·m = J, as the incremental potential (in velocity unknowns, with `Δx = Δt v`) needs.

use nalgebra::{Matrix2, Vector2};

/// The smoothing of the friction law: `f₀`, `f₁` with the slip distance `ε` \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSmoothing {
    /// `ε = ε_v Δt` \[m\]: the tangential displacement over a step below which contact sticks.
    pub epsilon: f64,
}

impl FrictionSmoothing {
    /// The smoothing for a stick–slide velocity threshold `ε_v` \[m/s\] and time step `Δt` \[s\].
    pub fn new(stick_velocity: f64, dt: f64) -> Self {
        Self {
            epsilon: stick_velocity * dt,
        }
    }

    /// `f₀(y)` for `y ≥ 0`.
    pub fn f0(&self, y: f64) -> f64 {
        let e = self.epsilon;
        if y < e {
            -y * y * y / (3.0 * e * e) + y * y / e + e / 3.0
        } else {
            y
        }
    }

    /// `f₁(y) = f₀'(y)` for `y ≥ 0`.
    pub fn f1(&self, y: f64) -> f64 {
        let e = self.epsilon;
        if y < e { 2.0 * y / e - y * y / (e * e) } else { 1.0 }
    }

    /// `f₁(y) / y`, finite at `y = 0` (where it is `2/ε`).
    pub fn f1_over_y(&self, y: f64) -> f64 {
        let e = self.epsilon;
        if y < e { 2.0 / e - y / (e * e) } else { 1.0 / y }
    }

    /// `f₁'(y)`.
    pub fn f1_derivative(&self, y: f64) -> f64 {
        let e = self.epsilon;
        if y < e { 2.0 / e - 2.0 * y / (e * e) } else { 0.0 }
    }

    /// `(f₀(|z|), ∇f₀, ∇²f₀)` with respect to the tangential displacement `z`.
    pub fn potential(&self, z: &Vector2<f64>) -> (f64, Vector2<f64>, Matrix2<f64>) {
        let y = z.norm();
        let a = self.f1_over_y(y);
        // ∇² = f₁/y I + (f₁' y − f₁)/y³ z zᵀ; below ε the coefficient is −1/(ε² y), which with z zᵀ ~ y²
        // stays bounded (and is zero at y = 0).
        let c = if y == 0.0 {
            0.0
        } else if y < self.epsilon {
            -1.0 / (self.epsilon * self.epsilon * y)
        } else {
            -1.0 / (y * y * y)
        };
        (self.f0(y), z * a, Matrix2::identity() * a + z * z.transpose() * c)
    }
}

//! Parameters of the contact model: barrier stiffness and width, friction coefficients per pair of
//! surface ids, the stick–slide threshold, CCD and candidate-search settings.

use crate::barrier::{non_negative, positive};
use crate::ccd::CcdSettings;
use crate::error::ContactError;
use std::collections::BTreeMap;

/// Friction coefficients `μ` per unordered pair of surface ids; pairs not set have `μ = 0`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrictionTable {
    coefficients: BTreeMap<(usize, usize), f64>,
}

impl FrictionTable {
    /// No friction anywhere.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `μ` \[-\] between surfaces `a` and `b` (`a = b` for self-contact).
    ///
    /// # Errors
    /// [`ContactError::InvalidParameter`] unless `μ` is finite and non-negative.
    pub fn set(&mut self, a: usize, b: usize, mu: f64) -> Result<(), ContactError> {
        non_negative("friction coefficient", mu)?;
        self.coefficients.insert((a.min(b), a.max(b)), mu);
        Ok(())
    }

    /// `μ` between surfaces `a` and `b`.
    pub fn get(&self, a: usize, b: usize) -> f64 {
        self.coefficients.get(&(a.min(b), a.max(b))).copied().unwrap_or(0.0)
    }

    /// Whether any coefficient is positive.
    pub fn any(&self) -> bool {
        self.coefficients.values().any(|&m| m > 0.0)
    }
}

/// Parameters of [`crate::ContactTerm`].
#[derive(Debug, Clone, PartialEq)]
pub struct ContactParameters {
    /// Barrier stiffness `κ` \[J/m²\] (energy per pair `−κ (g − d̂)² ln(g/d̂)`).
    pub stiffness: f64,
    /// Barrier width `d̂` \[m\]: a pair interacts while its gap (distance minus thickness) is below it.
    pub barrier_width: f64,
    /// Friction coefficients per pair of surface ids. Default: none.
    pub friction: FrictionTable,
    /// Stick–slide velocity threshold `ε_v` \[m/s\]; the slip distance is `ε_v Δt`. Default 0.1 (the
    /// reference code's default; the paper's scenes set 0.01).
    pub stick_velocity: f64,
    /// CCD settings. Default: 10 % minimum gap fraction.
    pub ccd: CcdSettings,
    /// Factor on the predicted motion of a step swept by the candidate search (≥ 1). Default 2.
    pub sweep_factor: f64,
    /// Extra reach of the candidate search beyond thickness plus barrier width \[m\]. Default `d̂`.
    pub candidate_margin: f64,
    /// Projects each pair's barrier Hessian onto the positive semi-definite cone (IPC does). Default
    /// true. Friction Hessians are positive semi-definite without projection.
    pub project_pd: bool,
}

impl ContactParameters {
    /// Parameters with barrier stiffness `κ` \[J/m²\] and width `d̂` \[m\], and defaults for the rest.
    pub fn new(stiffness: f64, barrier_width: f64) -> Self {
        Self {
            stiffness,
            barrier_width,
            friction: FrictionTable::new(),
            stick_velocity: 0.1,
            ccd: CcdSettings::default(),
            sweep_factor: 2.0,
            candidate_margin: barrier_width,
            project_pd: true,
        }
    }

    /// Checks every range.
    ///
    /// # Errors
    /// [`ContactError::InvalidParameter`] naming the first invalid field.
    pub fn validate(&self) -> Result<(), ContactError> {
        positive("stiffness", self.stiffness)?;
        positive("barrier_width", self.barrier_width)?;
        positive("stick_velocity", self.stick_velocity)?;
        non_negative("candidate_margin", self.candidate_margin)?;
        if !(self.sweep_factor.is_finite() && self.sweep_factor >= 1.0) {
            return Err(ContactError::InvalidParameter {
                name: "sweep_factor",
                value: self.sweep_factor,
                reason: "must be finite and at least 1",
            });
        }
        let s = self.ccd.min_gap_fraction;
        if !(s > 0.0 && s < 1.0) {
            return Err(ContactError::InvalidParameter {
                name: "ccd.min_gap_fraction",
                value: s,
                reason: "must lie in (0, 1)",
            });
        }
        if self.ccd.max_iterations == 0 {
            return Err(ContactError::InvalidParameter {
                name: "ccd.max_iterations",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        Ok(())
    }
}

//! IPC's logarithmic barrier on the gap between two primitives with a contact thickness.
//!
//! For a pair at distance `d` whose surfaces have thicknesses summing to `δ`, the gap is `g = d − δ` and
//! the energy (Li et al. 2020, "Incremental Potential Contact", eq. 6, applied to the gap)
//!
//! ```text
//! b(g) = −κ (g − d̂)² ln(g / d̂)   for 0 < g < d̂,     0 for g ≥ d̂,     +∞ for g ≤ 0,
//! ```
//!
//! is C² at `g = d̂` (value, slope and curvature vanish there) and grows without bound as the gap
//! closes, so a state of finite energy is always separated. Units: `g` and `d̂` in metres, `κ` in J/m²,
//! so `b` is an energy in joules per pair, as the incremental potential needs. The barrier is applied
//! per contact pair without area weighting (as in IPC); a finer mesh has more pairs in contact and so an
//! effectively stiffer barrier, which changes the penetration-free equilibrium gap only logarithmically.
//!
//! Distances come out of [`crate::distance`] squared, so [`Barrier::of_squared_distance`] also gives the
//! derivatives of `s ↦ b(√s − δ)`.

use crate::error::ContactError;
use cosserat_geometry::Real;

/// The barrier `b(g) = −κ (g − d̂)² ln(g / d̂)` on the gap `g`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Barrier {
    /// Stiffness `κ` \[J/m²\].
    pub stiffness: f64,
    /// Width `d̂` \[m\]: the barrier acts for gaps below it.
    pub width: f64,
}

impl Barrier {
    /// A barrier of stiffness `κ` \[J/m²\] and width `d̂` \[m\].
    ///
    /// # Errors
    /// [`ContactError::InvalidParameter`] unless both are finite and positive.
    pub fn try_new(stiffness: f64, width: f64) -> Result<Self, ContactError> {
        positive("stiffness", stiffness)?;
        positive("barrier_width", width)?;
        Ok(Self { stiffness, width })
    }

    /// `b(g)`: `+∞` for `g ≤ 0`, zero for `g ≥ d̂`.
    pub fn value<T: Real>(&self, g: T) -> T {
        if g.re() <= 0.0 {
            return T::from(f64::INFINITY);
        }
        if g.re() >= self.width {
            return T::zero();
        }
        let q = g - T::from(self.width);
        -(q * q * (g / T::from(self.width)).ln()) * self.stiffness
    }

    /// `(b(g), b'(g), b''(g))`; infinite for `g ≤ 0`, zero for `g ≥ d̂`.
    pub fn derivatives(&self, g: f64) -> (f64, f64, f64) {
        if g <= 0.0 {
            return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        }
        if g >= self.width {
            return (0.0, 0.0, 0.0);
        }
        let k = self.stiffness;
        let q = g - self.width;
        let l = (g / self.width).ln();
        let b = -k * q * q * l;
        let db = -k * (2.0 * q * l + q * q / g);
        let d2b = -k * (2.0 * l + 4.0 * q / g - q * q / (g * g));
        (b, db, d2b)
    }

    /// Whether a gap is within the barrier's reach (`g < d̂`).
    pub fn is_active(&self, g: f64) -> bool {
        g < self.width
    }

    /// `(E, dE/ds, d²E/ds²)` of `E(s) = b(√s − δ)` for a squared distance `s` and thickness `δ`.
    pub fn of_squared_distance(&self, s: f64, thickness: f64) -> (f64, f64, f64) {
        let d = s.sqrt();
        let (b, db, d2b) = self.derivatives(d - thickness);
        if b == 0.0 && db == 0.0 {
            return (0.0, 0.0, 0.0);
        }
        (b, db / (2.0 * d), (d2b - db / d) / (4.0 * s))
    }
}

pub(crate) fn positive(name: &'static str, value: f64) -> Result<(), ContactError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ContactError::InvalidParameter {
            name,
            value,
            reason: "must be finite and positive",
        })
    }
}

pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<(), ContactError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ContactError::InvalidParameter {
            name,
            value,
            reason: "must be finite and non-negative",
        })
    }
}

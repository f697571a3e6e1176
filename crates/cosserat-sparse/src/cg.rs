//! Block-Jacobi preconditioned conjugate gradients on the upper-triangular pattern of
//! [`SparseSolver`](super::SparseSolver): the iterative linear solver of [`LinearSolverKind::Cg`].
//!
//! This is the linear solver the reference used for its volumetric Tet4 runs: the preconditioner is
//! the inverse of the 3×3 diagonal blocks (one per node's velocity or angular velocity, unknowns
//! `3b, 3b + 1, 3b + 2`), and each solve runs from zero to a relative residual that Newton's method
//! sets per iteration from a forcing sequence ([`CgForcing`]), with an iteration cap.
//!
//! CG assumes a symmetric positive definite matrix. On a direction of non-positive curvature
//! `pᵀ A p ≤ 0` (an unprojected Hessian away from equilibrium can be indefinite) it stops and returns
//! the last iterate, or the preconditioned steepest-descent step if that happens at once. Started from
//! zero, every iterate before the first non-positive curvature satisfies `bᵀ x > 0`, so for `b = −∇Π`
//! the result is a descent direction (truncated Newton-CG, Nocedal & Wright, *Numerical Optimization*,
//! Algorithm 7.1). Diagonal blocks that are not positive definite are replaced by their absolute value
//! so that the preconditioner stays symmetric positive definite.
//!
//! [`LinearSolverKind::Cg`]: super::LinearSolverKind::Cg

use nalgebra::Matrix3;

use super::pattern::{ColumnTasks, UpperPattern};
use crate::error::LinearSolveError;

/// Settings of the conjugate-gradient solver ([`LinearSolverKind::Cg`](super::LinearSolverKind::Cg)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgSettings {
    /// Stop when `‖b − A x‖₂ ≤ relative_tolerance · ‖b‖₂` (dimensionless, in (0, 1), default 1e-8).
    /// Newton's method overwrites it before every solve from its forcing sequence
    /// (`NewtonSettings::cg_forcing` of the solver crate).
    pub relative_tolerance: f64,
    /// Iteration cap per solve; `None` (default) means `max(1000, n)` for a system of dimension `n`, the
    /// reference's cap. Reaching it is not an error: the last iterate is returned.
    pub max_iterations: Option<usize>,
}

impl Default for CgSettings {
    fn default() -> Self {
        Self {
            relative_tolerance: 1e-8,
            max_iterations: None,
        }
    }
}

impl CgSettings {
    /// The iteration cap for a system of dimension `n`.
    pub fn iteration_cap(&self, n: usize) -> usize {
        self.max_iterations.unwrap_or(n.max(1000))
    }

    /// Checks the tolerance and the cap.
    ///
    /// # Errors
    /// [`LinearSolveError::InvalidCgTolerance`] for a tolerance outside (0, 1) and
    /// [`LinearSolveError::ZeroCgIterationCap`] for a cap of zero.
    pub fn validate(&self) -> Result<(), LinearSolveError> {
        check_tolerance(self.relative_tolerance)?;
        if self.max_iterations == Some(0) {
            return Err(LinearSolveError::ZeroCgIterationCap);
        }
        Ok(())
    }
}

/// Checks that a relative CG tolerance lies in the open interval (0, 1).
pub(crate) fn check_tolerance(value: f64) -> Result<(), LinearSolveError> {
    if value > 0.0 && value < 1.0 {
        Ok(())
    } else {
        Err(LinearSolveError::InvalidCgTolerance { value })
    }
}

/// How Newton's method chooses the relative CG tolerance `η` of each step (inexact Newton).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CgForcing {
    /// The reference's sequence `η = min(0.1, ‖g‖ · min(0.5, √‖g‖))`, with `‖g‖` the Euclidean norm of
    /// the gradient over free unknowns divided by `NewtonSettings::residual_scale` (so in the units of
    /// the residual: N and N·m for a time step's incremental potential). Far from the solution a few CG
    /// iterations suffice; near it `η ~ ‖g‖^{3/2}`, so the steps become exact Newton steps and the
    /// convergence superlinear. `η` is floored at the machine epsilon, below which no relative residual
    /// can be reached. Default.
    #[default]
    Reference,
    /// A fixed relative tolerance in (0, 1).
    Fixed(f64),
}

impl CgForcing {
    /// The relative CG tolerance for a gradient norm `‖g‖` (in the residual's units).
    pub fn relative_tolerance(&self, gradient_norm: f64) -> f64 {
        match *self {
            Self::Reference => {
                let eta = 0.1_f64.min(gradient_norm * 0.5_f64.min(gradient_norm.sqrt()));
                // NaN (impossible for a checked gradient) falls to the floor too.
                if eta >= f64::EPSILON { eta } else { f64::EPSILON }
            }
            Self::Fixed(eta) => eta,
        }
    }
}

/// Why a conjugate-gradient solve stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CgStop {
    /// The relative residual reached the tolerance.
    Converged,
    /// The iteration cap was reached first; the last iterate was returned.
    IterationCap,
    /// A direction of non-positive curvature `pᵀ A p ≤ 0` was met: the matrix is not positive definite.
    /// The last iterate (or the preconditioned steepest-descent step) was returned.
    NegativeCurvature,
}

/// The outcome of one conjugate-gradient solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgReport {
    /// Iterations done (matrix–vector products).
    pub iterations: usize,
    /// `‖b − A x‖₂ / ‖b‖₂` of the returned `x` as updated by the recursion (0 for `b = 0`). At a
    /// negative-curvature stop in the first iteration it is that of the zero vector, 1.
    pub relative_residual: f64,
    /// The relative tolerance the solve aimed at.
    pub relative_tolerance: f64,
    /// Why the iteration stopped.
    pub stop: CgStop,
}

/// The inverses of the 3×3 diagonal blocks of a symmetric matrix, made symmetric positive definite.
#[derive(Debug, Clone)]
pub(crate) struct BlockJacobi {
    n: usize,
    inverse: Vec<Matrix3<f64>>,
}

impl BlockJacobi {
    /// An empty preconditioner for dimension `n` (all blocks identity until [`update`](Self::update)).
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            inverse: vec![Matrix3::identity(); n.div_ceil(3)],
        }
    }

    /// Rebuilds the block inverses from the upper-triangle `values` of `pattern`. A trailing partial
    /// block (dimension not a multiple of three) is padded with the identity.
    pub(crate) fn update(&mut self, pattern: &UpperPattern, values: &[f64]) {
        let mut blocks = vec![Matrix3::<f64>::zeros(); self.inverse.len()];
        for ((&v, &row), &col) in values.iter().zip(pattern.row_idx()).zip(pattern.col_idx()) {
            let b = col / 3;
            if row / 3 == b {
                let (r, c) = (row % 3, col % 3);
                blocks[b][(r, c)] = v;
                blocks[b][(c, r)] = v;
            }
        }
        for p in self.n..3 * blocks.len() {
            blocks[p / 3][(p % 3, p % 3)] = 1.0;
        }
        for (inv, block) in self.inverse.iter_mut().zip(&blocks) {
            *inv = spd_inverse(block);
        }
    }

    /// `z = M⁻¹ r`.
    pub(crate) fn apply_into(&self, r: &[f64], z: &mut [f64]) {
        for (b, inv) in self.inverse.iter().enumerate() {
            let base = 3 * b;
            let len = (self.n - base).min(3);
            for i in 0..len {
                let mut acc = 0.0;
                for j in 0..len {
                    acc += inv[(i, j)] * r[base + j];
                }
                z[base + i] = acc;
            }
        }
    }
}

/// The inverse of a symmetric 3×3 block if it is positive definite; otherwise the inverse of its
/// absolute value `V |Λ| Vᵀ` with eigenvalues floored at `1e-12` of the largest; the identity for a
/// zero block.
fn spd_inverse(m: &Matrix3<f64>) -> Matrix3<f64> {
    if let Some(chol) = m.cholesky() {
        let inv = chol.inverse();
        if inv.iter().all(|v| v.is_finite()) {
            return inv;
        }
    }
    let eig = m.symmetric_eigen();
    let largest = eig.eigenvalues.amax();
    if !(largest.is_finite() && largest > 0.0) {
        return Matrix3::identity();
    }
    let floor = 1e-12 * largest;
    let inv_abs = eig.eigenvalues.map(|l| 1.0 / l.abs().max(floor));
    eig.eigenvectors * Matrix3::from_diagonal(&inv_abs) * eig.eigenvectors.transpose()
}

/// The preconditioner and the vectors of the CG recursion, sized once per pattern.
#[derive(Debug, Clone)]
pub(crate) struct CgSolver {
    pub(crate) preconditioner: BlockJacobi,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl CgSolver {
    /// Buffers for dimension `n`.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            preconditioner: BlockJacobi::new(n),
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// Solves `A x = b` from `x = 0` for the symmetric matrix whose upper triangle (pattern order) is
    /// `values`, with the preconditioner of the last [`BlockJacobi::update`]. `b` and `values` must be
    /// finite.
    ///
    /// # Errors
    /// [`LinearSolveError::CgBreakdown`] if the recursion produces a non-finite value.
    pub(crate) fn solve(
        &mut self,
        pattern: &UpperPattern,
        product: &mut ColumnTasks,
        values: &[f64],
        b: &[f64],
        x: &mut [f64],
        relative_tolerance: f64,
        max_iterations: usize,
    ) -> Result<CgReport, LinearSolveError> {
        let n = b.len();
        let Self {
            preconditioner: m,
            r,
            z,
            p,
            q,
        } = self;
        x.fill(0.0);
        r.copy_from_slice(b);
        let b_norm = dot(b, b).sqrt();
        let report = |iterations, r_norm: f64, stop| CgReport {
            iterations,
            relative_residual: if b_norm > 0.0 { r_norm / b_norm } else { 0.0 },
            relative_tolerance,
            stop,
        };
        if b_norm == 0.0 {
            return Ok(report(0, 0.0, CgStop::Converged));
        }
        if !b_norm.is_finite() {
            return Err(LinearSolveError::CgBreakdown { iteration: 0 });
        }
        let target = relative_tolerance * b_norm;
        let mut r_norm = b_norm;
        let mut rho_old = 0.0;
        let mut iterations = 0;
        while r_norm > target {
            if iterations == max_iterations {
                return Ok(report(iterations, r_norm, CgStop::IterationCap));
            }
            m.apply_into(r, z);
            let rho = dot(r, z);
            if iterations == 0 {
                p.copy_from_slice(z);
            } else {
                conjugate_direction(p, z, rho / rho_old);
            }
            product.product_into(pattern, values, p, q);
            let curvature = dot(p, q);
            iterations += 1;
            if !curvature.is_finite() {
                return Err(LinearSolveError::CgBreakdown { iteration: iterations });
            }
            if curvature <= 0.0 {
                if iterations == 1 {
                    // The preconditioned steepest-descent step, scaled by the magnitude of the curvature
                    // along it (unscaled when the curvature vanishes).
                    let scale = if curvature < 0.0 { rho / -curvature } else { 1.0 };
                    for i in 0..n {
                        x[i] = p[i] * scale;
                    }
                }
                return Ok(report(iterations, r_norm, CgStop::NegativeCurvature));
            }
            step_along(rho / curvature, p, q, x, r);
            rho_old = rho;
            r_norm = dot(r, r).sqrt();
            if !r_norm.is_finite() {
                return Err(LinearSolveError::CgBreakdown { iteration: iterations });
            }
        }
        Ok(report(iterations, r_norm, CgStop::Converged))
    }
}

/// The next search direction `p = z + β p` from the preconditioned residual `z`.
fn conjugate_direction(p: &mut [f64], z: &[f64], beta: f64) {
    for (p, z) in p.iter_mut().zip(z) {
        *p = z + beta * *p;
    }
}

/// A step of length `α` along the direction `p`, whose product with the matrix is `q`: `x += α p`
/// and `r −= α q`.
fn step_along(alpha: f64, p: &[f64], q: &[f64], x: &mut [f64], r: &mut [f64]) {
    for (x, p) in x.iter_mut().zip(p) {
        *x += alpha * p;
    }
    for (r, q) in r.iter_mut().zip(q) {
        *r -= alpha * q;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spd_blocks_are_inverted_exactly() {
        let m = Matrix3::new(4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0);
        let inv = spd_inverse(&m);
        assert!((inv * m - Matrix3::identity()).amax() < 1e-14);
    }

    #[test]
    fn indefinite_blocks_become_their_absolute_value() {
        // diag(2, −1, 3) → inverse of diag(2, 1, 3).
        let m = Matrix3::from_diagonal(&nalgebra::Vector3::new(2.0, -1.0, 3.0));
        let inv = spd_inverse(&m);
        let expected = Matrix3::from_diagonal(&nalgebra::Vector3::new(0.5, 1.0, 1.0 / 3.0));
        assert!((inv - expected).amax() < 1e-14);
        // A zero block (an unknown without stiffness) is left unpreconditioned.
        assert_eq!(spd_inverse(&Matrix3::zeros()), Matrix3::identity());
        // A singular positive semi-definite block: eigenvalue 0 floored at 1e-12 of the largest.
        let s = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 0.0, 2.0));
        let inv = spd_inverse(&s);
        assert!(inv.iter().all(|v| v.is_finite()));
        assert!((inv[(1, 1)] * 2e-12 - 1.0).abs() < 1e-10);
    }

    #[test]
    fn reference_forcing_follows_the_closed_form() {
        // Far from the solution the tolerance is capped at 0.1.
        assert_eq!(CgForcing::Reference.relative_tolerance(100.0), 0.1);
        assert_eq!(CgForcing::Reference.relative_tolerance(0.3), 0.1);
        // ‖g‖ = 0.04: 0.04 · min(0.5, 0.2) = 0.008; ‖g‖ = 1e-4: ‖g‖^{3/2} = 1e-6.
        assert!((CgForcing::Reference.relative_tolerance(0.04) - 0.008).abs() < 1e-17);
        assert!((CgForcing::Reference.relative_tolerance(1e-4) - 1e-6).abs() < 1e-20);
        // Between √‖g‖ = 0.5 and η = 0.1: ‖g‖ = 0.25 gives 0.25 · 0.5 = 0.125 → 0.1.
        assert_eq!(CgForcing::Reference.relative_tolerance(0.25), 0.1);
        // A vanishing gradient is floored at the machine epsilon.
        assert_eq!(CgForcing::Reference.relative_tolerance(0.0), f64::EPSILON);
        assert_eq!(CgForcing::Fixed(0.3).relative_tolerance(1e-9), 0.3);
    }
}

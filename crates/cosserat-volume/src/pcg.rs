//! Preconditioned conjugate gradients on a symmetric matrix stored as its upper triangle (the
//! Hessian layout of `cosserat-assembly`), with a 3×3 block-Jacobi preconditioner.
//!
//! This is the linear solver the reference used for its volumetric Tet4 runs: block-diagonal
//! preconditioning over the 3×3 blocks of each node's velocity or angular velocity, a relative
//! residual tolerance set per Newton iteration by a forcing sequence (`newton_cg`), and an iteration
//! cap. It stops early on a direction of non-positive curvature (the Hessian of an unprojected energy
//! can be indefinite away from equilibrium) and then returns the last iterate, or the preconditioned
//! steepest-descent direction if that happens at once, so the result is always a descent direction
//! for Newton's method (truncated Newton-CG, Nocedal & Wright, Algorithm 7.1).

use crate::error::CgError;
use faer::sparse::SymbolicSparseColMatRef;
use nalgebra::Matrix3;

/// A symmetric matrix given by the values of its upper triangle in a compressed-column pattern.
#[derive(Debug, Clone, Copy)]
pub struct SymmetricUpper<'a> {
    /// The pattern (upper triangle, diagonal included).
    pub pattern: SymbolicSparseColMatRef<'a, usize>,
    /// Values in pattern order.
    pub values: &'a [f64],
}

impl SymmetricUpper<'_> {
    /// The dimension.
    pub fn n(&self) -> usize {
        self.pattern.ncols()
    }

    /// `y = A x`.
    ///
    /// # Panics
    /// If `x` or `y` has a length other than `n`.
    #[track_caller]
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n();
        assert!(x.len() == n && y.len() == n, "vector lengths differ from the dimension");
        y.fill(0.0);
        let col_ptr = self.pattern.col_ptr();
        let row_idx = self.pattern.row_idx();
        for col in 0..n {
            let xc = x[col];
            let mut acc = 0.0;
            for idx in col_ptr[col]..col_ptr[col + 1] {
                let (row, v) = (row_idx[idx], self.values[idx]);
                if row == col {
                    acc += v * xc;
                } else {
                    y[row] += v * xc;
                    acc += v * x[row];
                }
            }
            y[col] += acc;
        }
    }

    fn check_finite(&self) -> Result<(), CgError> {
        match self.values.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(index) => {
                let col_ptr = self.pattern.col_ptr();
                let col = col_ptr.partition_point(|&p| p <= index) - 1;
                Err(CgError::NonFiniteMatrix {
                    index,
                    row: self.pattern.row_idx()[index],
                    col,
                    value: self.values[index],
                })
            }
        }
    }
}

/// The inverse of every 3×3 diagonal block (unknowns `3b, 3b + 1, 3b + 2`).
///
/// A block that is not positive definite is replaced by its absolute value `V |Λ| Vᵀ` (eigenvalues
/// floored at `1e-12` of the largest), so the preconditioner is always symmetric positive definite
/// and the CG directions stay descent directions. A trailing partial block (dimension not a multiple
/// of three) is padded with the identity.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockJacobi {
    n: usize,
    inverse: Vec<Matrix3<f64>>,
}

impl BlockJacobi {
    /// The preconditioner of `a`.
    pub fn new(a: &SymmetricUpper<'_>) -> Self {
        let n = a.n();
        let n_blocks = n.div_ceil(3);
        let mut blocks = vec![Matrix3::<f64>::zeros(); n_blocks];
        let col_ptr = a.pattern.col_ptr();
        let row_idx = a.pattern.row_idx();
        for col in 0..n {
            let b = col / 3;
            for idx in col_ptr[col]..col_ptr[col + 1] {
                let row = row_idx[idx];
                if row / 3 == b {
                    let (r, c) = (row % 3, col % 3);
                    blocks[b][(r, c)] = a.values[idx];
                    blocks[b][(c, r)] = a.values[idx];
                }
            }
        }
        for p in n..3 * n_blocks {
            blocks[p / 3][(p % 3, p % 3)] = 1.0;
        }
        let inverse = blocks.iter().map(spd_inverse).collect();
        Self { n, inverse }
    }

    /// `z = M⁻¹ r`.
    ///
    /// # Panics
    /// If `r` or `z` has a length other than the dimension.
    #[track_caller]
    pub fn apply_into(&self, r: &[f64], z: &mut [f64]) {
        assert!(
            r.len() == self.n && z.len() == self.n,
            "vector lengths differ from the dimension"
        );
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

/// Stopping rules of [`pcg`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgSettings {
    /// Stop when `‖b − A x‖₂ ≤ relative_tolerance · ‖b‖₂` (dimensionless, default 1e-8).
    pub relative_tolerance: f64,
    /// Iteration cap (default 1000).
    pub max_iterations: usize,
}

impl Default for CgSettings {
    fn default() -> Self {
        Self {
            relative_tolerance: 1e-8,
            max_iterations: 1000,
        }
    }
}

/// The outcome of [`pcg`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgReport {
    /// Iterations done (matrix–vector products).
    pub iterations: usize,
    /// `‖b − A x‖₂ / ‖b‖₂` of the returned `x` (recursively updated; 0 for `b = 0`).
    pub relative_residual: f64,
    /// Whether the tolerance was reached.
    pub converged: bool,
    /// Whether a direction of non-positive curvature stopped the iteration.
    pub negative_curvature: bool,
}

/// Reusable vectors of [`pcg`].
#[derive(Debug, Clone, Default)]
pub struct CgWorkspace {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

impl CgWorkspace {
    fn resize(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            v.resize(n, 0.0);
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `A x = b` by preconditioned conjugate gradients from the initial guess in `x`.
///
/// On non-positive curvature `pᵀ A p ≤ 0` the iteration stops: `x` keeps the last iterate, or, at the
/// first iteration, becomes the preconditioned steepest-descent step `M⁻¹ b · (rᵀ M⁻¹ r)/|pᵀ A p|`
/// (`M⁻¹ b` itself if the curvature is exactly zero). Reaching `max_iterations` is not an error: the
/// report says whether the tolerance was met.
///
/// # Errors
/// [`CgError::NonFiniteMatrix`], [`CgError::NonFiniteRhs`] or [`CgError::NonFiniteInitialGuess`] for
/// NaN or infinite input,
/// [`CgError::Breakdown`] if an iterate stops being finite.
///
/// # Panics
/// If `b`, `x` or the preconditioner have a dimension other than the matrix's.
#[track_caller]
pub fn pcg(
    a: &SymmetricUpper<'_>,
    m: &BlockJacobi,
    b: &[f64],
    x: &mut [f64],
    settings: &CgSettings,
    ws: &mut CgWorkspace,
) -> Result<CgReport, CgError> {
    let n = a.n();
    assert!(
        b.len() == n && x.len() == n && m.n == n,
        "dimensions of the matrix, right-hand side, solution and preconditioner differ"
    );
    a.check_finite()?;
    if let Some(index) = b.iter().position(|v| !v.is_finite()) {
        return Err(CgError::NonFiniteRhs { index, value: b[index] });
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(CgError::NonFiniteInitialGuess { index, value: x[index] });
    }
    ws.resize(n);
    let CgWorkspace { r, z, p, q } = ws;
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.fill(0.0);
        return Ok(CgReport {
            iterations: 0,
            relative_residual: 0.0,
            converged: true,
            negative_curvature: false,
        });
    }
    a.mul_into(x, q);
    for i in 0..n {
        r[i] = b[i] - q[i];
    }
    let target = settings.relative_tolerance * b_norm;
    let mut r_norm = dot(r, r).sqrt();
    let mut rho_old = 0.0;
    let mut iterations = 0;
    while r_norm > target && iterations < settings.max_iterations {
        m.apply_into(r, z);
        let rho = dot(r, z);
        if iterations == 0 {
            p.copy_from_slice(z);
        } else {
            let beta = rho / rho_old;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        a.mul_into(p, q);
        let curvature = dot(p, q);
        iterations += 1;
        if curvature <= 0.0 || !curvature.is_finite() {
            if !curvature.is_finite() {
                return Err(CgError::Breakdown { iteration: iterations });
            }
            if iterations == 1 {
                let scale = if curvature < 0.0 { rho / -curvature } else { 1.0 };
                for i in 0..n {
                    x[i] = p[i] * scale;
                }
            }
            return Ok(CgReport {
                iterations,
                relative_residual: r_norm / b_norm,
                converged: false,
                negative_curvature: true,
            });
        }
        let alpha = rho / curvature;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
        }
        rho_old = rho;
        r_norm = dot(r, r).sqrt();
        if !r_norm.is_finite() {
            return Err(CgError::Breakdown { iteration: iterations });
        }
    }
    Ok(CgReport {
        iterations,
        relative_residual: r_norm / b_norm,
        converged: r_norm <= target,
        negative_curvature: false,
    })
}

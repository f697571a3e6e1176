//! The symmetric indefinite factorisation `A = P L B Lᵀ Pᵀ` on the shared supernodal analysis.
//!
//! faer 0.24.4 offers two sparse symmetric indefinite factorisations on a Cholesky analysis: an
//! unpivoted supernodal `L D Lᵀ`, which breaks down on a zero leading minor (a saddle-point matrix
//! with a zero block), and an intranode Bunch–Kaufman `L B Lᵀ`, which pivots with 1×1 and 2×2 blocks
//! inside each supernode. The latter is the more robust and is used here with rook pivoting, which
//! bounds the entries of `L`. Because pivoting cannot cross supernodes, a pivot can still be zero or
//! tiny; [`LbltFactor::check_pivots`] detects exact breakdown and the caller checks the solution's
//! backward error.

use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::lblt::factor::{LbltParams, PivotingStrategy};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{IntranodeLbltRef, SymbolicCholeskyRaw};
use faer::{Conj, MatMut, Spec};

use super::cholesky::{SymmetricFactor, in_factor_order, in_order};
use super::pattern::UpperPattern;
use crate::error::{Factorisation, LinearSolveError};

/// The pivoting parameters of the intranode `L B Lᵀ` factorisation.
pub(super) fn lblt_params() -> Spec<LbltParams, f64> {
    let mut params: Spec<LbltParams, f64> = Default::default();
    params.pivoting = PivotingStrategy::Rook;
    params
}

/// A pivot block of `B`: `d`, or `[a c; c b]`.
#[derive(Debug, Clone, Copy)]
enum Pivot {
    One(f64),
    Two { a: f64, b: f64, c: f64 },
}

/// The pivot data of an intranode `L B Lᵀ` factorisation: the sub-diagonal of `B` and the pivoting
/// permutation. `L` and the diagonal of `B` live in [`SymmetricFactor::l_values`].
#[derive(Debug)]
pub(crate) struct LbltFactor {
    subdiag: Vec<f64>,
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
}

impl LbltFactor {
    /// Buffers for an `n × n` system.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            subdiag: vec![0.0; n],
            perm_fwd: (0..n).collect(),
            perm_inv: (0..n).collect(),
        }
    }

    /// Numerical `L B Lᵀ` factorisation of the matrix whose upper triangle is `values`.
    ///
    /// # Errors
    /// [`LinearSolveError::Singular`] if a 1×1 pivot is zero, a 2×2 pivot block is singular, or a
    /// pivot is not finite.
    pub(crate) fn factorise(
        &mut self,
        sym: &mut SymmetricFactor,
        pattern: &UpperPattern,
        values: &[f64],
    ) -> Result<(), LinearSolveError> {
        let (a, side) = in_factor_order(&mut sym.reordered, pattern, values);
        if matches!(sym.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)) {
            // A diagonal factor (see `cholesky.rs`): unpivoted L D Lᵀ is exact, and faer's checked
            // routine reports a zero pivot (the intranode routine would ignore it).
            for (i, (f, v)) in self.perm_fwd.iter_mut().zip(&mut self.perm_inv).enumerate() {
                (*f, *v) = (i, i);
            }
            self.subdiag.fill(0.0);
            let result = sym.symbolic.factorize_numeric_ldlt(
                &mut sym.l_values,
                a,
                side,
                LdltRegularization::default(),
                sym.par,
                MemStack::new(&mut sym.mem),
                Default::default(),
            );
            return match result {
                Ok(_) => Ok(()),
                Err(LdltError::ZeroPivot { index }) => Err(LinearSolveError::Singular {
                    factorisation: Factorisation::Lblt,
                    col: Some(sym.failed_column(index)),
                }),
            };
        }
        sym.symbolic.factorize_numeric_intranode_lblt(
            &mut sym.l_values,
            &mut self.subdiag,
            &mut self.perm_fwd,
            &mut self.perm_inv,
            a,
            side,
            sym.par,
            MemStack::new(&mut sym.mem),
            lblt_params(),
        );
        self.check_pivots(sym)
    }

    /// Checks the block-diagonal factor `B` of a supernodal factorisation for exact breakdown.
    fn check_pivots(&self, sym: &SymmetricFactor) -> Result<(), LinearSolveError> {
        let mut failed = None;
        self.visit_pivots(sym, |start, pivot| {
            let determinant = match pivot {
                Pivot::One(d) => d,
                Pivot::Two { a, b, c } => a * b - c * c,
            };
            let singular = determinant == 0.0 || !determinant.is_finite();
            if singular {
                failed = Some(start);
            }
            !singular
        });
        match failed {
            Some(permuted) => Err(LinearSolveError::Singular {
                factorisation: Factorisation::Lblt,
                col: Some(sym.original_column(self.perm_fwd[permuted])),
            }),
            None => Ok(()),
        }
    }

    /// Whether the matrix of the last factorisation is positive definite, read from its `B` (a supernodal
    /// factorisation that passed [`check_pivots`](Self::check_pivots)); `None` after the unpivoted
    /// `L D Lᵀ` of a simplicial structure, whose pivots are not read here.
    pub(crate) fn positive_definite(&self, sym: &SymmetricFactor) -> Option<bool> {
        if matches!(sym.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)) {
            return None;
        }
        Some(self.visit_pivots(sym, |_, pivot| match pivot {
            Pivot::One(d) => d > 0.0,
            Pivot::Two { a, b, c } => a * b - c * c > 0.0 && a + b > 0.0,
        }))
    }

    /// Calls `visit` with each pivot block of `B` of a supernodal factorisation and its first column
    /// (in the factor's order), until `visit` returns `false`; returns whether it never did.
    fn visit_pivots(&self, sym: &SymmetricFactor, mut visit: impl FnMut(usize, Pivot) -> bool) -> bool {
        let SymbolicCholeskyRaw::Supernodal(sn) = sym.symbolic.raw() else {
            unreachable!("simplicial structures are factorised by the checked L D Lᵀ");
        };
        for s in 0..sn.n_supernodes() {
            let start = sn.supernode_begin()[s];
            let width = sn.supernode_end()[s] - start;
            let nrows = width + sn.supernode(s).pattern().len();
            let block = &sym.l_values[sn.col_ptr_for_val()[s]..sn.col_ptr_for_val()[s + 1]];
            let diag = |j: usize| block[j * nrows + j];
            let mut j = 0;
            while j < width {
                let off = self.subdiag[start + j];
                let (pivot, size) = if off == 0.0 {
                    (Pivot::One(diag(j)), 1)
                } else {
                    let (a, b) = (diag(j), diag(j + 1));
                    (Pivot::Two { a, b, c: off }, 2)
                };
                if !visit(start + j, pivot) {
                    return false;
                }
                j += size;
            }
        }
        true
    }

    /// Solves `A x = rhs` in place with the last `L B Lᵀ` factorisation.
    pub(crate) fn solve_in_place(&self, sym: &mut SymmetricFactor, rhs: &mut [f64]) {
        let n = rhs.len();
        let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, n);
        let factor = IntranodeLbltRef::new(&sym.symbolic, &sym.l_values, &self.subdiag, perm);
        let (par, mem) = (sym.par, &mut sym.mem);
        in_order(&mut sym.reordered, rhs, |rhs| {
            factor.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(rhs, n, 1),
                par,
                MemStack::new(mem),
            );
        });
    }
}

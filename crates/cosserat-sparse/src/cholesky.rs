//! The symmetric factorisations' shared state: the fill-reducing order with the matrix kept in it
//! (`reordered.rs`), one symbolic analysis of that matrix (elimination tree, supernodes) and the
//! numerical factor storage, plus the supernodal Cholesky `L Lᵀ` itself.
//!
//! The symbolic analysis is asked to be supernodal. faer's intranode Bunch–Kaufman `L B Lᵀ`
//! (`ldlt.rs`) pivots only inside supernodes and degrades to unpivoted `L D Lᵀ` on a simplicial
//! structure, so one supernodal analysis serves both the Cholesky attempt and the indefinite fallback.
//! faer still chooses a simplicial structure when `L` is diagonal (its flop estimate is zero); then
//! no pivoting is needed and the unpivoted `L D Lᵀ` is exact.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::pattern::UpperPattern;
use super::reordered::ReorderedMatrix;
use super::{FactorStats, FillOrdering};
use crate::error::{LinearSolveError, LinearSolveStage};

/// The symbolic Cholesky analysis of a fixed pattern with the buffers for numerical factors and
/// solves.
pub(crate) struct SymmetricFactor {
    /// The analysis of the matrix in the factor's order (`reordered`, where there is a fill-reducing
    /// order), so that it holds no permutation of its own.
    pub(super) symbolic: SymbolicCholesky<usize>,
    /// The matrix in the factor's order; `None` for the identity order.
    pub(super) reordered: Option<ReorderedMatrix>,
    /// Numerical values of `L` (shared by `L Lᵀ` and `L B Lᵀ`).
    pub(super) l_values: Vec<f64>,
    /// Workspace for numerical factorisation and solves, sized once.
    pub(super) mem: MemBuffer,
    pub(super) par: Par,
    stats: FactorStats,
}

impl std::fmt::Debug for SymmetricFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SymmetricFactor")
            .field("symbolic", &self.symbolic)
            .field("reordered", &self.reordered.is_some())
            .field("len_l_values", &self.l_values.len())
            .field("par", &self.par)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl SymmetricFactor {
    /// Orders the pattern and runs the supernodal symbolic analysis; allocates all buffers.
    pub(crate) fn try_new(pattern: &UpperPattern, ordering: FillOrdering, par: Par) -> Result<Self, LinearSolveError> {
        let custom = match ordering {
            FillOrdering::Auto => Some(super::ordering::whole_order(pattern, true)?.0),
            FillOrdering::NestedDissection { block } => super::ordering::nested_dissection(pattern.as_ref(), block),
            FillOrdering::Amd | FillOrdering::Identity => None,
        };
        match (ordering, custom) {
            (FillOrdering::Identity, _) => Self::analyse(pattern, SymmetricOrdering::Identity, par),
            (_, Some(order)) => Self::try_with_order(pattern, &order, par),
            _ => Self::analyse(pattern, SymmetricOrdering::Amd, par),
        }
    }

    /// The symbolic analysis in the given factorisation order (`order[new] = old`), e.g. the order of
    /// an earlier analysis of a pattern that has since grown.
    pub(crate) fn try_with_order(pattern: &UpperPattern, order: &[usize], par: Par) -> Result<Self, LinearSolveError> {
        let mut inverse = vec![0; order.len()];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let perm = faer::perm::PermRef::new_checked(order, &inverse, order.len());
        Self::analyse(pattern, SymmetricOrdering::Custom(perm), par)
    }

    /// The factorisation order (`order[new] = old`).
    pub(crate) fn order(&self) -> Vec<usize> {
        match &self.reordered {
            Some(r) => r.order().to_vec(),
            None => (0..self.symbolic.nrows()).collect(),
        }
    }

    fn analyse(pattern: &UpperPattern, ord: SymmetricOrdering<'_, usize>, par: Par) -> Result<Self, LinearSolveError> {
        let order = match ord {
            SymmetricOrdering::Identity => None,
            SymmetricOrdering::Custom(perm) => Some(perm.arrays().0.to_vec()),
            // faer's minimum degree order comes with its analysis.
            _ => symbolic_analysis(pattern.as_ref(), ord)?.perm().map(|p| p.arrays().0.to_vec()),
        };
        let (reordered, symbolic) = match order {
            Some(order) => {
                let (matrix, upper) = ReorderedMatrix::new(pattern, order);
                (
                    Some(matrix),
                    symbolic_analysis(upper.as_ref(), SymmetricOrdering::Identity)?,
                )
            }
            None => (None, symbolic_analysis(pattern.as_ref(), SymmetricOrdering::Identity)?),
        };
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
            symbolic.factorize_numeric_intranode_lblt_scratch::<f64>(par, super::ldlt::lblt_params()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]);
        let mem = super::memory::mapped_workspace(req).ok_or(LinearSolveError::Faer {
            stage: LinearSolveStage::Workspace,
            source: faer::sparse::FaerError::OutOfMemory,
        })?;
        let l_values = super::memory::mapped_zeros(symbolic.len_val());
        let stats = factor_stats(&symbolic);
        Ok(Self {
            symbolic,
            reordered,
            l_values,
            mem,
            par,
            stats,
        })
    }

    /// Structural statistics of `L`.
    pub(crate) fn stats(&self) -> FactorStats {
        self.stats
    }

    /// The column, in the caller's numbering, of the pivot that faer reports as `index`.
    ///
    /// faer 0.24.4 reports pivot failures 1-based from its simplicial kernels and 0-based from its
    /// supernodal ones; both are mapped here, and an index out of range (which would be a faer bug) is
    /// passed through unchanged rather than panicking.
    pub(super) fn failed_column(&self, index: usize) -> usize {
        let permuted = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => index,
        };
        self.original_column(permuted)
    }

    /// The column, in the caller's numbering, of column `permuted` of the reordered matrix.
    pub(super) fn original_column(&self, permuted: usize) -> usize {
        self.reordered
            .as_ref()
            .and_then(|r| r.order().get(permuted).copied())
            .unwrap_or(permuted)
    }

    /// Numerical Cholesky factorisation of the matrix whose upper triangle is `values`.
    pub(crate) fn factorise_llt(&mut self, pattern: &UpperPattern, values: &[f64]) -> Result<(), LinearSolveError> {
        let (a, side) = in_factor_order(&mut self.reordered, pattern, values);
        let result = self.symbolic.factorize_numeric_llt(
            &mut self.l_values,
            a,
            side,
            LltRegularization::default(),
            self.par,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        match result {
            Ok(_) => Ok(()),
            Err(LltError::NonPositivePivot { index }) => Err(LinearSolveError::NotPositiveDefinite {
                col: self.failed_column(index),
            }),
        }
    }

    /// Solves `L Lᵀ x = rhs` in place with the last Cholesky factorisation.
    pub(crate) fn solve_llt_in_place(&mut self, rhs: &mut [f64]) {
        let factor = LltRef::new(&self.symbolic, &self.l_values);
        let (par, mem) = (self.par, &mut self.mem);
        in_order(&mut self.reordered, rhs, |rhs| {
            let n = rhs.len();
            factor.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(rhs, n, 1),
                par,
                MemStack::new(mem),
            );
        });
    }
}

/// The supernodal symbolic analysis of the upper triangle `pattern` in the order `ord`.
fn symbolic_analysis(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    ord: SymmetricOrdering<'_, usize>,
) -> Result<SymbolicCholesky<usize>, LinearSolveError> {
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    factorize_symbolic_cholesky(pattern, Side::Upper, ord, params).map_err(|source| LinearSolveError::Faer {
        stage: LinearSolveStage::SymmetricSymbolic,
        source,
    })
}

/// The matrix whose upper triangle is `values` as a numerical factorisation takes it: in the factor's
/// order where there is one (its lower triangle), and which triangle it is.
pub(super) fn in_factor_order<'a>(
    reordered: &'a mut Option<ReorderedMatrix>,
    pattern: &'a UpperPattern,
    values: &'a [f64],
) -> (SparseColMatRef<'a, usize, f64>, Side) {
    match reordered {
        Some(r) => (r.gather(values), Side::Lower),
        None => (SparseColMatRef::new(pattern.as_ref(), values), Side::Upper),
    }
}

/// Runs a solve in the factor's order on `rhs`.
pub(super) fn in_order(reordered: &mut Option<ReorderedMatrix>, rhs: &mut [f64], solve: impl FnOnce(&mut [f64])) {
    match reordered {
        Some(r) => r.solve_in_order(rhs, solve),
        None => solve(rhs),
    }
}

/// Number of stored entries of `L` and the operation-count estimate `Σ_j c_j²` from the symbolic
/// structure, with `c_j` the stored entries of column `j` including the diagonal.
fn factor_stats(symbolic: &SymbolicCholesky<usize>) -> FactorStats {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => supernodal_stats(sn, sn.nrows()),
        SymbolicCholeskyRaw::Simplicial(simp) => {
            let counts = simp.col_ptr().windows(2).map(|w| w[1] - w[0]);
            FactorStats {
                nnz_l: counts.clone().sum(),
                flops: counts.map(|c| (c as f64) * (c as f64)).sum(),
                n_supernodes: simp.ncols(),
                domains: 1,
            }
        }
    }
}

/// [`factor_stats`] of the columns before `columns_end` of a supernodal factor, and the number of
/// supernodes that hold any of them (the two-domain halves eliminate only their own columns).
pub(super) fn supernodal_stats(sn: &SymbolicSupernodalCholesky<usize>, columns_end: usize) -> FactorStats {
    let (mut nnz_l, mut flops) = (0usize, 0.0f64);
    let n_supernodes = sn.supernode_begin().partition_point(|&begin| begin < columns_end);
    for s in 0..n_supernodes {
        let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        let below = sn.supernode(s).pattern().len();
        for local in 0..end.min(columns_end) - begin {
            let count = end - begin - local + below;
            nnz_l += count;
            flops += (count as f64) * (count as f64);
        }
    }
    FactorStats {
        nnz_l,
        flops,
        n_supernodes,
        domains: 1,
    }
}

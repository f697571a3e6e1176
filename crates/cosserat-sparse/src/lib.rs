//! Sparse symmetric linear solvers on a fixed sparsity pattern, built on faer.
//!
//! The Newton matrix of the shell simulator is symmetric, sparse, and has the same pattern for the
//! whole run, while its values change every iteration. [`SparseSolver`] therefore does all symbolic
//! work (fill-reducing ordering, elimination tree, supernodes, mirrored LU pattern) once and keeps all
//! workspaces, so a numerical factorisation and solve allocate only what faer allocates internally.
//!
//! Input is the upper triangle including the diagonal in compressed sparse column form (a faer
//! [`SymbolicSparseColMatRef`] plus a values slice in pattern order).
//!
//! Solvers ([`LinearSolverKind`]), four direct ones:
//! - supernodal Cholesky `L Lᵀ` for positive definite matrices (`cholesky.rs`, which also holds the
//!   shared symbolic analysis), on large meshes as two halves factorised at once by a multifrontal
//!   kernel (`multifrontal.rs`) and joined through their separator's dense Schur complement
//!   (`two_domain.rs`, [`DomainSplit`]);
//! - supernodal Bunch–Kaufman `L B Lᵀ` with rook pivoting inside supernodes for indefinite ones
//!   (`ldlt.rs`);
//! - sparse LU with partial pivoting on the mirrored full matrix (`lu.rs`);
//! - `Auto`: Cholesky, then `L B Lᵀ` if the matrix is not positive definite, then LU if `L B Lᵀ` breaks
//!   down or its solution is inaccurate. The factorisation actually used is reported;
//!
//! and one iterative solver, `Cg`: block-Jacobi preconditioned conjugate gradients (`cg.rs`), which
//! needs no symbolic analysis and no factor storage, for large positive definite systems solved
//! inexactly to a relative residual that Newton's method chooses per iteration.
//!
//! Fixed unknowns are eliminated without touching the pattern: their rows and columns are replaced by
//! those of the identity in a copy of the values and their right-hand-side entries are zeroed, so the
//! solve returns the reduced system's solution on the free unknowns and exact zeros on the fixed ones.

mod cg;
mod cholesky;
mod error;
mod ldlt;
mod lu;
pub mod memory;
mod metis;
mod multifrontal;
mod ordering;
mod pattern;
mod reordered;
#[cfg(feature = "testing")]
pub mod testing;
mod two_domain;
mod vector_state;

use faer::Par;
use faer::sparse::SymbolicSparseColMatRef;

pub use self::cg::{CgForcing, CgReport, CgSettings, CgStop};

use self::cg::CgSolver;
use self::cholesky::SymmetricFactor;
use self::ldlt::LbltFactor;
use self::lu::LuFactor;
use self::pattern::{ColumnTasks, UpperPattern, backward_error};
use self::two_domain::TwoDomainCholesky;
pub use crate::error::{Factorisation, LinearSolveError, LinearSolveStage};

/// Which factorisation [`SparseSolver`] uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum LinearSolverKind {
    /// Supernodal Cholesky `L Lᵀ`. Fails with [`LinearSolveError::NotPositiveDefinite`] on a matrix
    /// that is not positive definite. The fastest choice for positive definite systems.
    Cholesky,
    /// Symmetric indefinite `P L B Lᵀ Pᵀ` with 1×1 and 2×2 pivots (faer's intranode Bunch–Kaufman with
    /// rook pivoting, the most robust symmetric indefinite factorisation faer 0.24 offers).
    Ldlt,
    /// Sparse LU with partial pivoting on the full matrix: the most robust and the most expensive.
    Lu,
    /// Cholesky first; on a non-positive pivot the symmetric indefinite factorisation; if that breaks
    /// down or its solution's backward error exceeds the bound, LU. The LU analysis is done on first
    /// use only and then kept.
    #[default]
    Auto,
    /// Conjugate gradients with a 3×3 block-Jacobi preconditioner ([`CgSettings`]), for large positive
    /// definite systems whose factorisation would be too expensive (volumetric meshes). Inexact by
    /// design: each solve stops at the relative residual `settings.cg.relative_tolerance` (Newton's
    /// method sets it per iteration, see [`CgForcing`]) or at the iteration cap, and no backward-error
    /// check is made. Not meant for indefinite matrices: at a direction of non-positive curvature it
    /// stops and returns the last iterate, which for a right-hand side `−∇Π` is still a descent
    /// direction (truncated Newton-CG), not a solution. No symbolic analysis is run.
    Cg,
}

/// The fill-reducing ordering of the symmetric factorisations. LU always uses faer's COLAMD column
/// ordering, which faer 0.24 does not let the caller replace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum FillOrdering {
    /// AMD or METIS's nested dissection (on nodes of three unknowns): nested dissection when its
    /// factor needs at most three quarters of AMD's operations, counted exactly from both orders'
    /// column counts before the symbolic analysis (it then factorises faster despite a lower rate
    /// per operation). In the two-domain Cholesky, the same choice is made inside each domain.
    #[default]
    Auto,
    /// Approximate minimum degree (AMD).
    Amd,
    /// No reordering (for banded matrices, or to make the factor structure predictable).
    Identity,
    /// METIS's multilevel nested dissection on the graph of node blocks of the given size (three
    /// unknowns per node for shells): less fill and larger supernodes than AMD on large meshes. Falls
    /// back to AMD if the size is not a multiple of the block.
    NestedDissection {
        /// Unknowns per node.
        block: usize,
    },
}

/// Whether the Cholesky factorisation splits the unknowns into two domains that are factorised at the
/// same time, one per core, and joined through the dense Schur complement of their separator (a
/// vertex bisection of the node graph). faer's factorisation of one matrix is sequential over its
/// supernodes; on two cores the split nearly doubles its rate (docs/performance.md). The split
/// applies to the Cholesky attempt with the AMD ordering (inside each domain); the indefinite and LU
/// fallbacks factorise the whole matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum DomainSplit {
    /// One factorisation of the whole matrix.
    Off,
    /// Two domains for systems of at least [`DomainSplit::AUTO_MIN_UNKNOWNS`] unknowns whose node graph
    /// (three unknowns per node) bisects into balanced parts with a small separator, and only if the
    /// larger domain's factorisation plus the separator's needs at most 0.7 of the operations of the
    /// whole matrix's (counted exactly from the column counts of both orderings).
    /// The choice depends on the pattern only, never on the number of threads, so a run gives the same
    /// results on any machine. A time stepper whose pattern grows with contact
    /// keeps the choice made for its first pattern.
    #[default]
    Auto,
    /// Two domains whenever the node graph can be bisected with a separator of at most `4 √n`
    /// unknowns, balanced or not (for tests and comparisons).
    Always,
}

/// The largest growth of the factor's operations, relative to the last analysis that ordered its
/// pattern afresh, at which [`SparseSolver::try_grown`] keeps reusing the orders. Orders found for a
/// pattern stay good while contact adds a few couplings; the bound renews them once the couplings
/// have changed the factor's structure.
pub const GROWN_REORDER_RATIO: f64 = 1.25;

/// The largest ratio of the split's critical-path operations to the whole factorisation's at which
/// [`DomainSplit::Auto`] splits.
const AUTO_MAX_CRITICAL_SHARE: f64 = 0.7;

impl DomainSplit {
    /// The size from which [`DomainSplit::Auto`] splits.
    pub const AUTO_MIN_UNKNOWNS: usize = 20_000;
}

/// Settings of [`SparseSolver`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearSolverSettings {
    /// The factorisation (default [`LinearSolverKind::Auto`]).
    pub kind: LinearSolverKind,
    /// The fill-reducing ordering of the symmetric factorisations (default [`FillOrdering::Auto`]).
    pub ordering: FillOrdering,
    /// faer's parallelism for factorisation and solves (default sequential).
    pub parallelism: Par,
    /// Largest accepted normwise backward error `‖b − A x‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` of a solution
    /// (dimensionless, default 1e-8). A backward-stable factorisation reaches about 1e-15; a larger
    /// value signals pivot growth. `Auto` then falls back to LU; otherwise the solve fails with
    /// [`LinearSolveError::Inaccurate`]. `f64::INFINITY` disables the check. Not used by
    /// [`LinearSolverKind::Cg`].
    pub max_backward_error: f64,
    /// Tolerance and iteration cap of [`LinearSolverKind::Cg`] (ignored by the factorisations).
    pub cg: CgSettings,
    /// Two-domain Cholesky (default [`DomainSplit::Auto`]).
    pub domains: DomainSplit,
}

impl Default for LinearSolverSettings {
    fn default() -> Self {
        Self {
            kind: LinearSolverKind::Auto,
            ordering: FillOrdering::Auto,
            parallelism: Par::Seq,
            max_backward_error: 1e-8,
            cg: CgSettings::default(),
            domains: DomainSplit::Auto,
        }
    }
}

/// Structural statistics of the symmetric factor `L`, for performance tables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactorStats {
    /// Entries of `L` in the supernodal structure, diagonal included. Supernode amalgamation may store
    /// some explicit zeros; they are counted because the factorisation works on them.
    pub nnz_l: usize,
    /// Operation-count estimate `Σ_j c_j²` of the numerical factorisation, with `c_j` the entries of
    /// column `j` of `L` (about twice the number of multiply–add pairs).
    pub flops: f64,
    /// Number of supernodes (with two domains: of both, plus the dense separator block).
    pub n_supernodes: usize,
    /// 1 for one factorisation of the whole matrix, 2 for the two-domain Cholesky ([`DomainSplit`]).
    pub domains: usize,
}

/// A sparse symmetric solver for one fixed pattern: symbolic analysis once, numerical factorisation
/// and solves many times.
///
/// ```
/// use cosserat_sparse::{LinearSolverSettings, SparseSolver};
/// use faer::sparse::SymbolicSparseColMat;
/// // Upper triangle of [[4, 1], [1, 3]].
/// let pattern = SymbolicSparseColMat::new_checked(2, 2, vec![0, 1, 3], None, vec![0, 0, 1]);
/// let mut solver = SparseSolver::try_new(pattern.as_ref(), LinearSolverSettings::default()).unwrap();
/// solver.factorise(&[4.0, 1.0, 3.0], None).unwrap();
/// let mut x = [1.0, 2.0];
/// solver.solve_in_place(&mut x).unwrap();
/// assert!((x[0] - 1.0 / 11.0).abs() < 1e-15 && (x[1] - 7.0 / 11.0).abs() < 1e-15);
/// ```
#[derive(Debug)]
pub struct SparseSolver {
    settings: LinearSolverSettings,
    pattern: UpperPattern,
    symmetric: Option<SymmetricFactor>,
    /// The two-domain Cholesky, when the settings and the pattern call for it.
    two_domain: Option<TwoDomainCholesky>,
    /// Whether the two-domain analysis was attempted for the current settings.
    two_domain_tried: bool,
    lblt: Option<LbltFactor>,
    lu: Option<LuFactor>,
    cg: Option<CgSolver>,
    /// The values actually factorised (fixed rows and columns replaced by the identity).
    values: Vec<f64>,
    /// The fixed mask of the current factorisation (all `false` without one).
    fixed: Vec<bool>,
    norm_a: f64,
    current: Option<Factorisation>,
    rhs_copy: Vec<f64>,
    product: Vec<f64>,
    /// The column tasks of the passes over the values: their preparation before each factorisation,
    /// the product `A x` that checks every direct solution, and CG's products.
    column_tasks: ColumnTasks,
    symbolic_analyses: usize,
    /// The operations of the factor of the last analysis that ordered its pattern afresh (the
    /// reference of [`SparseSolver::try_grown`]).
    fresh_operations: Option<f64>,
    /// Whether the symbolic analysis reused the orders of the solver this one grew from.
    reuses_orders: bool,
    last_backward_error: Option<f64>,
    last_cg: Option<CgReport>,
    /// In `Auto`, whether the last factorisation found the matrix indefinite: the next one then starts
    /// with `L B Lᵀ` (see [`factorise_auto`](Self::factorise_auto)).
    indefinite_last: bool,
}

/// Checks the settings' numerical values.
fn validate(settings: &LinearSolverSettings) -> Result<(), LinearSolveError> {
    let bound = settings.max_backward_error;
    if bound.is_nan() || bound <= 0.0 {
        return Err(LinearSolveError::InvalidBackwardErrorBound { value: bound });
    }
    settings.cg.validate()
}

impl SparseSolver {
    /// Validates and copies the pattern (upper triangle with every diagonal entry stored) and runs the
    /// symbolic analysis the chosen kind needs (none for [`LinearSolverKind::Cg`]).
    ///
    /// # Errors
    /// [`LinearSolveError::InvalidBackwardErrorBound`] for a bound that is not positive,
    /// [`LinearSolveError::InvalidCgTolerance`] or [`LinearSolveError::ZeroCgIterationCap`] for invalid
    /// CG settings, a pattern
    /// error ([`LinearSolveError::NotSquare`], [`LinearSolveError::LowerTriangleEntry`],
    /// [`LinearSolveError::MissingDiagonal`], ...) or [`LinearSolveError::Faer`] if faer runs out of
    /// memory.
    pub fn try_new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        settings: LinearSolverSettings,
    ) -> Result<Self, LinearSolveError> {
        let mut solver = Self::unanalysed(pattern, settings)?;
        solver.prepare_symbolic()?;
        Ok(solver)
    }

    /// A solver for `pattern` with `settings`, reusing this solver's fill-reducing orders (if the
    /// settings keep its ordering and parallelism, and any two-domain split it made):
    /// for a pattern of the same dimension that contains this solver's, such as a Hessian pattern
    /// grown by new contact couplings. The symbolic analysis then skips the orderings, which cost
    /// several times the analysis itself. A two-domain split keeps its domains' orders, and the nodes
    /// that a new entry couples across the domains move into the separator. The orders are reused as
    /// long as the factor needs at most [`GROWN_REORDER_RATIO`] times the operations of the last
    /// analysis that ordered afresh; beyond that, or when nothing can be reused, the pattern is
    /// ordered afresh as by [`try_new`](Self::try_new). The choice depends on the sequence of patterns
    /// only, so results do not depend on the number of threads.
    ///
    /// # Errors
    /// As [`try_new`](Self::try_new).
    pub fn try_grown(
        &self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        settings: LinearSolverSettings,
    ) -> Result<Self, LinearSolveError> {
        let mut grown = Self::unanalysed(pattern, settings)?;
        let same_orders =
            settings.ordering == self.settings.ordering && settings.parallelism == self.settings.parallelism;
        if same_orders && grown.pattern.n() == self.pattern.n() {
            grown.two_domain_tried = self.two_domain_tried;
            grown.indefinite_last = self.indefinite_last;
            if let Some(split) = &self.two_domain {
                grown.two_domain = split.try_grown(&grown.pattern)?;
            } else if let Some(symmetric) = &self.symmetric {
                grown.symmetric = Some(SymmetricFactor::try_with_order(
                    &grown.pattern,
                    &symmetric.order(),
                    self.settings.parallelism,
                )?);
            }
            let operations = grown.symmetric_stats().map(|stats| stats.flops);
            match (operations, self.fresh_operations) {
                (Some(operations), Some(fresh)) if operations <= GROWN_REORDER_RATIO * fresh => {
                    grown.fresh_operations = Some(fresh);
                    grown.symbolic_analyses = 1;
                    grown.reuses_orders = true;
                }
                _ => {
                    grown.two_domain = None;
                    grown.symmetric = None;
                    grown.two_domain_tried = false;
                }
            }
        }
        grown.prepare_symbolic()?;
        Ok(grown)
    }

    /// The solver with its buffers and no symbolic analysis.
    fn unanalysed(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        settings: LinearSolverSettings,
    ) -> Result<Self, LinearSolveError> {
        validate(&settings)?;
        let pattern = UpperPattern::try_new(pattern)?;
        let n = pattern.n();
        let nnz = pattern.nnz();
        let column_tasks = ColumnTasks::new(&pattern);
        let solver = Self {
            settings,
            pattern,
            symmetric: None,
            two_domain: None,
            two_domain_tried: false,
            lblt: None,
            lu: None,
            cg: None,
            values: memory::mapped_zeros(nnz),
            fixed: vec![false; n],
            norm_a: 0.0,
            current: None,
            rhs_copy: vec![0.0; n],
            product: vec![0.0; n],
            column_tasks,
            symbolic_analyses: 0,
            fresh_operations: None,
            reuses_orders: false,
            last_backward_error: None,
            last_cg: None,
            indefinite_last: false,
        };
        Ok(solver)
    }

    /// Runs the symbolic analyses the current kind needs and that are not done yet (for CG: allocates
    /// its vectors).
    fn prepare_symbolic(&mut self) -> Result<(), LinearSolveError> {
        let kind = self.settings.kind;
        if kind == LinearSolverKind::Cg {
            if self.cg.is_none() {
                self.cg = Some(CgSolver::new(self.pattern.n()));
            }
            return Ok(());
        }
        if matches!(kind, LinearSolverKind::Cholesky | LinearSolverKind::Auto) && !self.two_domain_tried {
            self.two_domain_tried = true;
            self.two_domain = self.try_two_domain()?;
            if self.two_domain.is_some() {
                self.symbolic_analyses += 1;
            }
        }
        if kind == LinearSolverKind::Ldlt || (kind != LinearSolverKind::Lu && self.two_domain.is_none()) {
            self.ensure_symmetric()?;
        }
        if matches!(kind, LinearSolverKind::Ldlt | LinearSolverKind::Auto) && self.lblt.is_none() {
            self.lblt = Some(LbltFactor::new(self.pattern.n()));
        }
        if kind == LinearSolverKind::Lu {
            self.ensure_lu()?;
        }
        if self.fresh_operations.is_none() {
            self.fresh_operations = self.symmetric_stats().map(|stats| stats.flops);
        }
        Ok(())
    }

    /// The two-domain Cholesky analysis, if the settings ask for it and the pattern bisects well.
    fn try_two_domain(&self) -> Result<Option<TwoDomainCholesky>, LinearSolveError> {
        let n = self.pattern.n();
        let auto = match (self.settings.domains, self.settings.ordering) {
            (DomainSplit::Off, _) => return Ok(None),
            (DomainSplit::Auto, FillOrdering::Auto | FillOrdering::Amd) if n >= DomainSplit::AUTO_MIN_UNKNOWNS => true,
            (DomainSplit::Auto, _) => return Ok(None),
            (DomainSplit::Always, _) => false,
        };
        let Some(bisection) = ordering::bisection(self.pattern.as_ref(), ordering::NODE_BLOCK) else {
            return Ok(None);
        };
        let n_sep = bisection.separator.len();
        let smallest = bisection.parts.iter().map(Vec::len).min().unwrap_or(0);
        // A separator whose dense Schur complement (n_sep² entries, n_sep³/3 operations) stays small
        // against the domains' factors (about n log n entries and n^1.5 operations on a 2D mesh), and,
        // for `Auto`, balanced parts (the slower half sets the time).
        if smallest == 0 || n_sep * n_sep > 16 * n || (auto && 5 * smallest < n) {
            return Ok(None);
        }
        // On two cores the split pays when its critical path is well below the whole factorisation:
        // measured at 0.46 of the whole's operations on the plate strip Tri6 320 × 32 (factorisation
        // 1.9× faster), 0.67 on the Armadillos (two bodies, step 1.3× faster), and 0.73 on the closed
        // Bunny surface cut at a breadth-first level (no faster, and more memory); METIS's separator
        // cuts the Bunny below the bound.
        TwoDomainCholesky::try_new(
            &self.pattern,
            &bisection,
            auto.then_some(AUTO_MAX_CRITICAL_SHARE),
            self.settings.ordering == FillOrdering::Auto,
        )
    }

    /// Runs the whole-matrix symbolic analysis if it is not there yet (with the two-domain Cholesky,
    /// only when the indefinite fallback first needs it).
    fn ensure_symmetric(&mut self) -> Result<(), LinearSolveError> {
        if self.symmetric.is_none() {
            self.symmetric = Some(SymmetricFactor::try_new(
                &self.pattern,
                self.settings.ordering,
                self.settings.parallelism,
            )?);
            self.symbolic_analyses += 1;
        }
        Ok(())
    }

    fn ensure_lu(&mut self) -> Result<&mut LuFactor, LinearSolveError> {
        if self.lu.is_none() {
            self.lu = Some(LuFactor::try_new(&self.pattern, self.settings.parallelism)?);
            self.symbolic_analyses += 1;
        }
        Ok(self.lu.as_mut().expect("the LU factor was just built"))
    }

    /// The current settings.
    pub fn settings(&self) -> &LinearSolverSettings {
        &self.settings
    }

    /// Changes the settings. Symbolic analyses that remain valid are kept; a new ordering or
    /// parallelism discards them and redoes the ones the new kind needs. The current factorisation is
    /// discarded, unless only the CG settings changed (they do not enter the preconditioner).
    ///
    /// # Errors
    /// As [`try_new`](Self::try_new) for the settings and the symbolic analysis.
    pub fn set_settings(&mut self, settings: LinearSolverSettings) -> Result<(), LinearSolveError> {
        if settings == self.settings {
            return Ok(());
        }
        validate(&settings)?;
        if settings.ordering != self.settings.ordering || settings.parallelism != self.settings.parallelism {
            self.symmetric = None;
            self.lu = None;
        }
        if settings.ordering != self.settings.ordering || settings.domains != self.settings.domains {
            self.two_domain = None;
            self.two_domain_tried = false;
            self.fresh_operations = None;
        }
        let only_cg_changed = LinearSolverSettings {
            cg: self.settings.cg,
            ..settings
        } == self.settings;
        self.settings = settings;
        if !only_cg_changed {
            self.current = None;
        }
        self.prepare_symbolic()
    }

    /// Sets the relative tolerance of the next [`LinearSolverKind::Cg`] solves
    /// (`settings().cg.relative_tolerance`) without discarding the preconditioner. Newton's method calls
    /// it before every solve with the tolerance of its forcing sequence.
    ///
    /// # Errors
    /// [`LinearSolveError::InvalidCgTolerance`] for a tolerance outside (0, 1); the settings are then
    /// unchanged.
    pub fn set_cg_relative_tolerance(&mut self, relative_tolerance: f64) -> Result<(), LinearSolveError> {
        cg::check_tolerance(relative_tolerance)?;
        self.settings.cg.relative_tolerance = relative_tolerance;
        Ok(())
    }

    /// The dimension `n` of the system.
    pub fn n(&self) -> usize {
        self.pattern.n()
    }

    /// The number of stored entries of the upper-triangle pattern (the length of the values slice).
    pub fn nnz(&self) -> usize {
        self.pattern.nnz()
    }

    /// Whether `pattern` is the pattern this solver was built for (same dimension and the same entries
    /// in the same order).
    pub fn pattern_matches(&self, pattern: SymbolicSparseColMatRef<'_, usize>) -> bool {
        self.pattern.same_as(pattern)
    }

    /// How many symbolic analyses this solver has run: one for the symmetric factorisations, one for
    /// LU, each at most once per pattern and settings (none for CG).
    pub fn symbolic_analysis_count(&self) -> usize {
        self.symbolic_analyses
    }

    /// Whether the symbolic analysis reused the fill-reducing orders of the solver this one grew from
    /// ([`try_grown`](Self::try_grown)) instead of ordering its pattern afresh.
    pub fn reuses_orders(&self) -> bool {
        self.reuses_orders
    }

    /// Structural statistics of the symmetric factor `L` (`None` for pure LU, whose factor structure
    /// faer 0.24 does not expose).
    pub fn symmetric_stats(&self) -> Option<FactorStats> {
        match &self.two_domain {
            Some(split) => Some(split.stats()),
            None => self.symmetric.as_ref().map(SymmetricFactor::stats),
        }
    }

    /// The factorisation currently held, if any. After a solve in `Auto` mode this is the one that
    /// produced the solution.
    pub fn factorisation(&self) -> Option<Factorisation> {
        self.current
    }

    /// The normwise backward error of the last solution (`None` after a CG solve, which is inexact by
    /// design and is not checked).
    pub fn last_backward_error(&self) -> Option<f64> {
        self.last_backward_error
    }

    /// The report of the last [`LinearSolverKind::Cg`] solve (iterations, relative residual, why it
    /// stopped); `None` before the first CG solve and after a solve by a factorisation.
    pub fn last_cg_report(&self) -> Option<CgReport> {
        self.last_cg
    }

    /// The number of CG iterations of the last solve (0 unless it was a CG solve).
    pub fn last_cg_iterations(&self) -> usize {
        self.last_cg.map_or(0, |r| r.iterations)
    }

    /// Factorises the symmetric matrix whose upper triangle (pattern order) is `values`, with the
    /// unknowns marked in `fixed` eliminated. For [`LinearSolverKind::Cg`] it keeps the values and
    /// builds the block-Jacobi preconditioner instead.
    ///
    /// # Errors
    /// - [`LinearSolveError::NonFiniteValue`] naming the first NaN or infinite value;
    /// - [`LinearSolveError::NotPositiveDefinite`] for `Cholesky` on a matrix that is not positive
    ///   definite;
    /// - [`LinearSolveError::Singular`] if the last factorisation tried breaks down;
    /// - [`LinearSolveError::Faer`] on allocation failure.
    ///
    /// # Panics
    /// If `values.len() != self.nnz()` or `fixed` has a length other than `self.n()`.
    #[track_caller]
    pub fn factorise(&mut self, values: &[f64], fixed: Option<&[bool]>) -> Result<Factorisation, LinearSolveError> {
        let result = self.factorise_values(values, fixed);
        self.clear_vector_state();
        result
    }

    /// Leaves the vector registers of the threads that ran faer's kernels clean (see
    /// [`vector_state`]).
    fn clear_vector_state(&self) {
        if self.settings.parallelism == Par::Seq {
            vector_state::clear_this_thread();
        } else {
            vector_state::clear_all_threads();
        }
    }

    /// [`factorise`](Self::factorise) without the clean-up of the vector registers.
    #[track_caller]
    fn factorise_values(&mut self, values: &[f64], fixed: Option<&[bool]>) -> Result<Factorisation, LinearSolveError> {
        assert_eq!(
            values.len(),
            self.nnz(),
            "values slice length differs from the pattern's entry count"
        );
        if let Some(f) = fixed {
            assert_eq!(f.len(), self.n(), "fixed mask length differs from the dimension");
        }
        self.current = None;
        self.norm_a =
            self.column_tasks
                .prepare_values(&self.pattern, values, fixed, &mut self.values, &mut self.product)?;
        match fixed {
            Some(f) => self.fixed.copy_from_slice(f),
            None => self.fixed.fill(false),
        }
        let used = match self.settings.kind {
            LinearSolverKind::Cholesky => self.factorise_llt()?,
            LinearSolverKind::Ldlt => self.factorise_lblt()?,
            LinearSolverKind::Lu => self.factorise_lu()?,
            LinearSolverKind::Cg => self.prepare_cg(),
            LinearSolverKind::Auto => self.factorise_auto()?,
        };
        self.current = Some(used);
        Ok(used)
    }

    /// `Auto`: Cholesky, `L B Lᵀ` where it breaks down, LU where that is singular.
    ///
    /// While the matrices stay indefinite (a twisted strip past its buckling, a shell through a snap)
    /// every Cholesky attempt breaks down again, after much of its work; so after a matrix that needed
    /// `L B Lᵀ` the next starts with it. Where that finds the matrix positive definite, the Cholesky
    /// factorisation follows and is the one used, so that the factor and the solution are always
    /// those of the order above.
    fn factorise_auto(&mut self) -> Result<Factorisation, LinearSolveError> {
        if self.indefinite_last {
            match self.factorise_lblt() {
                Ok(f) if self.lblt_positive_definite() == Some(false) => return Ok(f),
                Ok(_) => self.indefinite_last = false,
                Err(LinearSolveError::Singular { .. }) => return self.factorise_lu(),
                Err(e) => return Err(e),
            }
        }
        match self.factorise_llt() {
            Err(LinearSolveError::NotPositiveDefinite { .. }) => {}
            other => return other,
        }
        match self.factorise_lblt() {
            Ok(f) => {
                self.indefinite_last = self.lblt_positive_definite() == Some(false);
                Ok(f)
            }
            Err(LinearSolveError::Singular { .. }) => {
                self.indefinite_last = true;
                self.factorise_lu()
            }
            Err(e) => Err(e),
        }
    }

    /// Whether the last `L B Lᵀ` factorisation found its matrix positive definite, where it tells.
    fn lblt_positive_definite(&self) -> Option<bool> {
        match (&self.lblt, &self.symmetric) {
            (Some(lblt), Some(sym)) => lblt.positive_definite(sym),
            _ => None,
        }
    }

    fn factorise_llt(&mut self) -> Result<Factorisation, LinearSolveError> {
        match &mut self.two_domain {
            Some(split) => split.factorise(&self.values)?,
            None => {
                let sym = self.symmetric.as_mut().expect("symmetric analysis exists for this kind");
                sym.factorise_llt(&self.pattern, &self.values)?;
            }
        }
        Ok(Factorisation::Llt)
    }

    fn factorise_lblt(&mut self) -> Result<Factorisation, LinearSolveError> {
        self.ensure_symmetric()?;
        let sym = self.symmetric.as_mut().expect("symmetric analysis exists for this kind");
        let lblt = self.lblt.as_mut().expect("pivot buffers exist for this kind");
        lblt.factorise(sym, &self.pattern, &self.values)?;
        Ok(Factorisation::Lblt)
    }

    fn prepare_cg(&mut self) -> Factorisation {
        let cg = self.cg.get_or_insert_with(|| CgSolver::new(self.pattern.n()));
        cg.preconditioner.update(&self.pattern, &self.values);
        Factorisation::Cg
    }

    fn factorise_lu(&mut self) -> Result<Factorisation, LinearSolveError> {
        self.ensure_lu()?;
        let lu = self.lu.as_mut().expect("the LU factor was just built");
        lu.factorise(&self.values)?;
        Ok(Factorisation::Lu)
    }

    /// Solves `A x = rhs` in place with the current factorisation; fixed unknowns get exactly zero.
    /// Returns the factorisation that produced the solution: in `Auto` mode an inaccurate `L B Lᵀ`
    /// solution triggers an LU factorisation of the same values and a second solve.
    ///
    /// With [`LinearSolverKind::Cg`] it runs preconditioned conjugate gradients from zero to the relative
    /// tolerance `settings().cg.relative_tolerance` or the iteration cap, without a backward-error check;
    /// [`last_cg_report`](Self::last_cg_report) tells how it stopped.
    ///
    /// # Errors
    /// - [`LinearSolveError::NotFactorised`] without a successful [`factorise`](Self::factorise);
    /// - [`LinearSolveError::NonFiniteRhs`] naming the first NaN or infinite entry;
    /// - [`LinearSolveError::Singular`] if the solution is not finite;
    /// - [`LinearSolveError::Inaccurate`] if its backward error exceeds the bound;
    /// - [`LinearSolveError::CgBreakdown`] if the CG recursion overflows.
    ///
    /// # Panics
    /// If `rhs.len() != self.n()`.
    #[track_caller]
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<Factorisation, LinearSolveError> {
        let result = self.solve_rhs(rhs);
        self.clear_vector_state();
        result
    }

    /// [`solve_in_place`](Self::solve_in_place) without the clean-up of the vector registers.
    #[track_caller]
    fn solve_rhs(&mut self, rhs: &mut [f64]) -> Result<Factorisation, LinearSolveError> {
        assert_eq!(rhs.len(), self.n(), "right-hand side length differs from the dimension");
        let Some(current) = self.current else {
            return Err(LinearSolveError::NotFactorised);
        };
        if let Some(index) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(LinearSolveError::NonFiniteRhs {
                index,
                value: rhs[index],
            });
        }
        for (r, &f) in rhs.iter_mut().zip(&self.fixed) {
            if f {
                *r = 0.0;
            }
        }
        self.rhs_copy.copy_from_slice(rhs);
        self.last_cg = None;
        match self.solve_checked(current, rhs) {
            Err(LinearSolveError::Singular { .. } | LinearSolveError::Inaccurate { .. })
                if current == Factorisation::Lblt && self.settings.kind == LinearSolverKind::Auto =>
            {
                self.current = None;
                self.factorise_lu()?;
                self.current = Some(Factorisation::Lu);
                rhs.copy_from_slice(&self.rhs_copy);
                self.solve_checked(Factorisation::Lu, rhs)?;
                Ok(Factorisation::Lu)
            }
            Err(e) => Err(e),
            Ok(()) => Ok(current),
        }
    }

    /// Runs CG for `rhs_copy` into `rhs` and zeroes the fixed entries (which CG keeps at zero anyway:
    /// their rows and columns are those of the identity and their right-hand side is zero).
    fn solve_cg(&mut self, rhs: &mut [f64]) -> Result<(), LinearSolveError> {
        self.last_backward_error = None;
        let cap = self.settings.cg.iteration_cap(self.pattern.n());
        let tolerance = self.settings.cg.relative_tolerance;
        let cg = self.cg.as_mut().expect("the preconditioner exists after a CG factorise");
        let (pattern, tasks, values, b) = (&self.pattern, &mut self.column_tasks, &self.values, &self.rhs_copy);
        // The whole recursion runs on a pool thread: called from outside the pool, each product's
        // join would be a round trip through the kernel, and the caller's thread would compete for
        // the cores with the pool's threads waiting for the next product.
        let report = rayon::scope(|_| cg.solve(pattern, tasks, values, b, rhs, tolerance, cap))?;
        for (x, &f) in rhs.iter_mut().zip(&self.fixed) {
            if f {
                *x = 0.0;
            }
        }
        self.last_cg = Some(report);
        Ok(())
    }

    /// Solves with `factorisation`, zeroes the fixed entries and checks the solution against
    /// `rhs_copy` (CG: solves only, see [`solve_cg`](Self::solve_cg)).
    fn solve_checked(&mut self, factorisation: Factorisation, rhs: &mut [f64]) -> Result<(), LinearSolveError> {
        match factorisation {
            Factorisation::Cg => return self.solve_cg(rhs),
            Factorisation::Llt => match &mut self.two_domain {
                Some(split) => split.solve_in_place(rhs),
                None => self.symmetric.as_mut().expect("factorised").solve_llt_in_place(rhs),
            },
            Factorisation::Lblt => {
                let sym = self.symmetric.as_mut().expect("factorised");
                self.lblt.as_ref().expect("factorised").solve_in_place(sym, rhs);
            }
            Factorisation::Lu => self.lu.as_mut().expect("factorised").solve_in_place(rhs),
        }
        for (x, &f) in rhs.iter_mut().zip(&self.fixed) {
            if f {
                *x = 0.0;
            }
        }
        self.column_tasks
            .product_into(&self.pattern, &self.values, rhs, &mut self.product);
        let eta = backward_error(self.norm_a, &self.rhs_copy, rhs, &self.product);
        self.last_backward_error = Some(eta);
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearSolveError::Singular {
                factorisation,
                col: None,
            });
        }
        if eta > self.settings.max_backward_error {
            return Err(LinearSolveError::Inaccurate {
                factorisation,
                backward_error: eta,
                bound: self.settings.max_backward_error,
            });
        }
        Ok(())
    }
}

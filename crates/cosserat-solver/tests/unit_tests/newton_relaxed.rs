//! The relaxed steps of the mixed-integration-point Newton method: a full step that raises the energy
//! by a spurious stretch is taken when the next step removes it, and undone when a run of them does
//! not bring the energy below its start's.

use cosserat_solver::{IndefiniteHessian, NewtonProblem, NewtonSettings, ProblemError, Tolerance};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

use super::newton::solve;
use super::toy::{Scalar, pattern_of, slot};

/// A bar bent by a transverse force: `Π(u, w) = ½ k w² − f w + ½ K ε²` with the stretch
/// `ε = u + ½ w²`, the one-dimensional picture of a thin shell (bending stiffness `k`, membrane
/// stiffness `K ≫ k`). The minimiser is inextensional, `w = f/k`, `u = −½ w²`. From rest the Newton
/// step lifts the bar by `f/k` without the shortening `−½ w²`, a stretch whose energy `⅛ K w⁴` dwarfs
/// the bending's; the next step, with the predicted stretch (zero along the first step) in place of
/// the actual one in its matrix, shortens it to the minimiser.
struct StretchedBar {
    bending: f64,
    membrane: f64,
    force: f64,
    /// The stretch predicted along the steps, and its linearisation at the last iterate.
    predicted: Option<f64>,
    linearised: (f64, f64),
    pattern: SymbolicSparseColMat<usize>,
}

impl StretchedBar {
    fn new() -> Self {
        Self {
            bending: 1.0,
            membrane: 1e6,
            force: 1.0,
            predicted: None,
            linearised: (0.0, 0.0),
            pattern: pattern_of(2, [(0, 0), (0, 1), (1, 1)]),
        }
    }

    fn stretch(x: &[f64]) -> f64 {
        x[0] + 0.5 * x[1] * x[1]
    }
}

impl NewtonProblem for StretchedBar {
    fn n_dofs(&self) -> usize {
        2
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let e = Self::stretch(x);
        Ok(0.5 * self.bending * x[1] * x[1] - self.force * x[1] + 0.5 * self.membrane * e * e)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let stress = self.membrane * Self::stretch(x);
        g[0] = stress;
        g[1] = self.bending * x[1] - self.force + stress * x[1];
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        // `K ∇ε ∇εᵀ` plus the stress times `∇²ε` (1 in `ww`), the stress predicted where there is one.
        let stress = self.membrane * self.predicted.unwrap_or(Self::stretch(x));
        h[slot(&self.pattern, 0, 0)] = self.membrane;
        h[slot(&self.pattern, 0, 1)] = self.membrane * x[1];
        h[slot(&self.pattern, 1, 1)] = self.bending + self.membrane * x[1] * x[1] + stress;
        self.gradient(x, g)
    }
    fn predicts_strains(&self) -> bool {
        true
    }
    fn linearize_strains(&mut self, x: &[f64], dx: &[f64]) -> Result<(), ProblemError> {
        let at = self.predicted.unwrap_or(Self::stretch(x));
        self.linearised = (at, dx[0] + x[1] * dx[1]);
        Ok(())
    }
    fn advance_predicted_strains(&mut self, alpha: f64) {
        self.predicted = Some(self.linearised.0 + alpha * self.linearised.1);
    }
    fn clear_predicted_strains(&mut self) {
        self.predicted = None;
    }
}

fn settings(mixed: bool) -> NewtonSettings {
    NewtonSettings {
        tolerance: Tolerance::Absolute(1e-9),
        indefinite_hessian: IndefiniteHessian::Factorise,
        mixed_integration_points: mixed,
        ..NewtonSettings::default()
    }
}

/// With mixed integration points the bar reaches its minimiser in two iterations, the first step taken
/// in full although it raises the energy from 0 to 1.25e5; the line search of the plain method cuts
/// that step to a sliver and crawls along the inextensional path (over a hundred iterations).
#[test]
fn a_relaxed_step_crosses_the_stretch_that_the_line_search_crawls_along() {
    let mut x = [0.0, 0.0];
    let mixed = solve(&mut StretchedBar::new(), &mut x, settings(true)).unwrap();
    assert!((x[1] - 1.0).abs() < 1e-9 && (x[0] + 0.5).abs() < 1e-9, "{x:?}");
    assert!(mixed.relaxed_steps >= 1, "{mixed:?}");
    assert_eq!(mixed.undone_relaxed_steps, 0);
    assert!(mixed.iterations <= 3, "{} iterations", mixed.iterations);

    let mut x = [0.0, 0.0];
    let plain = NewtonSettings {
        max_iterations: 1000,
        ..settings(false)
    };
    let plain = solve(&mut StretchedBar::new(), &mut x, plain).unwrap();
    assert!((x[1] - 1.0).abs() < 1e-9 && (x[0] + 0.5).abs() < 1e-9, "{x:?}");
    assert_eq!(plain.relaxed_steps, 0);
    assert!(plain.line_search_backtracks > 0);
    assert!(
        plain.iterations >= 20 * mixed.iterations,
        "{} iterations without, {} with",
        plain.iterations,
        mixed.iterations
    );
}

/// `√(1 + x²)`, whose Newton steps leave ever farther (`x ← −x³`), under a problem that claims to
/// predict strains: from 1.5 the relaxed step reaches −3.375, where the energy is twice the start's,
/// and the next line search (two halvings allowed) finds no decrease. The run is undone, and the solve
/// reaches the minimum from 1.5 with line searches. A problem that predicts nothing takes no relaxed
/// step at all.
#[test]
fn a_relaxed_step_that_the_next_steps_do_not_recover_from_is_undone() {
    let root = || {
        Scalar::new(
            |x: f64| (1.0 + x * x).sqrt(),
            |x: f64| x / (1.0 + x * x).sqrt(),
            |x: f64| (1.0 + x * x).powf(-1.5),
        )
    };
    let short = NewtonSettings {
        max_line_search_iterations: 2,
        ..settings(true)
    };
    let mut x = [1.5];
    let report = solve(&mut Claims(root()), &mut x, short).unwrap();
    assert!(x[0].abs() < 1e-6, "{x:?}");
    assert_eq!(report.relaxed_steps, 1, "{report:?}");
    assert_eq!(report.undone_relaxed_steps, 1, "{report:?}");
    // Every iteration is counted, the undone and the failed one too; the start's residual takes the
    // place of the undone iterate's.
    assert_eq!(report.residuals.len(), report.iterations, "{report:?}");
    assert_eq!(report.residuals[1], report.residuals[0]);

    let mut x = [1.5];
    let report = solve(&mut root(), &mut x, short).unwrap();
    assert!(x[0].abs() < 1e-6);
    assert_eq!(report.relaxed_steps, 0);
    assert!(report.line_search_backtracks > 0);
}

/// A problem that claims to predict strains (and predicts nothing).
struct Claims<P>(P);

impl<P: NewtonProblem> NewtonProblem for Claims<P> {
    fn n_dofs(&self) -> usize {
        self.0.n_dofs()
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.0.hessian_pattern()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        self.0.value(x)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        self.0.gradient(x, g)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        self.0.hessian(x, g, h)
    }
    fn predicts_strains(&self) -> bool {
        true
    }
}

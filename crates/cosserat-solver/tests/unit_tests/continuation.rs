//! Arc-length continuation on a problem with a closed-form equilibrium path through two limit points
//! of the load and two of the displacement (snap-through and snap-back).

use cosserat_solver::{
    ArcLengthSettings, NewtonProblem, NewtonSettings, PathError, PathProblem, ProblemError, trace_path,
};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

use super::toy::{pattern_of, slot};

/// A shallow two-bar (von Mises) truss loaded through a soft spring: unknowns the apex's downward
/// displacement `w` and the loaded end's `v`,
///
/// `Π(w, v; λ) = k (L(w) − L₀)² + ½ k_s (v − w)² − λ P v`, `L(w) = √(a² + (h − w)²)`.
///
/// On the equilibrium path the spring carries the truss force, `λ P = k_s (v − w) = F(w)` with
/// `F(w) = 2k (L₀ − L)(h − w)/L`, so `λ(w) = F(w)/P` and `v(w) = w + F(w)/k_s`: `F` rises to a
/// maximum, falls through zero where the bars are flat (`w = h`) to a minimum and rises again
/// (snap-through), and where `F' < −k_s`, `v` decreases along the path (snap-back).
struct SpringTruss {
    a: f64,
    h: f64,
    k: f64,
    ks: f64,
    p: f64,
    lambda: f64,
    /// The committed equilibrium `(w, v)`.
    base: [f64; 2],
    pattern: SymbolicSparseColMat<usize>,
}

impl SpringTruss {
    fn new() -> Self {
        Self {
            a: 1.0,
            h: 0.5,
            k: 1.0,
            ks: 0.1,
            p: 1.0,
            lambda: 0.0,
            base: [0.0; 2],
            pattern: pattern_of(2, [(0, 0), (0, 1), (1, 1)]),
        }
    }

    fn rest_length(&self) -> f64 {
        (self.a * self.a + self.h * self.h).sqrt()
    }

    /// The truss force `F(w)` (downward load it carries).
    fn force(&self, w: f64) -> f64 {
        let l = (self.a * self.a + (self.h - w).powi(2)).sqrt();
        2.0 * self.k * (self.rest_length() - l) * (self.h - w) / l
    }
}

impl NewtonProblem for SpringTruss {
    fn n_dofs(&self) -> usize {
        2
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let (w, v) = (self.base[0] + x[0], self.base[1] + x[1]);
        let l = (self.a * self.a + (self.h - w).powi(2)).sqrt();
        Ok(self.k * (l - self.rest_length()).powi(2) + 0.5 * self.ks * (v - w).powi(2) - self.lambda * self.p * v)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let (w, v) = (self.base[0] + x[0], self.base[1] + x[1]);
        g[0] = self.force(w) - self.ks * (v - w);
        g[1] = self.ks * (v - w) - self.lambda * self.p;
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        let w = self.base[0] + x[0];
        let l = (self.a * self.a + (self.h - w).powi(2)).sqrt();
        let dl = -(self.h - w) / l;
        let d2l = self.a * self.a / l.powi(3);
        h[slot(&self.pattern, 0, 0)] = 2.0 * self.k * (dl * dl + (l - self.rest_length()) * d2l) + self.ks;
        h[slot(&self.pattern, 0, 1)] = -self.ks;
        h[slot(&self.pattern, 1, 1)] = self.ks;
        self.gradient(x, g)
    }
}

impl PathProblem for SpringTruss {
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError> {
        self.lambda = lambda;
        Ok(())
    }
    fn commit(&mut self, x: &[f64]) {
        self.base[0] += x[0];
        self.base[1] += x[1];
    }
}

#[test]
fn arc_length_follows_snap_through_and_snap_back_on_the_closed_form_path() {
    let mut truss = SpringTruss::new();
    // The extreme loads of the path, from the closed form on a fine grid of w.
    let grid: Vec<f64> = (0..=20_000).map(|i| 2.0 * truss.h * i as f64 / 20_000.0).collect();
    let f_max = grid.iter().map(|&w| truss.force(w)).fold(f64::NEG_INFINITY, f64::max);
    let f_min = grid.iter().map(|&w| truss.force(w)).fold(f64::INFINITY, f64::min);
    let settings = ArcLengthSettings {
        initial_increment: 0.05 * f_max / truss.p,
        end: 1.5 * f_max / truss.p,
        ..ArcLengthSettings::default()
    };
    let mut path = Vec::new();
    let points = trace_path(&mut truss, &settings, &mut |t, point| {
        path.push((t.base[0], t.base[1], point.load_factor));
    })
    .unwrap();
    assert_eq!(points.len(), path.len());
    let (w_end, _, l_end) = *path.last().unwrap();
    assert_eq!(l_end, settings.end);
    assert!(
        w_end > 2.0 * truss.h,
        "the path ends beyond the inverted truss's zero force: w = {w_end}"
    );
    // Every equilibrium lies on the closed-form path, to the corrector's tolerance (a millionth of the
    // load).
    for &(w, v, lambda) in &path {
        let f = truss.force(w);
        assert!(
            (lambda * truss.p - f).abs() < 1e-6 * f_max,
            "λ P = {} vs F(w) = {f}",
            lambda * truss.p
        );
        let v_exact = w + lambda * truss.p / truss.ks;
        assert!((v - v_exact).abs() < 1e-6 * f_max / truss.ks, "v = {v} vs {v_exact}");
    }
    // Followed continuously: w grows along the path (no jump to another branch), the load passes both
    // limit points (its sampled extremes lie within 2 % of the exact ones) and v decreases over a part
    // of the path (snap-back).
    assert!(
        path.windows(2).all(|p| p[1].0 > p[0].0),
        "w must increase along the path"
    );
    // The limit points: the largest load before the bars lie flat (w < h), the smallest before they
    // are unloaded again (w < 2h).
    let l_max = path
        .iter()
        .filter(|p| p.0 < truss.h)
        .map(|p| p.2)
        .fold(f64::NEG_INFINITY, f64::max);
    let l_min = path
        .iter()
        .filter(|p| p.0 < 2.0 * truss.h)
        .map(|p| p.2)
        .fold(f64::INFINITY, f64::min);
    assert!(
        l_max * truss.p > 0.98 * f_max && l_max * truss.p <= f_max * (1.0 + 1e-6),
        "{l_max}"
    );
    assert!(
        l_min * truss.p < 0.98 * f_min && l_min * truss.p >= f_min * (1.0 + 1e-6),
        "{l_min}"
    );
    assert!(path.windows(2).any(|p| p[1].1 < p[0].1), "no snap-back in v");
    let iterations: usize = points.iter().map(|p| p.iterations).sum();
    eprintln!(
        "spring truss: {} steps, {:.2} corrector iterations per step, λ from {l_min:.4} to {l_max:.4} (exact {:.4} to {:.4})",
        points.len(),
        iterations as f64 / points.len() as f64,
        f_min / truss.p,
        f_max / truss.p
    );
}

/// A first load increment so small that the squares of its displacements underflow (or fall among the
/// subnormal numbers) still sets a finite first arc length: the path goes on at finite load factors,
/// each equilibrium on the closed-form path, until the step limit.
#[test]
fn a_tiny_first_increment_keeps_finite_load_factors() {
    for initial_increment in [1e-300, 1e-160] {
        let mut truss = SpringTruss::new();
        let settings = ArcLengthSettings {
            initial_increment,
            max_steps: 3,
            ..ArcLengthSettings::default()
        };
        let mut path = Vec::new();
        let result = trace_path(&mut truss, &settings, &mut |t, point| {
            path.push((t.base[0], t.base[1], point.load_factor, point.arc_length));
        });
        match result {
            Err(PathError::TooManySteps {
                steps: 3, load_factor, ..
            }) => {
                assert!(load_factor.is_finite() && load_factor > 0.0, "λ = {load_factor:e}");
            }
            other => panic!("increment {initial_increment:e}: expected the step limit, got {other:?}"),
        }
        assert_eq!(path.len(), 3);
        for (k, &(w, v, lambda, arc)) in path.iter().enumerate() {
            assert!(arc > 0.0 && arc.is_finite(), "step {}: arc length {arc:e}", k + 1);
            assert!(lambda > 0.0 && lambda.is_finite(), "step {}: λ = {lambda:e}", k + 1);
            // The spring carries the load: λ P = k_s (v − w).
            let carried = truss.ks * (v - w);
            assert!(
                (carried - lambda * truss.p).abs() <= 1e-6 * lambda * truss.p,
                "step {}: λ P = {:e}, k_s (v − w) = {carried:e}",
                k + 1,
                lambda * truss.p
            );
        }
        assert!(path.windows(2).all(|p| p[1].2 > p[0].2), "λ must grow: {path:?}");
    }
}

/// A load that moves nothing gives the first step no arc length: the path stops with that reason
/// instead of scaling later predictors by `0/0`.
#[test]
fn a_first_increment_that_moves_nothing_is_refused() {
    let mut truss = SpringTruss::new();
    truss.p = 0.0;
    let settings = ArcLengthSettings::default();
    let result = trace_path(&mut truss, &settings, &mut |_, _| {});
    match result {
        Err(e @ PathError::NoFirstArc { initial_increment }) => {
            assert_eq!(initial_increment, settings.initial_increment);
            assert!(
                e.to_string().contains("first load increment 0.05 moves no unknown"),
                "{e}"
            );
        }
        other => panic!("expected NoFirstArc, got {other:?}"),
    }
}

/// A sheet pulled along a path: unknowns the stretch `s` and a turn `y`, increments from the committed
/// equilibrium,
///
/// `Π(s, y; λ) = ½ (s − λ a)² + ½ (c + σ − s) y² − λ b y`:
///
/// the stretch takes stiffness from the turn (a stretched sheet's membrane energy falls as its
/// directors turn), which the stabilisation `σ` gives back. Each step starts with `σ = 2 s` of its
/// committed stretch (a shell's factors hold twice the stress of the step's start); with `follows`,
/// [`NewtonProblem::follow_iterate`] raises it to `2 s` at an iterate that stretches beyond `c + σ`.
/// An equilibrium is stable where the Hessian `[[1, −y], [−y, c + σ − s]]` is positive definite.
struct PulledSheet {
    a: f64,
    c: f64,
    b: f64,
    lambda: f64,
    base: [f64; 2],
    sigma: f64,
    follows: bool,
    raised: usize,
    /// Whether each committed equilibrium is stable under the energy it was found with.
    stable: Vec<bool>,
    pattern: SymbolicSparseColMat<usize>,
}

impl PulledSheet {
    fn new(follows: bool) -> Self {
        Self {
            a: 1.0,
            c: 0.1,
            b: 0.01,
            lambda: 0.0,
            base: [0.0; 2],
            sigma: 0.0,
            follows,
            raised: 0,
            stable: Vec::new(),
            pattern: pattern_of(2, [(0, 0), (0, 1), (1, 1)]),
        }
    }

    /// The turn's stiffness at the stretch `s`.
    fn stiffness(&self, s: f64) -> f64 {
        self.c + self.sigma - s
    }

    /// The stabilisation a step from the committed state starts with.
    fn start_stabilisation(&self) -> f64 {
        2.0 * self.base[0].max(0.0)
    }
}

impl NewtonProblem for PulledSheet {
    fn n_dofs(&self) -> usize {
        2
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let (s, y) = (self.base[0] + x[0], self.base[1] + x[1]);
        let pull = self.lambda * self.a;
        Ok(0.5 * (s - pull).powi(2) + 0.5 * self.stiffness(s) * y * y - self.lambda * self.b * y)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let (s, y) = (self.base[0] + x[0], self.base[1] + x[1]);
        g[0] = s - self.lambda * self.a - 0.5 * y * y;
        g[1] = self.stiffness(s) * y - self.lambda * self.b;
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        let (s, y) = (self.base[0] + x[0], self.base[1] + x[1]);
        h[slot(&self.pattern, 0, 0)] = 1.0;
        h[slot(&self.pattern, 0, 1)] = -y;
        h[slot(&self.pattern, 1, 1)] = self.stiffness(s);
        self.gradient(x, g)
    }
    fn follow_iterate(&mut self, x: &[f64]) -> bool {
        let s = self.base[0] + x[0];
        if !self.follows || self.c + self.sigma >= s {
            return false;
        }
        self.sigma = 2.0 * s;
        self.raised += 1;
        true
    }
    fn abandon_solve(&mut self) {
        self.sigma = self.start_stabilisation();
    }
}

impl PathProblem for PulledSheet {
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError> {
        self.lambda = lambda;
        Ok(())
    }
    fn commit(&mut self, x: &[f64]) {
        self.base[0] += x[0];
        self.base[1] += x[1];
        let (s, y) = (self.base[0], self.base[1]);
        self.stable.push(self.stiffness(s) - y * y > 0.0);
        self.sigma = self.start_stabilisation();
    }
}

/// A sheet pulled taut within one step of the path: the corrector offers its predictor and iterates to
/// the problem, whose stabilisation follows them, and every equilibrium it reaches is stable; with the
/// stabilisation of each step's start the first step, from rest, ends at an unstable equilibrium (a
/// saddle, which the corrector, taking full Newton steps, converges to as readily). A failed corrector
/// puts the stabilisation back.
#[test]
fn the_corrector_lets_the_stabilisation_follow_a_sheet_pulled_taut() {
    let settings = ArcLengthSettings {
        initial_increment: 1.0,
        end: 2.0,
        ..ArcLengthSettings::default()
    };
    let trace = |follows: bool| {
        let mut sheet = PulledSheet::new(follows);
        let points = trace_path(&mut sheet, &settings, &mut |_, _| {});
        (sheet, points)
    };
    let (sheet, points) = trace(true);
    let points = points.unwrap();
    assert!(sheet.raised >= 1, "the stabilisation never followed");
    assert!(sheet.stable.iter().all(|s| *s), "{:?}", sheet.stable);
    assert_eq!(points.last().map(|p| p.load_factor), Some(settings.end));
    // On the path the stretch follows the pull (the turn is small): s = λ a + ½ y².
    assert!(
        (sheet.base[0] - settings.end * sheet.a).abs() < 1e-3,
        "{:?}",
        sheet.base
    );

    let (sheet, _) = trace(false);
    assert_eq!(
        sheet.stable.first(),
        Some(&false),
        "with the start's stabilisation the first step reached a stable state"
    );

    let mut failing = PulledSheet::new(true);
    let short = ArcLengthSettings {
        newton: NewtonSettings {
            max_iterations: 0,
            ..settings.newton
        },
        max_cuts: 0,
        ..settings
    };
    assert!(trace_path(&mut failing, &short, &mut |_, _| {}).is_err());
    assert!(failing.raised >= 1, "the failed corrector never followed");
    assert_eq!(failing.sigma, 0.0);
}

/// A spring under a load script with a kink: `Π(x; λ) = ½ k x² − f(λ) x` with `f = λ` up to `λ = ½` and
/// `½ + s (λ − ½)` beyond (a pull, then a small load once it is complete), so that past the kink the
/// equilibrium `x = f(λ) / k` moves `1/s` times more slowly with the load.
struct KinkedSpring {
    k: f64,
    s: f64,
    lambda: f64,
    base: f64,
    pattern: SymbolicSparseColMat<usize>,
}

impl KinkedSpring {
    fn load(&self, lambda: f64) -> f64 {
        if lambda <= 0.5 {
            lambda
        } else {
            0.5 + self.s * (lambda - 0.5)
        }
    }
}

impl NewtonProblem for KinkedSpring {
    fn n_dofs(&self) -> usize {
        1
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let u = self.base + x[0];
        Ok(0.5 * self.k * u * u - self.load(self.lambda) * u)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        g[0] = self.k * (self.base + x[0]) - self.load(self.lambda);
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        h[0] = self.k;
        self.gradient(x, g)
    }
}

impl PathProblem for KinkedSpring {
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError> {
        self.lambda = lambda;
        Ok(())
    }
    fn commit(&mut self, x: &[f64]) {
        self.base += x[0];
    }
}

/// Past the kink the corrector, given the load's derivative on the side it goes to (a central
/// difference at the kink would mix the two slopes), converges at once; and since the path is now flat
/// in the load, the step's arc length spans more load than is left: the step that passes the end lands
/// on it, and the path ends there at the closed-form equilibrium.
#[test]
fn a_path_past_a_kink_of_the_load_script_lands_on_its_end() {
    let mut spring = KinkedSpring {
        k: 2.0,
        s: 1e-3,
        lambda: 0.0,
        base: 0.0,
        pattern: pattern_of(1, [(0, 0)]),
    };
    let settings = ArcLengthSettings {
        initial_increment: 0.1,
        end: 1.0,
        ..ArcLengthSettings::default()
    };
    let mut path = Vec::new();
    let points = trace_path(&mut spring, &settings, &mut |spring, point| {
        path.push((point.load_factor, spring.base));
    })
    .unwrap();
    let (lambda, x) = *path.last().unwrap();
    assert_eq!(lambda, settings.end);
    assert!((x - spring.load(1.0) / spring.k).abs() < 1e-12, "x = {x}");
    for &(lambda, x) in &path {
        assert!(
            (x - spring.load(lambda) / spring.k).abs() < 1e-12,
            "λ = {lambda}: x = {x}"
        );
    }
    // Five steps to the kink, then one to the end; none cut, and the corrector past the kink converges
    // in one iteration on this linear problem.
    assert!(points.len() <= 7, "{} steps", points.len());
    assert!(points.iter().all(|p| p.cuts == 0 && p.iterations <= 1), "{points:?}");
}

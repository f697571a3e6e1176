//! Toy minimisation problems with closed-form derivatives and known minimisers, for Newton's method.

use cosserat_solver::{NewtonProblem, ProblemError};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

use super::fixtures::{PatternBuilder, UpperMatrix};

/// Slot of entry `(i, j)` (any order) in an upper-triangle pattern.
pub fn slot(pattern: &SymbolicSparseColMat<usize>, i: usize, j: usize) -> usize {
    let (r, c) = if i <= j { (i, j) } else { (j, i) };
    let p = pattern.as_ref();
    let start = p.col_ptr()[c];
    let rows = &p.row_idx()[start..p.col_ptr()[c + 1]];
    start + rows.iter().position(|&x| x == r).expect("entry in pattern")
}

/// The pattern of `entries` (upper or lower, duplicates allowed) with zero values.
pub fn pattern_of(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> SymbolicSparseColMat<usize> {
    let mut b = PatternBuilder::new(n);
    for (i, j) in entries {
        b.add(i, j, 0.0);
    }
    b.build().pattern
}

/// `Π(x) = ½ xᵀ A x − bᵀ x` with `A` symmetric positive definite.
pub struct Quadratic {
    pub a: UpperMatrix,
    pub b: Vec<f64>,
}

impl Quadratic {
    fn product(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for (&v, (i, j)) in self.a.values.iter().zip(self.a.entries()) {
            y[i] += v * x[j];
            if i != j {
                y[j] += v * x[i];
            }
        }
        y
    }
}

impl NewtonProblem for Quadratic {
    fn n_dofs(&self) -> usize {
        self.a.n()
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.a.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let ax = self.product(x);
        Ok(x.iter()
            .zip(&ax)
            .zip(&self.b)
            .map(|((xi, ai), bi)| 0.5 * xi * ai - bi * xi)
            .sum())
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let ax = self.product(x);
        for i in 0..x.len() {
            g[i] = ax[i] - self.b[i];
        }
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        h.copy_from_slice(&self.a.values);
        self.gradient(x, g)
    }
}

/// The chained Rosenbrock function `Σ_{i<n−1} 100 (x_{i+1} − x_i²)² + (1 − x_i)²` with its
/// tridiagonal Hessian; `n = 2` is the classic Rosenbrock function. Minimiser: all ones.
pub struct Rosenbrock {
    pub n: usize,
    pub pattern: SymbolicSparseColMat<usize>,
}

impl Rosenbrock {
    pub fn new(n: usize) -> Self {
        let pattern = pattern_of(n, (0..n).map(|i| (i, i)).chain((1..n).map(|i| (i - 1, i))));
        Self { n, pattern }
    }
}

impl NewtonProblem for Rosenbrock {
    fn n_dofs(&self) -> usize {
        self.n
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        Ok((0..self.n - 1)
            .map(|i| 100.0 * (x[i + 1] - x[i] * x[i]).powi(2) + (1.0 - x[i]).powi(2))
            .sum())
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        for i in 0..self.n - 1 {
            let a = x[i + 1] - x[i] * x[i];
            g[i] += -400.0 * x[i] * a - 2.0 * (1.0 - x[i]);
            g[i + 1] += 200.0 * a;
        }
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        for i in 0..self.n - 1 {
            h[slot(&self.pattern, i, i)] += 1200.0 * x[i] * x[i] - 400.0 * x[i + 1] + 2.0;
            h[slot(&self.pattern, i, i + 1)] += -400.0 * x[i];
            h[slot(&self.pattern, i + 1, i + 1)] += 200.0;
        }
        self.gradient(x, g)
    }
}

/// A chain of `n_nodes` points in 3D joined by linear springs `½ k_i (|x_{i+1} − x_i| − l_i)²`, the
/// first and last points fixed (walls). Unknowns: all positions, `3 n_nodes`.
pub struct SpringChain {
    pub n_nodes: usize,
    pub stiffness: Vec<f64>,
    pub rest_length: Vec<f64>,
    pub pattern: SymbolicSparseColMat<usize>,
    pub fixed: Vec<bool>,
}

impl SpringChain {
    pub fn new(stiffness: Vec<f64>, rest_length: Vec<f64>) -> Self {
        let n_nodes = stiffness.len() + 1;
        let mut entries = Vec::new();
        for node in 0..n_nodes {
            for a in 0..3 {
                for b in 0..3 {
                    entries.push((3 * node + a, 3 * node + b));
                    if node + 1 < n_nodes {
                        entries.push((3 * node + a, 3 * (node + 1) + b));
                    }
                }
            }
        }
        let pattern = pattern_of(3 * n_nodes, entries);
        let fixed = (0..3 * n_nodes).map(|i| i < 3 || i >= 3 * (n_nodes - 1)).collect();
        Self {
            n_nodes,
            stiffness,
            rest_length,
            pattern,
            fixed,
        }
    }

    fn spring(&self, x: &[f64], i: usize) -> ([f64; 3], f64) {
        let e = [0, 1, 2].map(|d| x[3 * (i + 1) + d] - x[3 * i + d]);
        let r = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        (e, r)
    }
}

impl NewtonProblem for SpringChain {
    fn n_dofs(&self) -> usize {
        3 * self.n_nodes
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn fixed_dofs(&self) -> Option<&[bool]> {
        Some(&self.fixed)
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let mut e = 0.0;
        for i in 0..self.n_nodes - 1 {
            let (_, r) = self.spring(x, i);
            e += 0.5 * self.stiffness[i] * (r - self.rest_length[i]).powi(2);
        }
        Ok(e)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        for i in 0..self.n_nodes - 1 {
            let (e, r) = self.spring(x, i);
            if r == 0.0 {
                return Err(ProblemError::InvalidState {
                    reason: format!("spring {i} has zero length"),
                });
            }
            let f = self.stiffness[i] * (r - self.rest_length[i]) / r;
            for d in 0..3 {
                g[3 * (i + 1) + d] += f * e[d];
                g[3 * i + d] -= f * e[d];
            }
        }
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        for i in 0..self.n_nodes - 1 {
            let (e, r) = self.spring(x, i);
            if r == 0.0 {
                return Err(ProblemError::InvalidState {
                    reason: format!("spring {i} has zero length"),
                });
            }
            let u = e.map(|v| v / r);
            let (k, l) = (self.stiffness[i], self.rest_length[i]);
            // K = k [u uᵀ + (1 − l/r)(I − u uᵀ)].
            let block = |a: usize, b: usize| {
                let uu = u[a] * u[b];
                let id = if a == b { 1.0 } else { 0.0 };
                k * (uu + (1.0 - l / r) * (id - uu))
            };
            let (p, q) = (3 * i, 3 * (i + 1));
            for a in 0..3 {
                for b in 0..3 {
                    let kab = block(a, b);
                    if a <= b {
                        h[slot(&self.pattern, p + a, p + b)] += kab;
                        h[slot(&self.pattern, q + a, q + b)] += kab;
                    }
                    h[slot(&self.pattern, p + a, q + b)] -= kab;
                }
            }
        }
        self.gradient(x, g)
    }
}

/// A one-unknown problem given by closures for `Π`, `Π'` and `Π''`, with states `x < lower`
/// reported invalid and an optional cap on the step fraction.
pub struct Scalar<F, G, H> {
    pub f: F,
    pub df: G,
    pub d2f: H,
    pub lower: f64,
    pub max_fraction: f64,
    pub pattern: SymbolicSparseColMat<usize>,
}

impl<F, G, H> Scalar<F, G, H>
where
    F: Fn(f64) -> f64,
    G: Fn(f64) -> f64,
    H: Fn(f64) -> f64,
{
    pub fn new(f: F, df: G, d2f: H) -> Self {
        Self {
            f,
            df,
            d2f,
            lower: f64::NEG_INFINITY,
            max_fraction: 1.0,
            pattern: pattern_of(1, [(0, 0)]),
        }
    }

    fn check(&self, x: f64) -> Result<(), ProblemError> {
        if x < self.lower {
            Err(ProblemError::InvalidState {
                reason: format!("x = {x} below {}", self.lower),
            })
        } else {
            Ok(())
        }
    }
}

impl<F, G, H> NewtonProblem for Scalar<F, G, H>
where
    F: Fn(f64) -> f64,
    G: Fn(f64) -> f64,
    H: Fn(f64) -> f64,
{
    fn n_dofs(&self) -> usize {
        1
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        self.check(x[0])?;
        Ok((self.f)(x[0]))
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        self.check(x[0])?;
        g[0] = (self.df)(x[0]);
        Ok((self.f)(x[0]))
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        self.check(x[0])?;
        h[0] = (self.d2f)(x[0]);
        self.gradient(x, g)
    }
    fn max_step_fraction(&mut self, _x: &[f64], _dx: &[f64]) -> f64 {
        self.max_fraction
    }
}

/// An angle reached by a Cayley-type update of one unknown, `φ = φ₀ + 2 arctan(t/2)`, with the energy
/// `½ (φ − φ*)²`: from `φ₀` the update turns less than a half turn, and its derivative vanishes as it
/// approaches one. With `rebases`, [`NewtonProblem::rebase`] moves `φ₀` to the angle reached and `t` to
/// zero once `|t| > 2` (a quarter turn), as the shells' rotation updates do.
pub struct HalfTurn {
    pub base: f64,
    pub target: f64,
    pub rebases: bool,
    /// The base at the start of the solve, restored by [`NewtonProblem::abandon_solve`].
    pub start: f64,
    pub rebased: usize,
    pub pattern: SymbolicSparseColMat<usize>,
}

impl HalfTurn {
    pub fn new(target: f64, rebases: bool) -> Self {
        Self {
            base: 0.0,
            target,
            rebases,
            start: 0.0,
            rebased: 0,
            pattern: pattern_of(1, [(0, 0)]),
        }
    }

    /// The angle and its first two derivatives in `t`.
    fn angle(&self, t: f64) -> (f64, f64, f64) {
        let s = 1.0 + 0.25 * t * t;
        (self.base + 2.0 * (0.5 * t).atan(), 1.0 / s, -0.5 * t / (s * s))
    }
}

impl NewtonProblem for HalfTurn {
    fn n_dofs(&self) -> usize {
        1
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let (phi, _, _) = self.angle(x[0]);
        Ok(0.5 * (phi - self.target).powi(2))
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let (phi, d, _) = self.angle(x[0]);
        g[0] = (phi - self.target) * d;
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        let (phi, d, d2) = self.angle(x[0]);
        h[0] = d * d + (phi - self.target) * d2;
        self.gradient(x, g)
    }
    fn rebase(&mut self, x: &mut [f64]) -> bool {
        if !self.rebases || x[0].abs() <= 2.0 {
            return false;
        }
        self.base = self.angle(x[0]).0;
        x[0] = 0.0;
        self.rebased += 1;
        true
    }
    fn abandon_solve(&mut self) {
        self.base = self.start;
    }
}

/// A sheet's stretch `x` under the pull `a` and a turn `y` of its directors under the small load `b`,
/// `Π = ½ (x − a)² + ½ (c + s − x) y² − b y`: the stretch takes stiffness `x` from the turn (a stretched
/// sheet's membrane energy falls as its directors turn), which the stabilisation `s` gives back. With
/// `follows`, [`NewtonProblem::follow_iterate`] raises `s` to `2 x` at an accepted iterate whose stretch
/// exceeds what `c + s` holds, as a shell's stabilisation follows the tension; with `s = 0` throughout
/// the energy is unbounded below once `x > c`.
pub struct Taut {
    pub pull: f64,
    pub floor: f64,
    pub load: f64,
    pub stabilisation: f64,
    pub follows: bool,
    pub raised: usize,
    pub pattern: SymbolicSparseColMat<usize>,
}

impl Taut {
    pub fn new(follows: bool) -> Self {
        Self {
            pull: 1.0,
            floor: 0.1,
            load: 0.01,
            stabilisation: 0.0,
            follows,
            raised: 0,
            pattern: pattern_of(2, [(0, 0), (0, 1), (1, 1)]),
        }
    }

    /// The turn's stiffness at the stretch `x`.
    fn stiffness(&self, x: f64) -> f64 {
        self.floor + self.stabilisation - x
    }
}

impl NewtonProblem for Taut {
    fn n_dofs(&self) -> usize {
        2
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let (s, y) = (x[0], x[1]);
        Ok(0.5 * (s - self.pull).powi(2) + 0.5 * self.stiffness(s) * y * y - self.load * y)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let (s, y) = (x[0], x[1]);
        g[0] = s - self.pull - 0.5 * y * y;
        g[1] = self.stiffness(s) * y - self.load;
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        let (s, y) = (x[0], x[1]);
        // Upper triangle, column by column: (0, 0), (0, 1), (1, 1).
        h[0] = 1.0;
        h[1] = -y;
        h[2] = self.stiffness(s);
        self.gradient(x, g)
    }
    fn follow_iterate(&mut self, x: &[f64]) -> bool {
        if !self.follows || self.floor + self.stabilisation >= x[0] {
            return false;
        }
        self.stabilisation = 2.0 * x[0];
        self.raised += 1;
        true
    }
    fn abandon_solve(&mut self) {
        self.stabilisation = 0.0;
    }
}

//! Boundary conditions as penalty energies (model.md §6), and prescribed positions by elimination.
//!
//! Targets are absolute end-of-step values set by scripts before each step: positions in world
//! coordinates, rotations relative to the rest pose in world axes.

use crate::error::AssemblyError;
use crate::inertia::{add_diagonal, add3};
use crate::pattern::SparsityPattern;
use crate::scatter::add_diagonal_block;
use crate::term::{Evaluation, PotentialTerm, finite};
use nalgebra::{Matrix3, Vector3};

/// `½ k Σ_active (x_{i,j} − x̄_{i,j})²` on a set of displacement nodes, with `x = xⁿ + Δt v`.
#[derive(Debug, Clone, PartialEq)]
pub struct PositionPenalty {
    /// A name for summaries (the scene's BC name).
    pub label: String,
    /// Global displacement-node indices.
    pub nodes: Vec<usize>,
    /// End-of-step target per node \[m\].
    pub targets: Vec<Vector3<f64>>,
    /// Which world axes are constrained.
    pub active: [bool; 3],
    /// Penalty stiffness `k` \[N/m\].
    pub stiffness: f64,
}

impl DiagonalPenalty for PositionPenalty {
    fn term_name(&self) -> String {
        format!("position_penalty[{}]", self.label)
    }

    fn evaluate(
        &self,
        eval: &Evaluation<'_>,
        sink: &mut dyn FnMut(usize, Vector3<f64>, [f64; 3]),
    ) -> Result<f64, AssemblyError> {
        let (k, dt) = (self.stiffness, eval.dt);
        let mask = Vector3::from_fn(|c, _| if self.active[c] { 1.0 } else { 0.0 });
        let mut total = 0.0;
        for (n, &i) in self.nodes.iter().enumerate() {
            let d = (eval.state.x[i] + eval.layout.velocity(eval.u, i) * dt - self.targets[n]).component_mul(&mask);
            total += finite(0.5 * k * d.norm_squared(), &|| self.term_name(), "node", i)?;
            sink(
                eval.layout.disp_block(i),
                d * (k * dt),
                [mask.x * k * dt * dt, mask.y * k * dt * dt, mask.z * k * dt * dt],
            );
        }
        Ok(total)
    }
}

/// `½ k Σ_{j active} |R e_j − R̄ e_j|²` on a set of rotation nodes: a penalty on the selected directors
/// (columns), with `R = R(Φ(qⁿ, ω, Δt))`.
#[derive(Debug, Clone, PartialEq)]
pub struct RotationPenalty {
    /// A name for summaries.
    pub label: String,
    /// Global rotation-node indices.
    pub nodes: Vec<usize>,
    /// Target rotation per node (relative to the rest pose, world axes).
    pub targets: Vec<Matrix3<f64>>,
    /// Which directors (columns) are constrained; `[false, false, true]` is the paper's "d3 clamp".
    pub columns: [bool; 3],
    /// Penalty stiffness `k` \[N·m\].
    pub stiffness: f64,
}

impl PotentialTerm for RotationPenalty {
    fn name(&self) -> String {
        format!("rotation_penalty[{}]", self.label)
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        for (n, &k) in self.nodes.iter().enumerate() {
            let r = eval.rotations.matrix(k);
            let mut e = 0.0;
            for j in (0..3).filter(|&j| self.columns[j]) {
                e += (r.column(j) - self.targets[n].column(j)).norm_squared();
            }
            total += finite(0.5 * self.stiffness * e, &|| self.name(), "rotation node", k)?;
        }
        Ok(total)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        for (n, &k) in self.nodes.iter().enumerate() {
            let (e, g, _) = self.node(eval, n, k, false);
            total += finite(e, &|| self.name(), "rotation node", k)?;
            add3(grad, eval.layout.rot_block(k), &g);
        }
        Ok(total)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        for (n, &k) in self.nodes.iter().enumerate() {
            let (e, g, h) = self.node(eval, n, k, true);
            total += finite(e, &|| self.name(), "rotation node", k)?;
            let b = eval.layout.rot_block(k);
            add3(grad, b, &g);
            add_diagonal_block(pattern, values, b, &h);
        }
        Ok(total)
    }
}

impl RotationPenalty {
    fn node(&self, eval: &Evaluation<'_>, n: usize, k: usize, with_hessian: bool) -> (f64, Vector3<f64>, Matrix3<f64>) {
        let jet = eval.rotations.jet(k);
        let s = self.stiffness;
        let (mut e, mut g, mut h) = (0.0, Vector3::zeros(), Matrix3::zeros());
        // The penalised columns' misfits, zero elsewhere: `Σ_j d_j · ∂²R_j/∂ω_a∂ω_b = ⟨∂²R/∂ω_a∂ω_b, D⟩`.
        let mut misfit = Matrix3::zeros();
        for j in (0..3).filter(|&j| self.columns[j]) {
            let d = jet.r.column(j) - self.targets[n].column(j);
            e += 0.5 * s * d.norm_squared();
            for a in 0..3 {
                g[a] += s * d.dot(&jet.d1[a].column(j));
                if with_hessian {
                    for b in 0..3 {
                        h[(a, b)] += s * jet.d1[a].column(j).dot(&jet.d1[b].column(j));
                    }
                }
            }
            misfit.set_column(j, &d);
        }
        if with_hessian {
            let second = jet.second_contraction(&misfit);
            h += Matrix3::from_fn(|a, b| s * second[a][b]);
        }
        (e, g, h)
    }
}

/// `½ k Σ_active (ω_{k,j} − ω̄_j)²` on a set of rotation nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct AngularVelocityPenalty {
    /// A name for summaries.
    pub label: String,
    /// Global rotation-node indices.
    pub nodes: Vec<usize>,
    /// Target angular velocity \[rad/s\], the same for all nodes.
    pub target: Vector3<f64>,
    /// Which world components are constrained.
    pub active: [bool; 3],
    /// Penalty stiffness `k`.
    pub stiffness: f64,
}

impl DiagonalPenalty for AngularVelocityPenalty {
    fn term_name(&self) -> String {
        format!("angular_velocity_penalty[{}]", self.label)
    }

    fn evaluate(
        &self,
        eval: &Evaluation<'_>,
        sink: &mut dyn FnMut(usize, Vector3<f64>, [f64; 3]),
    ) -> Result<f64, AssemblyError> {
        let mask = Vector3::from_fn(|c, _| if self.active[c] { 1.0 } else { 0.0 });
        let mut total = 0.0;
        for &k in &self.nodes {
            let d = (eval.layout.omega(eval.u, k) - self.target).component_mul(&mask);
            total += finite(
                0.5 * self.stiffness * d.norm_squared(),
                &|| self.term_name(),
                "rotation node",
                k,
            )?;
            sink(
                eval.layout.rot_block(k),
                d * self.stiffness,
                [
                    mask.x * self.stiffness,
                    mask.y * self.stiffness,
                    mask.z * self.stiffness,
                ],
            );
        }
        Ok(total)
    }
}

/// A penalty whose Hessian is diagonal: per node it reports its block of unknowns, its gradient there
/// and the diagonal of its Hessian, from which the [`PotentialTerm`] methods follow.
trait DiagonalPenalty: Send + Sync + 'static {
    /// The term's name in summaries and errors.
    fn term_name(&self) -> String;

    /// The energy, with each node's block, gradient and Hessian diagonal passed to `sink`.
    fn evaluate(
        &self,
        eval: &Evaluation<'_>,
        sink: &mut dyn FnMut(usize, Vector3<f64>, [f64; 3]),
    ) -> Result<f64, AssemblyError>;
}

impl<P: DiagonalPenalty> PotentialTerm for P {
    fn name(&self) -> String {
        self.term_name()
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        self.evaluate(eval, &mut |_, _, _| {})
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        self.evaluate(eval, &mut |b, g, _| add3(grad, b, &g))
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        self.evaluate(eval, &mut |b, g, h| {
            add3(grad, b, &g);
            add_diagonal(pattern, values, b, h);
        })
    }
}

/// Prescribed positions enforced exactly: the velocity unknowns of the active axes are eliminated and
/// set to `(x̄ − xⁿ)/Δt`.
#[derive(Debug, Clone, PartialEq)]
pub struct PositionConstraint {
    /// A name for summaries.
    pub label: String,
    /// Global displacement-node indices.
    pub nodes: Vec<usize>,
    /// End-of-step target per node \[m\].
    pub targets: Vec<Vector3<f64>>,
    /// Which world axes are prescribed.
    pub active: [bool; 3],
}

//! Inertia and external loads in the velocity form of backward Euler (model.md §5.2).
//!
//! With end-of-step velocities `v` as unknowns and `x = xⁿ + Δt v`, stationarity of
//! `½ m |v − vⁿ|² + Δt (…)` gives `m (v − vⁿ)/Δt = f − m d v − ∂Ψ/∂x`: backward Euler with
//! mass-proportional damping. The elastic energy is not scaled by `Δt²`; instead loads enter as work
//! over the step, `−Δt f · v`.

use crate::error::AssemblyError;
use crate::pattern::SparsityPattern;
use crate::term::{Evaluation, PotentialTerm, finite};
use nalgebra::{Matrix3, Vector3};

/// Lumped translational and isotropic rotational inertia, with translational damping.
#[derive(Debug, Clone, PartialEq)]
pub struct InertiaTerm {
    /// Lumped mass per displacement node \[kg\].
    pub masses: Vec<f64>,
    /// Rotational inertia per rotation node \[kg·m²\] (`ρ_θ h A_k`; zero in the paper's scenes).
    pub rotational_inertia: Vec<f64>,
    /// Mass-proportional damping coefficient `d` \[1/s\] on translations, per displacement node.
    pub damping: Vec<f64>,
}

impl InertiaTerm {
    fn node_energy(&self, eval: &Evaluation<'_>, i: usize) -> (f64, Vector3<f64>, f64) {
        let m = self.masses[i];
        let v = eval.layout.velocity(eval.u, i);
        let dv = v - eval.state.v[i];
        let c = m * self.damping[i] * eval.dt;
        (
            0.5 * m * dv.norm_squared() + 0.5 * c * v.norm_squared(),
            dv * m + v * c,
            m + c,
        )
    }

    fn rot_energy(&self, eval: &Evaluation<'_>, k: usize) -> (f64, Vector3<f64>, f64) {
        let inertia = self.rotational_inertia[k];
        let dw = eval.layout.omega(eval.u, k) - eval.state.omega[k];
        (0.5 * inertia * dw.norm_squared(), dw * inertia, inertia)
    }

    fn evaluate(
        &self,
        eval: &Evaluation<'_>,
        mut sink: impl FnMut(usize, Vector3<f64>, f64),
    ) -> Result<f64, AssemblyError> {
        let name = || self.name();
        let mut total = 0.0;
        for i in 0..self.masses.len() {
            let (e, g, h) = self.node_energy(eval, i);
            total += finite(e, &name, "node", i)?;
            sink(eval.layout.disp_block(i), g, h);
        }
        for k in 0..self.rotational_inertia.len() {
            if self.rotational_inertia[k] != 0.0 {
                let (e, g, h) = self.rot_energy(eval, k);
                total += finite(e, &name, "rotation node", k)?;
                sink(eval.layout.rot_block(k), g, h);
            }
        }
        Ok(total)
    }
}

impl PotentialTerm for InertiaTerm {
    fn name(&self) -> String {
        "inertia".into()
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        self.evaluate(eval, |_, _, _| {})
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        self.evaluate(eval, |b, g, _| add3(grad, b, &g))
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        self.evaluate(eval, |b, g, h| {
            add3(grad, b, &g);
            add_diagonal(pattern, values, b, [h; 3]);
        })
    }
}

/// Gravity, nodal forces and nodal torques, as work over the step.
///
/// Forces do the work `f · Δt v`. A torque `τ` does the work `τ · ψ`, where `ψ` is the rotation vector of
/// the step's nodal rotation increment `cay(Δt ω)` (angle `2 arctan(Δt|ω|/2)` about `ω`): for a torque
/// about a fixed axis this is exactly the moment times the turned angle, so large quasi-static
/// rotations (a strip rolled up by an end moment) see the applied moment and not a step-size-dependent
/// approximation of it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadTerm {
    /// Mass per displacement node for gravity \[kg\].
    pub masses: Vec<f64>,
    /// Gravitational acceleration \[m/s²\].
    pub gravity: Vector3<f64>,
    /// External force per displacement node \[N\] (constant over a step; set by scripts).
    pub forces: Vec<Vector3<f64>>,
    /// External torque per rotation node \[N·m\].
    pub torques: Vec<Vector3<f64>>,
}

/// The rotation vector of the Cayley rotation `cay(v)`: `2 arctan(|v|/2) v/|v|`.
fn cayley_rotation_vector<T: cosserat_geometry::Real>(v: &Vector3<T>) -> Vector3<T> {
    let n2 = v.norm_squared();
    if n2.re() < 1e-12 {
        // 2 arctan(s/2)/s = 1 − s²/12 + s⁴/80 − …
        v * (T::one() - n2 / 12.0 + n2 * n2 / 80.0)
    } else {
        let n = n2.sqrt();
        v * ((n * 0.5).atan() * 2.0 / n)
    }
}

/// Value, gradient and Hessian of `−τ · ψ(Δt ω)` with respect to `ω`.
fn torque_work(tau: &Vector3<f64>, omega: &Vector3<f64>, dt: f64) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let (v, g, h) = num_dual::hessian(
        |w: nalgebra::SVector<num_dual::Dual2SVec64<3>, 3>| {
            let psi = cayley_rotation_vector(&Vector3::new(w[0] * dt, w[1] * dt, w[2] * dt));
            -(psi.x * tau.x + psi.y * tau.y + psi.z * tau.z)
        },
        omega,
    );
    (v, g, h)
}

impl LoadTerm {
    /// Whether the term contributes anything.
    pub fn is_active(&self) -> bool {
        self.gravity != Vector3::zeros()
            || self.forces.iter().any(|f| *f != Vector3::zeros())
            || self.torques.iter().any(|t| *t != Vector3::zeros())
    }

    fn evaluate(&self, eval: &Evaluation<'_>, mut sink: impl FnMut(usize, Vector3<f64>, Option<Matrix3<f64>>)) -> f64 {
        let mut total = 0.0;
        for i in 0..self.forces.len() {
            let f = (self.forces[i] + self.gravity * self.masses[i]) * eval.dt;
            total -= f.dot(&eval.layout.velocity(eval.u, i));
            sink(eval.layout.disp_block(i), -f, None);
        }
        for k in 0..self.torques.len() {
            if self.torques[k] != Vector3::zeros() {
                let (v, g, h) = torque_work(&self.torques[k], &eval.layout.omega(eval.u, k), eval.dt);
                total += v;
                sink(eval.layout.rot_block(k), g, Some(h));
            }
        }
        total
    }
}

impl PotentialTerm for LoadTerm {
    fn name(&self) -> String {
        "external_loads".into()
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        let v = self.evaluate(eval, |_, _, _| {});
        finite(v, &|| self.name(), "term", 0)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        let v = self.evaluate(eval, |b, g, _| add3(grad, b, &g));
        finite(v, &|| self.name(), "term", 0)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let v = self.evaluate(eval, |b, g, h| {
            add3(grad, b, &g);
            if let Some(h) = h {
                crate::scatter::add_diagonal_block(pattern, values, b, &h);
            }
        });
        finite(v, &|| self.name(), "term", 0)
    }
}

#[inline]
pub(crate) fn add3(grad: &mut [f64], block: usize, g: &Vector3<f64>) {
    for c in 0..3 {
        grad[3 * block + c] += g[c];
    }
}

#[inline]
pub(crate) fn add_diagonal(pattern: &SparsityPattern, values: &mut [f64], block: usize, d: [f64; 3]) {
    for (c, dc) in d.into_iter().enumerate() {
        let j = 3 * block + c;
        // The diagonal entry is the last one of its column in the upper triangle.
        let end = pattern.col_start(j + 1);
        values[end - 1] += dc;
    }
}

/// Lumped masses: each element's rest area split equally over its `n` displacement nodes.
pub fn lumped_masses(
    n_nodes: usize,
    elements: impl IntoIterator<Item = (Vec<usize>, f64)>,
    areal_density: f64,
) -> Vec<f64> {
    let mut m = vec![0.0; n_nodes];
    for (nodes, area) in elements {
        let share = areal_density * area / nodes.len() as f64;
        for i in nodes {
            m[i] += share;
        }
    }
    m
}

//! Dynamic terms (contact-like couplings that change between steps) assemble into their own pattern,
//! merged with the fixed one; the fixed pattern and element scatters stay untouched.

use super::common::{dense_hessian, strip};
use cosserat_assembly::term::Evaluation;
use cosserat_assembly::{AssemblyError, DofLayout, ElementPair, PotentialTerm, SparsityPattern, SystemState};
use cosserat_material::ShellModel;

/// Springs between node pairs chosen at the start of each step: `½ k |x_a − x_b|²`.
struct Springs {
    pairs: Vec<[usize; 2]>,
    next: Vec<Vec<[usize; 2]>>,
    k: f64,
}

impl Springs {
    fn energy(&self, eval: &Evaluation<'_>, mut sink: impl FnMut([usize; 2], nalgebra::Vector3<f64>, f64)) -> f64 {
        let mut e = 0.0;
        for &[a, b] in &self.pairs {
            let xa = eval.state.x[a] + eval.layout.velocity(eval.u, a) * eval.dt;
            let xb = eval.state.x[b] + eval.layout.velocity(eval.u, b) * eval.dt;
            let d = xa - xb;
            e += 0.5 * self.k * d.norm_squared();
            sink([a, b], d * (self.k * eval.dt), self.k * eval.dt * eval.dt);
        }
        e
    }
}

impl PotentialTerm for Springs {
    fn name(&self) -> String {
        "springs".into()
    }
    fn is_dynamic(&self) -> bool {
        true
    }
    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        self.pairs.iter().map(|p| p.to_vec()).collect()
    }
    fn begin_step(&mut self, _: &SystemState, _: &DofLayout, _: f64, _: &[f64]) -> Result<bool, AssemblyError> {
        Ok(match self.next.pop() {
            Some(p) => {
                let grew = p.iter().any(|q| !self.pairs.contains(q));
                self.pairs = p;
                grew
            }
            None => false,
        })
    }
    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        Ok(self.energy(eval, |_, _, _| {}))
    }
    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        Ok(self.energy(eval, |[a, b], g, _| {
            for c in 0..3 {
                grad[3 * a + c] += g[c];
                grad[3 * b + c] -= g[c];
            }
        }))
    }
    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        Ok(self.energy(eval, |[a, b], g, h| {
            for c in 0..3 {
                grad[3 * a + c] += g[c];
                grad[3 * b + c] -= g[c];
                let (ia, ib) = (3 * a + c, 3 * b + c);
                values[pattern.entry(ia, ia).unwrap()] += h;
                values[pattern.entry(ib, ib).unwrap()] += h;
                let (i, j) = if ia < ib { (ia, ib) } else { (ib, ia) };
                values[pattern.entry(i, j).unwrap()] -= h;
            }
        }))
    }
}

#[test]
fn dynamic_couplings_are_merged_and_the_pattern_grows_only_when_needed() {
    let mut sys = strip(ElementPair::Tri3Tri3, 6, 1, ShellModel::Plate, true);
    let n_nodes = sys.potential.parts.layout.n_disp_nodes;
    let (far_a, far_b) = (0, n_nodes - 1);
    let fixed_nnz = sys.potential.pattern().nnz();
    // Insert the dynamic term; it starts without pairs.
    assert!(!sys.potential.has_dynamic_terms());
    let springs = Springs {
        pairs: Vec::new(),
        next: vec![vec![[far_a, far_b]], vec![[far_a, far_b], [1, far_b]]],
        k: 7.0,
    };
    sys.potential.insert(springs);
    let mut p = sys.potential;
    assert_eq!(
        p.pattern().nnz(),
        fixed_nnz,
        "no pairs yet: the union equals the fixed pattern"
    );
    let u: Vec<f64> = (0..p.n_dofs()).map(|i| 0.01 * (i as f64).sin()).collect();
    // First step: two pairs (popped from the back); the pattern grows and couples far nodes.
    assert!(p.begin_step(&u).unwrap());
    assert!(p.pattern().entry(3 * far_a, 3 * far_b).is_some());
    let h = dense_hessian(&mut p, &u);
    // Finite differences of the gradient (the springs and the shell together).
    let n = p.n_dofs();
    let step = 1e-6;
    for j in [3 * far_a, 3 * far_b + 2, 3] {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[j] += step;
        um[j] -= step;
        let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
        p.gradient(&up, &mut gp).unwrap();
        p.gradient(&um, &mut gm).unwrap();
        for i in 0..n {
            let fd = (gp[i] - gm[i]) / (2.0 * step);
            assert!(
                (fd - h[(i, j)]).abs() <= 1e-6 * h.amax(),
                "({i}, {j}): {} vs {fd}",
                h[(i, j)]
            );
        }
    }
    // Second step: a subset of the pairs: no growth, no new symbolic analysis needed.
    assert!(!p.begin_step(&u).unwrap());
}

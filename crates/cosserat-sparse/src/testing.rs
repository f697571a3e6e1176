//! Sparse symmetric test matrices (seeded), kept as an upper triangle in CSC form with a dense
//! nalgebra twin for independent reference solutions: the fixtures of this crate's tests and of the
//! solvers built on it (feature `testing`).

use std::collections::BTreeMap;

use faer::sparse::SymbolicSparseColMat;
use nalgebra::{DMatrix, DVector};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

/// A seeded RNG.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// Collects upper-triangle entries `(row ≤ col)` and builds a compact CSC pattern with sorted rows.
#[derive(Debug, Clone)]
pub struct PatternBuilder {
    n: usize,
    entries: BTreeMap<(usize, usize), f64>,
}

impl PatternBuilder {
    /// An empty `n × n` matrix.
    pub fn new(n: usize) -> Self {
        Self {
            n,
            entries: BTreeMap::new(),
        }
    }

    /// Adds `v` to entry `(i, j)` of the symmetric matrix, stored at `(min, max)`.
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let (r, c) = if i <= j { (i, j) } else { (j, i) };
        *self.entries.entry((c, r)).or_insert(0.0) += v;
    }

    /// The matrix with a compact CSC pattern of the added entries (rows sorted).
    pub fn build(self) -> UpperMatrix {
        let mut col_ptr = vec![0usize; self.n + 1];
        let mut row_idx = Vec::with_capacity(self.entries.len());
        let mut values = Vec::with_capacity(self.entries.len());
        for (&(c, r), &v) in &self.entries {
            col_ptr[c + 1] += 1;
            row_idx.push(r);
            values.push(v);
        }
        for j in 0..self.n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let pattern = SymbolicSparseColMat::new_checked(self.n, self.n, col_ptr, None, row_idx);
        UpperMatrix { pattern, values }
    }
}

/// A symmetric matrix given by its upper triangle.
#[derive(Debug, Clone)]
pub struct UpperMatrix {
    /// The upper triangle's pattern (CSC, sorted rows).
    pub pattern: SymbolicSparseColMat<usize>,
    /// Its values in pattern order.
    pub values: Vec<f64>,
}

impl UpperMatrix {
    /// The dimension.
    pub fn n(&self) -> usize {
        self.pattern.ncols()
    }

    /// `(row, col)` of every stored entry in pattern order.
    pub fn entries(&self) -> Vec<(usize, usize)> {
        let p = self.pattern.as_ref();
        let mut out = Vec::with_capacity(self.values.len());
        for j in 0..self.n() {
            for &i in &p.row_idx()[p.col_ptr()[j]..p.col_ptr()[j + 1]] {
                out.push((i, j));
            }
        }
        out
    }

    /// The full symmetric matrix as a dense nalgebra matrix.
    pub fn to_dense(&self) -> DMatrix<f64> {
        let mut a = DMatrix::zeros(self.n(), self.n());
        for (&v, (i, j)) in self.values.iter().zip(self.entries()) {
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
        a
    }

    /// The same pattern with new values.
    pub fn with_values(&self, values: Vec<f64>) -> Self {
        assert_eq!(values.len(), self.values.len());
        Self {
            pattern: self.pattern.clone(),
            values,
        }
    }
}

/// `‖A x − b‖₂ / ‖b‖₂` with the dense twin.
pub fn relative_residual(a: &UpperMatrix, x: &[f64], b: &[f64]) -> f64 {
    let dense = a.to_dense();
    let r = &dense * DVector::from_column_slice(x) - DVector::from_column_slice(b);
    r.norm() / DVector::from_column_slice(b).norm()
}

/// `n` entries uniform in `[-1, 1)`.
pub fn random_vector(n: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-1.0..1.0)).collect()
}

/// The 5-point Laplacian of an `nx × ny` grid (Dirichlet-like, diagonal 4) plus a random positive
/// diagonal in [0.1, 1): symmetric positive definite.
pub fn laplacian_2d(nx: usize, ny: usize, rng: &mut ChaCha8Rng) -> UpperMatrix {
    let n = nx * ny;
    let id = |i: usize, j: usize| i * ny + j;
    let mut b = PatternBuilder::new(n);
    for i in 0..nx {
        for j in 0..ny {
            let p = id(i, j);
            b.add(p, p, 4.0 + rng.random_range(0.1..1.0));
            if i + 1 < nx {
                b.add(p, id(i + 1, j), -1.0);
            }
            if j + 1 < ny {
                b.add(p, id(i, j + 1), -1.0);
            }
        }
    }
    b.build()
}

/// A 3×3-block matrix on an `nx × ny` grid graph: every grid edge contributes `Gᵀ G` for a random
/// 6×6 `G` on the 6 unknowns of its two nodes, plus `shift · I`. Symmetric positive definite for
/// `shift > 0`.
pub fn block_grid(nx: usize, ny: usize, shift: f64, rng: &mut ChaCha8Rng) -> UpperMatrix {
    let n_nodes = nx * ny;
    let id = |i: usize, j: usize| i * ny + j;
    let mut b = PatternBuilder::new(3 * n_nodes);
    for p in 0..3 * n_nodes {
        b.add(p, p, shift);
    }
    let mut edge = |a: usize, c: usize, b: &mut PatternBuilder| {
        let g = DMatrix::<f64>::from_fn(6, 6, |_, _| rng.random_range(-1.0..1.0));
        let k = g.transpose() * g;
        let dofs: Vec<usize> = (0..3).map(|d| 3 * a + d).chain((0..3).map(|d| 3 * c + d)).collect();
        for r in 0..6 {
            for s in r..6 {
                b.add(dofs[r], dofs[s], k[(r, s)]);
            }
        }
    };
    for i in 0..nx {
        for j in 0..ny {
            if i + 1 < nx {
                edge(id(i, j), id(i + 1, j), &mut b);
            }
            if j + 1 < ny {
                edge(id(i, j), id(i, j + 1), &mut b);
            }
        }
    }
    b.build()
}

/// The saddle-point matrix `[[K, Bᵀ], [B, −δ I]]` with `K` the given SPD matrix and `B` an
/// `m × n` random sparse constraint matrix (each row couples `per_row` unknowns). Indefinite: `m`
/// negative and `n` positive eigenvalues. `delta = 0` gives a zero (2, 2) block, stored explicitly.
pub fn saddle_point(k: &UpperMatrix, m: usize, per_row: usize, delta: f64, rng: &mut ChaCha8Rng) -> UpperMatrix {
    let n = k.n();
    let mut b = PatternBuilder::new(n + m);
    for (&v, (i, j)) in k.values.iter().zip(k.entries()) {
        b.add(i, j, v);
    }
    for row in 0..m {
        for _ in 0..per_row {
            let col = rng.random_range(0..n);
            b.add(col, n + row, rng.random_range(0.5..1.5));
        }
        b.add(n + row, n + row, -delta);
    }
    b.build()
}

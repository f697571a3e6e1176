//! Two-domain Cholesky: the two halves of a bisected mesh are factorised at the same time, one per
//! core, and joined through the dense Schur complement of their separator.
//!
//! A sparse Cholesky walks the supernodes one after the other; faer's parallel mode only splits the
//! dense kernels inside a supernode, and the supernodes of a shell mesh are too small for that to pay
//! (measured slower than sequential, docs/performance.md). Two halves of a mesh that no matrix
//! entry couples, however, are eliminated independently. With a vertex separator `S` between the
//! parts `D₁`, `D₂` and the ordering `[D₁, D₂, S]`,
//!
//! ```text
//!     [ A₁₁   0   A₁ₛ ]           [ L₁   0   0  ]
//! A = [  0   A₂₂  A₂ₛ ] = L Lᵀ,  L = [  0   L₂   0  ]
//!     [ Aₛ₁  Aₛ₂  Aₛₛ ]           [ B₁   B₂  Lₛ ]
//! ```
//!
//! Domain `i` eliminates the own unknowns of the principal submatrix `Mᵢ = [Aᵢᵢ Aᵢₛ; Aₛᵢ Aₛₛ]`,
//! in an AMD order that knows the separator comes last ([`domain_order`]), on its own core with the
//! multifrontal kernel of `multifrontal.rs` (faer's symbolic analysis of `Mᵢ` gives the supernodes).
//! That yields `Lᵢ`, `Bᵢ` and `−Bᵢ Bᵢᵀ`; the separator's columns of `Mᵢ` are never factorised. The
//! separator's Schur complement `Lₛ Lₛᵀ = Aₛₛ − B₁ B₁ᵀ − B₂ B₂ᵀ` is then a small dense Cholesky. A
//! solve runs forward in both domains at once (which also forms `Bᵢ zᵢ`), through the separator, and
//! back in both domains at once.
//!
//! Results do not depend on the number of threads: each domain is computed sequentially and the two
//! are combined in a fixed order.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization, cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::reborrow::ReborrowMut;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::{Mat, MatMut, Par, Side};

use super::FactorStats;
use super::cholesky::supernodal_stats;
use super::multifrontal::Fronts;
use super::ordering::{
    Bisection, NESTED_DISSECTION_SHARE, NODE_BLOCK, amd_order, factor_operations, nested_dissection_of_pairs,
    upper_structure, whole_order,
};
use super::pattern::UpperPattern;
use super::reordered::{lower_and_upper, lower_entries};
use crate::error::{LinearSolveError, LinearSolveStage, out_of_memory};

const NONE: usize = usize::MAX;

/// The largest set of separator neighbours joined by a clique for AMD (see [`domain_order`]); larger
/// ones (a long separator) are left as they are to bound the clique's size.
const MAX_HALO_CLIQUE: usize = 4000;

/// One half of the bisection with the separator: its principal submatrix's factor and work vector.
struct Domain {
    /// The caller's index of each local unknown: the domain's own in AMD order, then the separator's.
    global: Vec<usize>,
    /// Number of the domain's own unknowns (the separator starts at this local index).
    n_own: usize,
    /// faer's supernodal structure of `M`'s factor, which the fronts fill and the substitutions read.
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// The multifrontal schedule of the own columns.
    fronts: Fronts,
    /// The first supernode that holds a separator column.
    first_separator_supernode: usize,
    /// The local vector of forward and backward substitution.
    work: Vec<f64>,
    /// The entries of `work` at one supernode's rows (its columns, then the rows below them), gathered
    /// once per supernode so that the substitutions run over contiguous memory and read the row
    /// indices once per supernode instead of once per column (as long as the tallest supernode).
    local: Vec<f64>,
    /// Per column of one supernode, the backward substitution's dot product over the rows below the
    /// supernode's columns (as long as the widest supernode).
    below_dots: Vec<f64>,
    /// `−Bᵢ Bᵢᵀ`, the domain's part of the separator's Schur complement (column-major, lower
    /// triangle), formed on the domain's thread.
    separator_update: Vec<f64>,
}

impl Domain {
    /// Builds `M` and its symbolic analysis for the factorisation order `global` (the domain's own
    /// `n_own` unknowns, then the separator's; from [`domain_order`]).
    fn try_new(pattern: &UpperPattern, global: Vec<usize>, n_own: usize) -> Result<Option<Self>, LinearSolveError> {
        let n_sep = global.len() - n_own;
        let mut local = vec![NONE; pattern.n()];
        for (l, &g) in global.iter().enumerate() {
            local[g] = l;
        }
        // The lower triangle, whose columns the fronts assemble, and its transpose for the analysis.
        let (m_pattern, gather, m_upper) = lower_and_upper(n_own + n_sep, lower_entries(pattern, &local));
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(m_upper.as_ref(), Side::Upper, SymmetricOrdering::Identity, params)
            .map_err(|source| LinearSolveError::Faer {
                stage: LinearSolveStage::SymmetricSymbolic,
                source,
            })?;
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            return Ok(None);
        };
        let first_separator_supernode = sn.supernode_end().partition_point(|&end| end <= n_own);
        // The substitutions' scratch: the tallest supernode's rows and the widest one's columns.
        let (tallest, widest) = (0..sn.n_supernodes()).fold((0, 0), |(tall, wide), s| {
            let width = sn.supernode_end()[s] - sn.supernode_begin()[s];
            (tall.max(width + sn.supernode(s).pattern().len()), wide.max(width))
        });
        let l_values = super::memory::mapped_zeros(symbolic.len_val());
        // faer's supernodes nest (each front's rows are rows of its parent); if they did not, the
        // whole matrix is factorised instead.
        let Some(fronts) = Fronts::try_new(sn, m_pattern.as_ref(), &gather, n_own) else {
            return Ok(None);
        };
        Ok(Some(Self {
            l_values,
            global,
            n_own,
            symbolic,
            fronts,
            first_separator_supernode,
            work: vec![0.0; n_own + n_sep],
            local: vec![0.0; tallest],
            below_dots: vec![0.0; widest],
            separator_update: super::memory::mapped_zeros(n_sep * n_sep),
        }))
    }

    /// Factorises the own columns of `M` and forms `−Bᵢ Bᵢᵀ`; on a non-positive pivot returns the
    /// caller's column.
    fn factorise(&mut self, values: &[f64]) -> Result<(), usize> {
        self.fronts
            .factorise(values, &mut self.l_values, &mut self.separator_update)
            .map_err(|index| self.global.get(index).copied().unwrap_or(index))
    }

    /// Forward substitution `Lᵢ zᵢ = bᵢ` over the domain's own columns; leaves `zᵢ` in the own part of
    /// `work` and `−Bᵢ zᵢ` in its separator part.
    fn forward(&mut self, rhs: &[f64]) {
        let n_own = self.n_own;
        for (w, &g) in self.work[..n_own].iter_mut().zip(&self.global) {
            *w = rhs[g];
        }
        self.work[n_own..].fill(0.0);
        let sn = supernodes(&self.symbolic);
        let work = &mut self.work;
        for s in 0..(self.first_separator_supernode + 1).min(sn.n_supernodes()) {
            let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
            let below = sn.supernode(s).pattern();
            let local = gather_rows(&mut self.local, work, begin..end, below);
            let rows = local.len();
            let block = &self.l_values[sn.col_ptr_for_val()[s]..sn.col_ptr_for_val()[s + 1]];
            for j in 0..(end - begin).min(n_own.saturating_sub(begin)) {
                let col = &block[j * rows..(j + 1) * rows];
                let x = local[j] / col[j];
                local[j] = x;
                for (v, &l) in local[j + 1..].iter_mut().zip(&col[j + 1..]) {
                    *v -= l * x;
                }
            }
            work[begin..end].copy_from_slice(&local[..end - begin]);
            for (&v, &r) in local[end - begin..].iter().zip(below) {
                work[r] = v;
            }
        }
    }

    /// Backward substitution `Lᵢᵀ xᵢ = zᵢ − Bᵢᵀ xₛ` given the separator's solution.
    fn backward(&mut self, x_separator: &[f64]) {
        let n_own = self.n_own;
        self.work[n_own..].copy_from_slice(x_separator);
        let sn = supernodes(&self.symbolic);
        let work = &mut self.work;
        for s in (0..(self.first_separator_supernode + 1).min(sn.n_supernodes())).rev() {
            let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
            let below = sn.supernode(s).pattern();
            let local = gather_rows(&mut self.local, work, begin..end, below);
            let rows = local.len();
            let block = &self.l_values[sn.col_ptr_for_val()[s]..sn.col_ptr_for_val()[s + 1]];
            let (width, solved) = (end - begin, (end - begin).min(n_own.saturating_sub(begin)));
            // The rows below the supernode's columns hold most of its entries and all the unknowns
            // they need are known: their dot products run first, over the columns in memory order,
            // so that the block streams from memory as in the forward substitution (walking the
            // columns backwards, as the triangle needs, defeats the hardware prefetcher).
            let (top, bottom) = local.split_at_mut(width);
            for (j, d) in self.below_dots[..solved].iter_mut().enumerate() {
                *d = dot(&block[j * rows + width..(j + 1) * rows], bottom);
            }
            for j in (0..solved).rev() {
                let col = &block[j * rows..j * rows + width];
                top[j] = (top[j] - self.below_dots[j] - dot(&col[j + 1..], &top[j + 1..])) / col[j];
            }
            work[begin..end].copy_from_slice(top);
        }
    }

    /// `Σ c_j²` over the domain's own columns, their entries and supernodes.
    fn stats(&self) -> FactorStats {
        supernodal_stats(supernodes(&self.symbolic), self.n_own)
    }
}

/// The caller's unknowns of `M` in factorisation order and the operations `Σ c_j²` of its factor: `own` in the best of several AMD orderings,
/// then `separator`. `local` (length `n`, all `NONE`) is scratch and is left dirty.
///
/// AMD on the domain's own block does not know that the separator comes last. Unknowns next to the
/// separator look like boundary unknowns of low degree and are eliminated early; the separator's rows
/// then ride along in every column of the front that sweeps the domain. Two remedies, measured on the
/// plate strips (Tri6, critical-path operations of the split at 157k / 620k unknowns):
/// - the separator's neighbours (the halo) are joined by a clique in the graph AMD sees, so that they
///   look as dense as they will be and go last: 4.6e9 → 2.8e9 and 5.4e10 → 2.6e10;
/// - AMD's tie-breaking still decides a lot (the same half-plate costs 2.6e10 or 6.8e10 depending only
///   on the order the unknowns are presented in), so AMD runs on four presentations (by breadth-first
///   distance from the separator, nearest or farthest first, ties in the given order or reversed) and
///   the ordering whose factor of `M` has the fewest operations `Σ c_j²` (from its column counts, in
///   near-linear time) is kept.
///
/// With `nested_dissection`, METIS's nested dissection of the own block is a fifth candidate, taken
/// if it needs at most [`NESTED_DISSECTION_SHARE`] of the best AMD order's operations (as for the
/// whole matrix, [`whole_order`]).
fn domain_order(
    pattern: &UpperPattern,
    own: &[usize],
    separator: &[usize],
    local: &mut [usize],
    nested_dissection: bool,
) -> Result<(Vec<usize>, f64), LinearSolveError> {
    let (n_own, n_sep) = (own.len(), separator.len());
    let m = n_own + n_sep;
    for (l, &g) in own.iter().chain(separator).enumerate() {
        local[g] = l;
    }
    // The off-diagonal entries of `M` as local pairs (the diagonal adds nothing to the structure).
    let pairs: Vec<(u32, u32)> = pattern
        .row_idx()
        .iter()
        .zip(pattern.col_idx())
        .filter_map(|(&r, &c)| {
            let (lr, lc) = (local[r], local[c]);
            (lr != NONE && lc != NONE && lr != lc).then_some((lr as u32, lc as u32))
        })
        .collect();
    let distance = distance_from_separator(m, n_own, &pairs);
    // By distance from the separator, nearest or farthest first, ties in the given order or reversed.
    let mut nearest: Vec<usize> = (0..n_own).collect();
    nearest.sort_by_key(|&l| distance[l]);
    let mut nearest_reversed_ties: Vec<usize> = (0..n_own).rev().collect();
    nearest_reversed_ties.sort_by_key(|&l| distance[l]);
    let farthest: Vec<usize> = nearest_reversed_ties.iter().rev().copied().collect();
    let farthest_reversed_ties: Vec<usize> = nearest.iter().rev().copied().collect();
    let mut best: Option<(f64, Vec<usize>)> = None;
    // The separator's neighbours are joined by a clique: after the separator comes last they all
    // share its rows, and as a clique they look to AMD like the dense unknowns they will be, so they
    // are eliminated late instead of first.
    let halo: Vec<usize> = (0..n_own).filter(|&l| distance[l] == 1).collect();
    let halo_clique = halo.len() <= MAX_HALO_CLIQUE;
    for input in [farthest, farthest_reversed_ties, nearest, nearest_reversed_ties] {
        // `input[k]` is the local unknown presented to AMD as its k-th.
        let mut position = vec![0u32; n_own];
        for (k, &l) in input.iter().enumerate() {
            position[l] = k as u32;
        }
        let mut presented: Vec<(u32, u32)> = pairs
            .iter()
            .filter(|&&(r, c)| (r as usize) < n_own && (c as usize) < n_own)
            .map(|&(r, c)| (position[r as usize], position[c as usize]))
            .collect();
        if halo_clique {
            for (i, &a) in halo.iter().enumerate() {
                for &b in &halo[..i] {
                    presented.push((position[a], position[b]));
                }
            }
        }
        let perm = amd_order(upper_structure(n_own, &presented).as_ref())?;
        drop(presented);
        // Factorisation order of the local unknowns: own by AMD, then the separator.
        let order: Vec<usize> = perm.iter().map(|&k| input[k]).chain(n_own..m).collect();
        let cost = factor_operations(&order, &pairs)?;
        // The first of the cheapest, so that the choice is deterministic.
        if best.as_ref().is_none_or(|(c, _)| cost < *c) {
            best = Some((cost, order));
        }
    }
    if nested_dissection
        && let Some((cost, order)) = nested_dissection_candidate(n_own, m, &pairs)?
        && best.as_ref().is_none_or(|(c, _)| cost <= NESTED_DISSECTION_SHARE * *c)
    {
        best = Some((cost, order));
    }
    let (operations, order) = best.unwrap_or_default();
    let by_local: Vec<usize> = own.iter().chain(separator).copied().collect();
    Ok((order.iter().map(|&l| by_local[l]).collect(), operations))
}

/// METIS's nested dissection of the domain's own block (local unknowns `0..n_own`, the separator
/// `n_own..m` after it) with its operations, or `None` if METIS cannot order it.
fn nested_dissection_candidate(
    n_own: usize,
    m: usize,
    pairs: &[(u32, u32)],
) -> Result<Option<(f64, Vec<usize>)>, LinearSolveError> {
    let own_pairs: Vec<(u32, u32)> = pairs
        .iter()
        .copied()
        .filter(|&(r, c)| (r as usize) < n_own && (c as usize) < n_own)
        .collect();
    let Some(perm) = nested_dissection_of_pairs(n_own, &own_pairs) else {
        return Ok(None);
    };
    let order: Vec<usize> = perm.into_iter().chain(n_own..m).collect();
    Ok(Some((factor_operations(&order, pairs)?, order)))
}

/// Breadth-first distance (in entries) of every local unknown from the separator (`n_own..m`).
fn distance_from_separator(m: usize, n_own: usize, pairs: &[(u32, u32)]) -> Vec<usize> {
    let mut degree = vec![0usize; m + 1];
    for &(r, c) in pairs {
        degree[r as usize + 1] += 1;
        degree[c as usize + 1] += 1;
    }
    for v in 0..m {
        degree[v + 1] += degree[v];
    }
    let ptr = degree;
    let mut fill = ptr.clone();
    let mut adjacency = vec![0u32; ptr[m]];
    for &(r, c) in pairs {
        adjacency[fill[r as usize]] = c;
        fill[r as usize] += 1;
        adjacency[fill[c as usize]] = r;
        fill[c as usize] += 1;
    }
    let mut distance = vec![usize::MAX; m];
    let mut queue: Vec<usize> = (n_own..m).collect();
    for &v in &queue {
        distance[v] = 0;
    }
    let mut head = 0;
    while head < queue.len() {
        let v = queue[head];
        head += 1;
        for &w in &adjacency[ptr[v]..ptr[v + 1]] {
            let w = w as usize;
            if distance[w] == usize::MAX {
                distance[w] = distance[v] + 1;
                queue.push(w);
            }
        }
    }
    distance
}

/// The critical path of the split: the larger domain factor, then the separator's dense factor.
fn critical(operations_0: f64, operations_1: f64, n_sep: usize) -> f64 {
    let n_sep = n_sep as f64;
    operations_0.max(operations_1) + n_sep * n_sep * n_sep / 3.0
}

/// `work` at the rows `columns` then `below`, copied to the front of `local`.
fn gather_rows<'a>(
    local: &'a mut [f64],
    work: &[f64],
    columns: std::ops::Range<usize>,
    below: &[usize],
) -> &'a mut [f64] {
    let width = columns.len();
    let local = &mut local[..width + below.len()];
    local[..width].copy_from_slice(&work[columns]);
    for (v, &r) in local[width..].iter_mut().zip(below) {
        *v = work[r];
    }
    local
}

/// `Σ l[k] · x[k]` with eight independent partial sums, so that the additions do not wait on each
/// other (a single running sum makes the backward substitution latency-bound) and run as vectors.
/// On the 620k plate's halves, eight made the backward substitution 11 % faster than four, and 16
/// slower again.
fn dot(l: &[f64], x: &[f64]) -> f64 {
    const P: usize = 8;
    let mut partial = [0.0; P];
    let (l_quads, l_rest) = l.split_at(l.len() - l.len() % P);
    let (x_quads, x_rest) = x.split_at(l_quads.len());
    for (lq, xq) in l_quads.chunks_exact(P).zip(x_quads.chunks_exact(P)) {
        for k in 0..P {
            partial[k] += lq[k] * xq[k];
        }
    }
    let rest: f64 = l_rest.iter().zip(x_rest).map(|(&v, &x)| v * x).sum();
    partial.iter().sum::<f64>() + rest
}

/// The supernodal structure of a domain factor (domains are only built supernodal).
fn supernodes(symbolic: &SymbolicCholesky<usize>) -> &SymbolicSupernodalCholesky<usize> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => sn,
        SymbolicCholeskyRaw::Simplicial(_) => unreachable!("domains are built supernodal only"),
    }
}

/// `(values position, row, column)` of the stored entries of `Aₛₛ` in separator numbering, or `None`
/// if an entry couples the two parts (they are then not separated).
fn separator_entries(
    pattern: &UpperPattern,
    parts: &[Vec<usize>; 2],
    separator: &[usize],
) -> Option<Vec<(usize, usize, usize)>> {
    let n = pattern.n();
    let mut part = vec![2u8; n];
    for (p, unknowns) in parts.iter().enumerate() {
        for &u in unknowns {
            part[u] = p as u8;
        }
    }
    let mut separator_local = vec![NONE; n];
    for (k, &u) in separator.iter().enumerate() {
        separator_local[u] = k;
    }
    let mut entries = Vec::new();
    for (k, (&r, &c)) in pattern.row_idx().iter().zip(pattern.col_idx()).enumerate() {
        match (part[r], part[c]) {
            (0, 1) | (1, 0) => return None,
            (2, 2) => entries.push((k, separator_local[r], separator_local[c])),
            _ => {}
        }
    }
    Some(entries)
}

/// The Cholesky factorisation of a bisected pattern: two domain factors and the separator's dense
/// Schur complement (see the module documentation).
pub(crate) struct TwoDomainCholesky {
    domains: [Domain; 2],
    /// The separator's unknowns in the caller's numbering.
    separator: Vec<usize>,
    /// `(values position, row, column)` of the stored entries of `Aₛₛ`, in separator numbering.
    separator_entries: Vec<(usize, usize, usize)>,
    /// `Aₛₛ − B₁ B₁ᵀ − B₂ B₂ᵀ`, then its Cholesky factor `Lₛ` (lower triangle).
    schur: Mat<f64>,
    mem: MemBuffer,
    x_separator: Vec<f64>,
    stats: FactorStats,
}

impl std::fmt::Debug for TwoDomainCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TwoDomainCholesky")
            .field("own", &[self.domains[0].n_own, self.domains[1].n_own])
            .field("separator", &self.separator.len())
            .field("domain_stats", &[self.domains[0].stats(), self.domains[1].stats()])
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl TwoDomainCholesky {
    /// Builds both domain analyses for `bisection`. `None` if the parts are coupled by an entry (the
    /// bisection is not a separator of this pattern) or a domain's structure is not supernodal.
    ///
    /// With `max_critical_share`, gives up (`None`) before the domains' symbolic analyses when the
    /// operations on the split's critical path (the larger domain factor, then the separator's dense
    /// factor, from exact column counts) exceed that share of the whole matrix's
    /// ([`whole_operations`]): a prediction of the split's time against one factorisation on two
    /// cores.
    pub(crate) fn try_new(
        pattern: &UpperPattern,
        bisection: &Bisection,
        max_critical_share: Option<f64>,
        nested_dissection: bool,
    ) -> Result<Option<Self>, LinearSolveError> {
        let n = pattern.n();
        if separator_entries(pattern, &bisection.parts, &bisection.separator).is_none() {
            return Ok(None);
        }
        let n_sep = bisection.separator.len();
        let order = |own: &[usize]| {
            domain_order(
                pattern,
                own,
                &bisection.separator,
                &mut vec![NONE; n],
                nested_dissection,
            )
        };
        let ((o0, o1), whole) = rayon::join(
            || rayon::join(|| order(&bisection.parts[0]), || order(&bisection.parts[1])),
            || max_critical_share.map(|_| whole_order(pattern, nested_dissection).map(|(_, operations)| operations)),
        );
        let ((g0, ops0), (g1, ops1)) = (o0?, o1?);
        if let (Some(share), Some(whole)) = (max_critical_share, whole.transpose()?)
            && critical(ops0, ops1, n_sep) > share * whole
        {
            return Ok(None);
        }
        let own = |g: &[usize], n_own: usize| g[..n_own].to_vec();
        let (n0, n1) = (bisection.parts[0].len(), bisection.parts[1].len());
        Self::try_from_orders(pattern, [own(&g0, n0), own(&g1, n1)], bisection.separator.clone())
    }

    /// The split of `pattern` (a pattern of the same dimension, usually this one's grown by contact)
    /// with this split's domain orders: the nodes (blocks of [`NODE_BLOCK`] unknowns) that a new entry
    /// couples across the domains move into the separator, and each domain keeps its order of the
    /// rest. A symbolic analysis without the orderings' cost; `None` if a domain's structure is not
    /// supernodal.
    pub(crate) fn try_grown(&self, pattern: &UpperPattern) -> Result<Option<Self>, LinearSolveError> {
        let n = pattern.n();
        let mut part = vec![2u8; n];
        for (p, d) in self.domains.iter().enumerate() {
            for &u in &d.global[..d.n_own] {
                part[u] = p as u8;
            }
        }
        let mut moved = Vec::new();
        for (&r, &c) in pattern.row_idx().iter().zip(pattern.col_idx()) {
            if part[r] < 2 && part[c] < 2 && part[r] != part[c] {
                let first = c - c % NODE_BLOCK;
                for u in first..(first + NODE_BLOCK).min(n) {
                    if part[u] < 2 {
                        part[u] = 2;
                        moved.push(u);
                    }
                }
            }
        }
        moved.sort_unstable();
        let own = |d: &Domain| -> Vec<usize> { d.global[..d.n_own].iter().copied().filter(|&u| part[u] < 2).collect() };
        let separator: Vec<usize> = self.separator.iter().copied().chain(moved).collect();
        Self::try_from_orders(pattern, [own(&self.domains[0]), own(&self.domains[1])], separator)
    }

    /// The split with the given factorisation orders of the domains' own unknowns and the separator.
    fn try_from_orders(
        pattern: &UpperPattern,
        own: [Vec<usize>; 2],
        separator: Vec<usize>,
    ) -> Result<Option<Self>, LinearSolveError> {
        let Some(separator_entries) = separator_entries(pattern, &own, &separator) else {
            return Ok(None);
        };
        let n_sep = separator.len();
        let [o0, o1] = own;
        let (n0, n1) = (o0.len(), o1.len());
        let global = |o: Vec<usize>| o.into_iter().chain(separator.iter().copied()).collect::<Vec<_>>();
        let (g0, g1) = (global(o0), global(o1));
        let (d0, d1) = rayon::join(|| Domain::try_new(pattern, g0, n0), || Domain::try_new(pattern, g1, n1));
        let (Some(d0), Some(d1)) = (d0?, d1?) else {
            return Ok(None);
        };
        let mem = MemBuffer::try_new(cholesky_in_place_scratch::<f64>(n_sep, Par::Seq, Default::default()))
            .map_err(|_| out_of_memory())?;
        let (s0, s1) = (d0.stats(), d1.stats());
        let dense = (1..=n_sep).map(|c| (c as f64) * (c as f64)).sum::<f64>();
        let stats = FactorStats {
            nnz_l: s0.nnz_l + s1.nnz_l + n_sep * (n_sep + 1) / 2,
            flops: s0.flops + s1.flops + dense,
            n_supernodes: s0.n_supernodes + s1.n_supernodes + 1,
            domains: 2,
        };
        Ok(Some(Self {
            domains: [d0, d1],
            separator,
            separator_entries,
            schur: Mat::zeros(n_sep, n_sep),
            mem,
            x_separator: vec![0.0; n_sep],
            stats,
        }))
    }

    /// Structural statistics: both domain factors and the dense separator factor.
    pub(crate) fn stats(&self) -> FactorStats {
        self.stats
    }

    /// Numerical factorisation of the matrix whose upper triangle is `values` (pattern order).
    pub(crate) fn factorise(&mut self, values: &[f64]) -> Result<(), LinearSolveError> {
        let [d0, d1] = &mut self.domains;
        // Each worker leaves its vector registers clean for the element kernels that run on it next.
        let factorise = |d: &mut Domain| {
            let result = d.factorise(values);
            super::vector_state::clear_this_thread();
            result
        };
        let (r0, r1) = rayon::join(|| factorise(d0), || factorise(d1));
        r0.and(r1).map_err(|col| LinearSolveError::NotPositiveDefinite { col })?;
        // `Aₛₛ − B₁ B₁ᵀ − B₂ B₂ᵀ`, lower triangle (the dense Cholesky reads no other).
        let n_sep = self.separator.len();
        let mut schur = self.schur.as_mut();
        for j in 0..n_sep {
            for i in j..n_sep {
                schur[(i, j)] = d0.separator_update[j * n_sep + i] + d1.separator_update[j * n_sep + i];
            }
        }
        for &(k, i, j) in &self.separator_entries {
            schur[(i.max(j), i.min(j))] += values[k];
        }
        cholesky_in_place(
            schur,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        )
        .map_err(
            |LltError::NonPositivePivot { index }| LinearSolveError::NotPositiveDefinite {
                col: self.separator.get(index).copied().unwrap_or(index),
            },
        )?;
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last factorisation.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let [d0, d1] = &mut self.domains;
        {
            let b: &[f64] = rhs;
            rayon::join(|| d0.forward(b), || d1.forward(b));
        }
        for (k, (x, &g)) in self.x_separator.iter_mut().zip(&self.separator).enumerate() {
            *x = rhs[g] + d0.work[d0.n_own + k] + d1.work[d1.n_own + k];
        }
        let n_sep = self.separator.len();
        let l = self.schur.as_ref();
        let mut x = MatMut::from_column_major_slice_mut(&mut self.x_separator, n_sep, 1);
        solve_lower_triangular_in_place(l, x.rb_mut(), Par::Seq);
        solve_upper_triangular_in_place(l.transpose(), x.rb_mut(), Par::Seq);
        let x_separator: &[f64] = &self.x_separator;
        rayon::join(|| d0.backward(x_separator), || d1.backward(x_separator));
        for d in [&*d0, &*d1] {
            for (&g, &x) in d.global[..d.n_own].iter().zip(&d.work) {
                rhs[g] = x;
            }
        }
        for (&g, &x) in self.separator.iter().zip(x_separator) {
            rhs[g] = x;
        }
    }
}

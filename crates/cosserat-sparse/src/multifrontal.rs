//! Multifrontal numerical Cholesky of a domain's own columns, on faer's supernodal structure.
//!
//! faer 0.24's supernodal Cholesky is left-looking: before factorising a supernode it applies, one
//! after the other, the update of every descendant that touches it, each as a product whose inner
//! dimension is the descendant's width and whose result is scattered into the supernode. On the plate
//! domains three quarters of the operations sit in supernodes 128–512 columns wide, but they arrive
//! as many thin products, each packing its operands again, and the kernel runs at about half of one
//! core's dense GEMM rate (docs/performance.md).
//!
//! Here each supernode (a *front*) instead forms its whole update matrix `U = −L₂₁ L₂₁ᵀ` at once, a
//! product whose inner dimension is its own width, and hands it to its parent in the supernodal
//! elimination tree, which adds it into its own rows (the *extend-add*) before it is factorised. The
//! fronts run in a postorder, so the pending update matrices form a stack: a front's children are
//! the topmost entries when it runs. The factor is written in faer's supernodal layout, so faer's
//! structure still describes it for the substitutions.
//!
//! The domain's separator columns are not factorised at all: the fronts whose update rows are all
//! separator rows add their updates into one dense matrix, which ends as `−Bᵢ Bᵢᵀ`, this domain's
//! part of the separator's Schur complement (`two_domain.rs`).

use std::ops::Range;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization, cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::triangular::{BlockStructure, matmul};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::{Accum, MatMut, Par};

/// Where a front's update matrix goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// The front of this supernode (its parent in the elimination tree).
    Front(usize),
    /// The separator's dense block (all its update rows are separator rows).
    Separator,
    /// Nowhere: the front has no update rows.
    Nothing,
}

/// One supernode's elimination: its eliminated columns and the rows below them.
#[derive(Clone, Debug)]
struct Front {
    /// First column (domain-local numbering).
    begin: usize,
    /// Number of columns eliminated here (the supernode's columns before the separator).
    eliminated: usize,
    /// Rows of the panel in `L`: the eliminated columns, then the update rows. It is also the leading
    /// dimension of faer's block for this supernode, whose first `eliminated` columns the panel is.
    height: usize,
    /// Start of the supernode's block in `L`'s values.
    l_offset: usize,
    target: Target,
    /// Positions of the update rows in the target (the parent's rows, or the separator's).
    rel: Range<usize>,
    /// The stretches of consecutive positions in `rel` (a range of `runs`).
    runs: Range<usize>,
    /// Entries of `M` in the eliminated columns (ranges of `a_source` and `a_target`).
    a: Range<usize>,
    /// The children's fronts (a range of `children`).
    children: Range<usize>,
    /// The stack of the update matrix: the parity of the front's depth in the elimination tree.
    stack: usize,
    /// Where the update matrix (`m × m`, column-major, lower triangle) sits on its stack.
    stack_offset: usize,
}

impl Front {
    fn update_rows(&self) -> usize {
        self.height - self.eliminated
    }

    /// The front's update matrix on `stack` (its stack, once it has run).
    fn update_on<'a>(&self, stack: &'a [f64]) -> &'a [f64] {
        let m = self.update_rows();
        &stack[self.stack_offset..self.stack_offset + m * m]
    }
}

/// Adds the lower triangle of a child's `m_c × m_c` update matrix (column-major) into `target`
/// (column-major with leading dimension `ld`), entry `(i, j)` at `(rel[i] − shift, rel[j] − shift)`,
/// for the child's columns `columns`. `runs` are the starts of the stretches where `rel` is
/// consecutive, then `m_c`; each stretch of a column is one slice addition.
fn extend_add(
    update: &[f64],
    rel: &[usize],
    runs: &[usize],
    columns: Range<usize>,
    target: &mut [f64],
    ld: usize,
    shift: usize,
) {
    let mc = rel.len();
    // The stretch holding column `j`'s diagonal entry.
    let mut k = 0;
    for j in columns {
        while runs[k + 1] <= j {
            k += 1;
        }
        let column = &update[j * mc..(j + 1) * mc];
        let base = (rel[j] - shift) * ld;
        let mut start = j;
        for &end in &runs[k + 1..] {
            let first = base + rel[start] - shift;
            for (t, &v) in target[first..first + end - start].iter_mut().zip(&column[start..end]) {
                *t += v;
            }
            start = end;
        }
    }
}

/// The multifrontal schedule of a domain factor and its buffers.
pub(super) struct Fronts {
    /// Indexed by supernode (only the supernodes that start before the separator).
    fronts: Vec<Front>,
    /// The fronts in the order they run (a postorder of the elimination tree).
    order: Vec<usize>,
    children: Vec<usize>,
    rel: Vec<usize>,
    /// For each front, the indices in its `rel` where a stretch of consecutive positions starts, then
    /// the number of update rows: the extend-add adds whole stretches as contiguous slices (about 20
    /// entries on average on the plate domains).
    runs: Vec<usize>,
    /// Position in the caller's values of each entry of `M` in an eliminated column.
    a_source: Vec<usize>,
    /// Position in its front's panel (from the front's `l_offset`) where that entry is assembled.
    a_target: Vec<usize>,
    /// The update matrices, by the parity of their front's depth: a front writes its update
    /// straight onto its stack while its children's are read from the other one.
    stacks: [Vec<f64>; 2],
    /// Scratch of the dense Cholesky of the widest front.
    mem: MemBuffer,
    n_sep: usize,
}

/// The rows of supernode `s` in order: its columns, then its pattern below them.
fn position_in(sn: &SymbolicSupernodalCholesky<usize>, s: usize, row: usize) -> Option<usize> {
    let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
    if (begin..end).contains(&row) {
        return Some(row - begin);
    }
    sn.supernode(s).pattern().binary_search(&row).ok().map(|k| end - begin + k)
}

impl Fronts {
    /// The schedule for the domain factor `sn` of `M` (lower triangle `m_lower`, whose entry `k` is
    /// the caller's value `gather[k]`), with the separator from local column `n_own` on. `None` if a
    /// front's rows are not all rows of its parent (faer's structure would not nest as expected).
    pub(super) fn try_new(
        sn: &SymbolicSupernodalCholesky<usize>,
        m_lower: SymbolicSparseColMatRef<'_, usize>,
        gather: &[usize],
        n_own: usize,
    ) -> Option<Self> {
        let n_sep = m_lower.ncols() - n_own;
        let n_fronts = sn.supernode_begin().partition_point(|&begin| begin < n_own);
        let mut fronts = Vec::with_capacity(n_fronts);
        let mut rel = Vec::new();
        let mut runs = Vec::new();
        let (mut a_source, mut a_target) = (Vec::new(), Vec::new());
        for s in 0..n_fronts {
            let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
            let pattern = sn.supernode(s).pattern();
            let eliminated = end.min(n_own) - begin;
            let height = end - begin + pattern.len();
            let l_offset = sn.col_ptr_for_val()[s];
            let update_rows = (begin + eliminated..end).chain(pattern.iter().copied());
            let rel_start = rel.len();
            let target = update_target(sn, update_rows, n_own, &mut rel)?;
            let runs_start = runs.len();
            push_runs(&rel[rel_start..], &mut runs);
            let a_start = a_source.len();
            for j in begin..begin + eliminated {
                let rows = m_lower.row_idx_of_col_raw(j);
                let range = m_lower.col_range(j);
                for (&i, k) in rows.iter().zip(range) {
                    let position = position_in(sn, s, i)?;
                    a_source.push(gather[k]);
                    a_target.push((j - begin) * height + position);
                }
            }
            fronts.push(Front {
                begin,
                eliminated,
                height,
                l_offset,
                target,
                rel: rel_start..rel.len(),
                runs: runs_start..runs.len(),
                a: a_start..a_source.len(),
                children: 0..0,
                stack: 0,
                stack_offset: 0,
            });
        }
        let children = link_children(&mut fronts);
        let order = postorder(&fronts, &children)?;
        let peak = assign_stacks(&mut fronts, &order, &children);
        let widest = fronts.iter().map(|f| f.eliminated).max().unwrap_or(0);
        let mem =
            super::memory::mapped_workspace(cholesky_in_place_scratch::<f64>(widest, Par::Seq, Default::default()))?;
        Some(Self {
            fronts,
            order,
            children,
            rel,
            runs,
            a_source,
            a_target,
            stacks: [
                super::memory::mapped_zeros(peak[0]),
                super::memory::mapped_zeros(peak[1]),
            ],
            mem,
            n_sep,
        })
    }

    /// Factorises the eliminated columns of `M` (whose entries are read from the caller's `values`)
    /// into `l_values`, and writes `−Bᵢ Bᵢᵀ` into the lower triangle of `separator` (column-major,
    /// `n_sep × n_sep`). On a non-positive pivot returns its local column.
    pub(super) fn factorise(
        &mut self,
        values: &[f64],
        l_values: &mut [f64],
        separator: &mut [f64],
    ) -> Result<(), usize> {
        let n_sep = self.n_sep;
        debug_assert_eq!(separator.len(), n_sep * n_sep);
        for j in 0..n_sep {
            separator[j * n_sep + j..(j + 1) * n_sep].fill(0.0);
        }
        let positions = Positions {
            fronts: &self.fronts,
            rel: &self.rel,
            runs: &self.runs,
        };
        for &f in &self.order {
            let front = &self.fronts[f];
            let (height, eliminated, m) = (front.height, front.eliminated, front.update_rows());
            let panel = &mut l_values[front.l_offset..front.l_offset + height * eliminated];
            panel.fill(0.0);
            for (&source, &target) in self.a_source[front.a.clone()].iter().zip(&self.a_target[front.a.clone()]) {
                panel[target] += values[source];
            }
            let (own, other) = match &mut self.stacks {
                [zero, one] if front.stack == 0 => (zero, &*one),
                [zero, one] => (one, &*zero),
            };
            let children = &self.children[front.children.clone()];
            // The children's update entries in the eliminated columns, before they are factorised.
            positions.add_children(children, other, eliminated, Part::Eliminated, panel, height);
            let panel = MatMut::from_column_major_slice_mut(panel, height, eliminated);
            let (mut top, mut below) = panel.split_at_row_mut(eliminated);
            if let Err(LltError::NonPositivePivot { index }) = cholesky_in_place(
                top.rb_mut(),
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.mem),
                Default::default(),
            ) {
                return Err(front.begin + index);
            }
            if m == 0 {
                continue;
            }
            solve_lower_triangular_in_place(top.rb(), below.rb_mut().transpose_mut(), Par::Seq);
            let update = &mut own[front.stack_offset..front.stack_offset + m * m];
            matmul(
                MatMut::from_column_major_slice_mut(update, m, m),
                BlockStructure::TriangularLower,
                Accum::Replace,
                below.rb(),
                BlockStructure::Rectangular,
                below.rb().transpose(),
                BlockStructure::Rectangular,
                -1.0,
                Par::Seq,
            );
            // The children's update entries in the update rows.
            positions.add_children(children, other, eliminated, Part::Update, update, m);
            if front.target == Target::Separator {
                let rel = &self.rel[front.rel.clone()];
                extend_add(update, rel, &self.runs[front.runs.clone()], 0..m, separator, n_sep, 0);
            }
        }
        Ok(())
    }
}

/// Which columns of a front the children's update entries go to.
#[derive(Debug, Clone, Copy)]
enum Part {
    /// The eliminated columns (the panel, before its Cholesky factorisation).
    Eliminated,
    /// The update rows' columns (the front's own update matrix).
    Update,
}

/// The fronts with their update rows' positions in their targets, borrowed apart from the update
/// stacks that the factorisation writes.
struct Positions<'a> {
    fronts: &'a [Front],
    rel: &'a [usize],
    runs: &'a [usize],
}

impl Positions<'_> {
    /// Extend-adds the entries of the `children`'s update matrices (on `stack`) that fall in `part`
    /// of their parent, whose first `eliminated` columns are eliminated, into `target` (leading
    /// dimension `ld`: the panel's height, or the update matrix's order).
    fn add_children(
        &self,
        children: &[usize],
        stack: &[f64],
        eliminated: usize,
        part: Part,
        target: &mut [f64],
        ld: usize,
    ) {
        for &c in children {
            let child = &self.fronts[c];
            let rel = &self.rel[child.rel.clone()];
            let split = rel.partition_point(|&gj| gj < eliminated);
            let (columns, shift) = match part {
                Part::Eliminated => (0..split, 0),
                Part::Update => (split..rel.len(), eliminated),
            };
            extend_add(
                child.update_on(stack),
                rel,
                &self.runs[child.runs.clone()],
                columns,
                target,
                ld,
                shift,
            );
        }
    }
}

/// Where a front with these update rows sends its update: nowhere, the separator or its parent
/// front, with the rows' positions there pushed onto `rel`. `None` if a row is not a row of the
/// parent.
fn update_target(
    sn: &SymbolicSupernodalCholesky<usize>,
    update_rows: impl Iterator<Item = usize> + Clone,
    n_own: usize,
    rel: &mut Vec<usize>,
) -> Option<Target> {
    Some(match update_rows.clone().next() {
        None => Target::Nothing,
        Some(first) if first >= n_own => {
            rel.extend(update_rows.map(|r| r - n_own));
            Target::Separator
        }
        Some(first) => {
            let parent = sn.supernode_end().partition_point(|&e| e <= first);
            for r in update_rows {
                rel.push(position_in(sn, parent, r)?);
            }
            Target::Front(parent)
        }
    })
}

/// Pushes the indices of `positions` where a stretch of consecutive positions starts, then their
/// count (the extend-add's `runs`).
fn push_runs(positions: &[usize], runs: &mut Vec<usize>) {
    runs.extend((0..positions.len()).filter(|&i| i == 0 || positions[i] != positions[i - 1] + 1));
    runs.push(positions.len());
}

/// Sets every front's children (in increasing supernode order) and returns the list they index.
fn link_children(fronts: &mut [Front]) -> Vec<usize> {
    let n_fronts = fronts.len();
    // Children lists, in increasing supernode order.
    let mut count = vec![0usize; n_fronts + 1];
    for f in fronts.iter() {
        if let Target::Front(p) = f.target {
            count[p + 1] += 1;
        }
    }
    for p in 0..n_fronts {
        count[p + 1] += count[p];
    }
    let mut children = vec![0usize; count[n_fronts]];
    let mut next = count.clone();
    for (c, f) in fronts.iter().enumerate() {
        if let Target::Front(p) = f.target {
            children[next[p]] = c;
            next[p] += 1;
        }
    }
    for (p, f) in fronts.iter_mut().enumerate() {
        f.children = count[p]..count[p + 1];
    }
    children
}

/// A postorder of the fronts: every subtree runs contiguously, children in increasing order. `None`
/// if some front is not reached from a root.
fn postorder(fronts: &[Front], children: &[usize]) -> Option<Vec<usize>> {
    let n_fronts = fronts.len();
    let mut order = Vec::with_capacity(n_fronts);
    let mut path: Vec<(usize, usize)> = Vec::new();
    for root in (0..n_fronts).filter(|&f| !matches!(fronts[f].target, Target::Front(_))) {
        path.push((root, 0));
        while let Some(&mut (f, ref mut k)) = path.last_mut() {
            let kids = fronts[f].children.clone();
            if *k < kids.len() {
                let child = children[kids.start + *k];
                *k += 1;
                path.push((child, 0));
            } else {
                order.push(f);
                path.pop();
            }
        }
    }
    (order.len() == n_fronts).then_some(order)
}

/// Assigns every front its stack and offset, and returns the peak size of each stack. Two stacks, by
/// the parity of the depth: a front's children are the topmost entries of the other stack when it runs
/// (a postorder consumes every deeper update before), and its own update goes on top of its stack, where
/// the product writes it directly. It is popped by the parent, or at once when it goes to the separator.
fn assign_stacks(fronts: &mut [Front], order: &[usize], children: &[usize]) -> [usize; 2] {
    for &f in order.iter().rev() {
        if let Target::Front(p) = fronts[f].target {
            fronts[f].stack = 1 - fronts[p].stack;
        }
    }
    let (mut top, mut peak) = ([0usize; 2], [0usize; 2]);
    for &f in order {
        let (own, other) = (fronts[f].stack, 1 - fronts[f].stack);
        let size = fronts[f].update_rows().pow(2);
        fronts[f].stack_offset = top[own];
        peak[own] = peak[own].max(top[own] + size);
        if let Some(first) = fronts[f].children.clone().map(|c| fronts[children[c]].stack_offset).min() {
            top[other] = first;
        }
        if let Target::Front(_) = fronts[f].target {
            top[own] += size;
        }
    }
    peak
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::dyn_stack::MemBuffer;
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::linalg::cholesky::{
        CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
    };
    use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
    use faer::{Mat, Side};
    use rand::{Rng, SeedableRng};

    /// A symmetric positive definite matrix on a grid of `nx × ny` nodes with three unknowns each,
    /// coupled to the eight neighbouring nodes, as `(row, column, value)` lower entries in AMD order.
    fn grid(nx: usize, ny: usize, seed: u64) -> (usize, Vec<(usize, usize, f64)>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let n = 3 * nx * ny;
        let mut pairs = Vec::new();
        for (x, y) in (0..nx).flat_map(|x| (0..ny).map(move |y| (x, y))) {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1), (1, usize::MAX)] {
                let (x2, y2) = (x + dx, y.wrapping_add(dy));
                if x2 < nx && y2 < ny {
                    pairs.push((x * ny + y, x2 * ny + y2));
                }
            }
        }
        let mut entries = Vec::new();
        let mut diagonal = vec![1.0; n];
        for (a, b) in pairs {
            for (i, j) in (0..3).flat_map(|i| (0..3).map(move |j| (3 * a + i, 3 * b + j))) {
                if a != b || i > j {
                    let v: f64 = rng.random_range(-1.0..1.0);
                    diagonal[i] += v.abs();
                    diagonal[j] += v.abs();
                    entries.push((i.max(j), i.min(j), v));
                }
            }
        }
        entries.extend(diagonal.iter().enumerate().map(|(i, &d)| (i, i, d)));
        // AMD order, so that the elimination tree branches.
        let upper: Vec<(u32, u32)> = entries
            .iter()
            .filter(|e| e.0 != e.1)
            .map(|e| (e.1 as u32, e.0 as u32))
            .collect();
        let mut col_ptr = vec![0usize; n + 1];
        for &(_, c) in &upper {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0usize; upper.len()];
        for &(r, c) in &upper {
            row_idx[next[c as usize]] = r as usize;
            next[c as usize] += 1;
        }
        let structure = SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx);
        let perm = crate::ordering::amd_order(structure.as_ref()).unwrap();
        let mut position = vec![0; n];
        for (new, &old) in perm.iter().enumerate() {
            position[old] = new;
        }
        let permuted = entries
            .into_iter()
            .map(|(i, j, v)| {
                let (pi, pj) = (position[i], position[j]);
                (pi.max(pj), pi.min(pj), v)
            })
            .collect();
        (n, permuted)
    }

    /// The lower pattern (rows sorted), the values in its order and faer's supernodal analysis.
    fn analyse(
        n: usize,
        entries: &[(usize, usize, f64)],
    ) -> (SymbolicSparseColMat<usize>, Vec<f64>, SymbolicCholesky<usize>) {
        let mut sorted: Vec<_> = entries.to_vec();
        sorted.sort_by_key(|e| (e.1, e.0));
        let mut col_ptr = vec![0usize; n + 1];
        for e in &sorted {
            col_ptr[e.1 + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let lower =
            SymbolicSparseColMat::new_checked(n, n, col_ptr.clone(), None, sorted.iter().map(|e| e.0).collect());
        // faer's symbolic analysis reads the transpose as the upper triangle (see two_domain.rs).
        let upper = lower.as_ref().transpose().to_col_major().unwrap();
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(upper.as_ref(), Side::Upper, SymmetricOrdering::Identity, params).unwrap();
        (lower, sorted.iter().map(|e| e.2).collect(), symbolic)
    }

    /// The dense lower factor stored in faer's supernodal layout.
    fn dense(sn: &SymbolicSupernodalCholesky<usize>, l_values: &[f64], n: usize) -> Mat<f64> {
        let mut l = Mat::zeros(n, n);
        for s in 0..sn.n_supernodes() {
            let (begin, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
            let rows: Vec<usize> = (begin..end).chain(sn.supernode(s).pattern().iter().copied()).collect();
            let block = &l_values[sn.col_ptr_for_val()[s]..];
            for j in 0..end - begin {
                for (k, &r) in rows.iter().enumerate().skip(j) {
                    l[(r, begin + j)] = block[j * rows.len() + k];
                }
            }
        }
        l
    }

    #[test]
    fn fronts_give_faers_factor_and_the_separators_update_for_any_split() {
        let (n, entries) = grid(9, 7, 5);
        let (lower, values, symbolic) = analyse(n, &entries);
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            panic!("supernodal analysis expected");
        };
        let mut reference = vec![0.0; symbolic.len_val()];
        let mut mem = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut reference,
                SparseColMatRef::new(lower.as_ref(), &values),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        let l_ref = dense(sn, &reference, n);
        let gather: Vec<usize> = (0..values.len()).collect();
        let mut splits_inside_a_supernode = 0;
        let mut tested_with_branching = false;
        for n_own in [n, n - 1, n - 4, n - 17, n - 40, n / 2] {
            splits_inside_a_supernode += usize::from(n_own < n && !sn.supernode_begin().contains(&n_own));
            let mut fronts = Fronts::try_new(sn, lower.as_ref(), &gather, n_own).expect("faer's supernodes nest");
            tested_with_branching |= fronts.fronts.iter().any(|f| f.children.len() > 1);
            let n_sep = n - n_own;
            let mut l_values = vec![f64::NAN; symbolic.len_val()];
            let mut separator = vec![f64::NAN; n_sep * n_sep];
            // Twice, so that the second run starts from the buffers the first one left.
            for _ in 0..2 {
                fronts.factorise(&values, &mut l_values, &mut separator).unwrap();
            }
            let l = dense(sn, &l_values, n);
            let scale = l_ref.norm_max();
            for j in 0..n_own {
                for i in j..n {
                    let diff = (l[(i, j)] - l_ref[(i, j)]).abs();
                    assert!(diff <= 1e-13 * scale, "n_own {n_own}: L({i}, {j}) differs by {diff:e}");
                }
            }
            // −B Bᵀ from the reference factor's rows below the own columns.
            for k in 0..n_sep {
                for i in k..n_sep {
                    let expected: f64 = -(0..n_own).map(|j| l_ref[(n_own + i, j)] * l_ref[(n_own + k, j)]).sum::<f64>();
                    let got = separator[k * n_sep + i];
                    assert!(
                        (got - expected).abs() <= 1e-12 * scale * scale,
                        "n_own {n_own}: separator ({i}, {k}) is {got}, expected {expected}"
                    );
                }
            }
        }
        assert!(splits_inside_a_supernode > 0, "no split ran through a supernode");
        assert!(tested_with_branching, "no front had two children");
    }

    #[test]
    fn a_non_positive_pivot_is_the_column_that_holds_it() {
        let (n, positive) = grid(6, 6, 7);
        for column in [0, n / 3, n - 5] {
            let mut entries = positive.clone();
            let diagonal = entries.iter_mut().find(|e| e.0 == column && e.1 == column).unwrap();
            diagonal.2 = -100.0;
            let (lower, values, symbolic) = analyse(n, &entries);
            let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
                panic!("supernodal analysis expected");
            };
            let gather: Vec<usize> = (0..values.len()).collect();
            let mut fronts = Fronts::try_new(sn, lower.as_ref(), &gather, n - 3).unwrap();
            let mut l_values = vec![0.0; symbolic.len_val()];
            let mut separator = vec![0.0; 9];
            let result = fronts.factorise(&values, &mut l_values, &mut separator);
            // A pivot in the separator is not this kernel's to find.
            let expected = if column < n - 3 { Err(column) } else { Ok(()) };
            assert_eq!(result, expected, "negative diagonal at {column}");
        }
    }
}

//! Fill-reducing orderings of the symmetric factorisations, and the bisection of the two-domain
//! Cholesky.
//!
//! Shell meshes are two-dimensional: their matrices have small separators (a cut across the mesh), and
//! ordering each separator after the two parts it separates, recursively, gives less fill and larger
//! dense supernodes than minimum degree on large meshes (O(n^1.5) operations). faer 0.24 has AMD but
//! no nested dissection; METIS's ([`crate::metis`]) runs on the *node* graph (blocks of three unknowns
//! that share one sparsity structure). Which of the two a factorisation uses is decided per pattern
//! from the exact operation counts of both ([`whole_order`]): on the plate strips and the closed Bunny
//! surface nested dissection needs 0.5–0.7 of AMD's operations, and more so once contact presses
//! the surface together, but the supernodal kernels run at a lower rate on its orders.
//!
//! [`bisection`] splits the node graph once, with METIS's vertex separator (separate bodies dealt
//! whole to the two sides); the two-domain Cholesky (`two_domain.rs`) factorises the two sides in
//! parallel. A George–Liu level-structure cut stands in if METIS fails.

use crate::error::{LinearSolveError, LinearSolveStage, out_of_memory};
use crate::metis::MetisGraph;
use crate::pattern::UpperPattern;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::simplicial;
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

/// The largest ratio of nested dissection's factor operations to AMD's at which the automatic choices
/// take nested dissection. The supernodal factorisations run at a lower rate on nested-dissection
/// orders (more, smaller fronts below the large separators), so fewer operations alone do not make
/// it faster; below this ratio it was faster on every pattern measured (plate strips and the closed
/// Bunny surface, with and without contact).
pub(crate) const NESTED_DISSECTION_SHARE: f64 = 0.75;

/// Unknowns per node of the node graphs that the automatic choices dissect (three per node for the
/// shells' displacements and rotations, and for the volumes' displacements).
pub(crate) const NODE_BLOCK: usize = 3;

/// The node adjacency (CSR) of a symmetric pattern given by its upper triangle with `block`-sized
/// node blocks.
fn node_graph(pattern: SymbolicSparseColMatRef<'_, usize>, block: usize) -> (Vec<usize>, Vec<u32>) {
    let n_nodes = pattern.ncols() / block;
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    let mut edges: Vec<(usize, usize)> = Vec::new();
    for b in 0..n_nodes {
        // The first column of a block carries the block's off-diagonal structure.
        let j = b * block;
        let mut last = usize::MAX;
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let a = i / block;
            if a != b && a != last {
                edges.push((a, b));
                last = a;
            }
        }
    }
    adjacency(n_nodes, || edges.iter().copied())
}

/// The adjacency (CSR) of the undirected graph on `n_nodes` nodes with the given `edges`, each listed
/// at both its ends in the order of `edges` (repeats kept).
fn adjacency<I: Iterator<Item = (usize, usize)>>(n_nodes: usize, edges: impl Fn() -> I) -> (Vec<usize>, Vec<u32>) {
    let mut ptr = vec![0usize; n_nodes + 1];
    for (a, b) in edges() {
        ptr[a + 1] += 1;
        ptr[b + 1] += 1;
    }
    for v in 0..n_nodes {
        ptr[v + 1] += ptr[v];
    }
    let mut fill = ptr.clone();
    let mut adj = vec![0u32; ptr[n_nodes]];
    for (a, b) in edges() {
        adj[fill[a]] = b as u32;
        fill[a] += 1;
        adj[fill[b]] = a as u32;
        fill[b] += 1;
    }
    (ptr, adj)
}

/// The outcome of one level-structure cut.
enum Cut {
    /// Fewer than three levels: nothing to separate.
    Shallow,
    /// The part is disconnected.
    Disconnected,
    /// `separator` separates `a` from `b`: no edge joins them.
    Separated {
        a: Vec<usize>,
        b: Vec<usize>,
        separator: Vec<usize>,
    },
}

struct Dissector<'a> {
    ptr: &'a [usize],
    adj: &'a [u32],
    /// Part label of each node during the recursion (`u32::MAX` = ordered or in a separator).
    part: Vec<u32>,
    level: Vec<u32>,
    /// Visit stamps of the breadth-first searches.
    mark: Vec<u32>,
    stamp: u32,
}

impl<'a> Dissector<'a> {
    /// A dissector of the node graph `(ptr, adj)` (CSR) with every node in part 0.
    fn new(ptr: &'a [usize], adj: &'a [u32]) -> Self {
        let n_nodes = ptr.len() - 1;
        Self {
            ptr,
            adj,
            part: vec![0; n_nodes],
            level: vec![0; n_nodes],
            mark: vec![0; n_nodes],
            stamp: 0,
        }
    }

    /// Breadth-first levels from `root` within the part `label`; returns the visited nodes in BFS order
    /// (levels in `self.level`, visited nodes marked with the current stamp).
    fn bfs(&mut self, root: usize, label: u32) -> Vec<usize> {
        let (ptr, adj) = (self.ptr, self.adj);
        self.stamp += 1;
        let s = self.stamp;
        self.mark[root] = s;
        self.level[root] = 0;
        let mut queue = vec![root];
        let mut head = 0;
        while head < queue.len() {
            let v = queue[head];
            head += 1;
            for &w in &adj[ptr[v]..ptr[v + 1]] {
                let w = w as usize;
                if self.part[w] == label && self.mark[w] != s {
                    self.mark[w] = s;
                    self.level[w] = self.level[v] + 1;
                    queue.push(w);
                }
            }
        }
        queue
    }

    /// Splits the connected part `label` (`nodes` lists it) at the middle breadth-first level from a
    /// pseudo-peripheral node. Leaves labels unchanged.
    fn cut(&mut self, nodes: &[usize], label: u32) -> Cut {
        let mut root = nodes[0];
        let mut visited = self.bfs(root, label);
        if visited.len() < nodes.len() {
            return Cut::Disconnected;
        }
        // Pseudo-peripheral root: restart from the farthest node while the depth grows.
        for _ in 0..4 {
            let far = *visited.last().unwrap_or(&root);
            let depth = self.level[far];
            let again = self.bfs(far, label);
            if self.level[*again.last().unwrap_or(&far)] <= depth {
                visited = self.bfs(root, label);
                break;
            }
            root = far;
            visited = again;
        }
        let depth = self.level[*visited.last().unwrap_or(&root)];
        if depth < 2 {
            return Cut::Shallow;
        }
        // The level holding the median node (by BFS order) is the separator.
        let cut = self.level[visited[visited.len() / 2]].clamp(1, depth - 1);
        let (mut a, mut b, mut sep) = (Vec::new(), Vec::new(), Vec::new());
        for &v in &visited {
            match self.level[v].cmp(&cut) {
                std::cmp::Ordering::Less => a.push(v),
                std::cmp::Ordering::Greater => b.push(v),
                std::cmp::Ordering::Equal => sep.push(v),
            }
        }
        // Thin the separator: a cut-level node with no neighbour beyond the cut joins part `a`.
        let (ptr, adj) = (self.ptr, self.adj);
        let mut separator = Vec::with_capacity(sep.len());
        for v in sep {
            let touches_b = adj[ptr[v]..ptr[v + 1]]
                .iter()
                .any(|&w| self.part[w as usize] == label && self.level[w as usize] == cut + 1);
            if touches_b { separator.push(v) } else { a.push(v) }
        }
        Cut::Separated { a, b, separator }
    }
}

/// METIS's nested-dissection permutation of the unknowns of a pattern whose unknowns come in node
/// blocks of `block` (`perm[new] = old`). Returns `None` if the size is not a multiple of `block` or
/// METIS cannot order the graph.
pub(crate) fn nested_dissection(pattern: SymbolicSparseColMatRef<'_, usize>, block: usize) -> Option<Vec<usize>> {
    let n = pattern.ncols();
    if block == 0 || n % block != 0 {
        return None;
    }
    let (ptr, adj) = node_graph(pattern, block);
    let nodes = MetisGraph::new(&ptr, &adj)?.nested_dissection()?;
    Some(nodes.iter().flat_map(|&v| (0..block).map(move |c| v * block + c)).collect())
}

/// METIS's nested-dissection permutation (`perm[new] = old`) of the unknowns `0..n` of a symmetric
/// matrix with off-diagonal `pairs`, on node blocks of [`NODE_BLOCK`] unknowns. `None` if `n` is not
/// a multiple of the block or METIS cannot order the graph.
pub(crate) fn nested_dissection_of_pairs(n: usize, pairs: &[(u32, u32)]) -> Option<Vec<usize>> {
    if !n.is_multiple_of(NODE_BLOCK) {
        return None;
    }
    let (ptr, adj) = node_graph_of_pairs(n / NODE_BLOCK, pairs);
    let nodes = MetisGraph::new(&ptr, &adj)?.nested_dissection()?;
    Some(
        nodes
            .iter()
            .flat_map(|&v| (0..NODE_BLOCK).map(move |c| v * NODE_BLOCK + c))
            .collect(),
    )
}

/// The node adjacency (CSR, each list ascending) of the symmetric matrix with off-diagonal `pairs`
/// on `n_nodes` node blocks of [`NODE_BLOCK`] unknowns. A pair of nodes is coupled by up to
/// `NODE_BLOCK²` pairs of unknowns: the lists are gathered with their repeats, which a marker per
/// neighbour drops node by node, so only the short deduplicated lists are sorted.
fn node_graph_of_pairs(n_nodes: usize, pairs: &[(u32, u32)]) -> (Vec<usize>, Vec<u32>) {
    let node = |u: u32| (u / NODE_BLOCK as u32) as usize;
    let (start, repeated) = adjacency(n_nodes, || {
        pairs.iter().map(|&(r, c)| (node(r), node(c))).filter(|(a, b)| a != b)
    });
    let mut seen_by = vec![usize::MAX; n_nodes];
    let mut ptr = Vec::with_capacity(n_nodes + 1);
    ptr.push(0);
    let mut adj = Vec::new();
    for v in 0..n_nodes {
        let first = adj.len();
        for &w in &repeated[start[v]..start[v + 1]] {
            if seen_by[w as usize] != v {
                seen_by[w as usize] = v;
                adj.push(w);
            }
        }
        adj[first..].sort_unstable();
        ptr.push(adj.len());
    }
    (ptr, adj)
}

/// A vertex bisection of the node graph: two parts that no matrix entry couples, and the separator.
/// Unknown indices are those of the pattern (all `block` unknowns of a node together), each list
/// sorted.
#[derive(Debug, Clone)]
pub(crate) struct Bisection {
    pub(crate) parts: [Vec<usize>; 2],
    pub(crate) separator: Vec<usize>,
}

/// A balanced vertex bisection of the node graph. Connected components (separate bodies) are dealt
/// to the lighter part whole, with no separator between them; a component holding more than half of
/// the nodes is first cut at the middle level of its level structure (the first step of
/// [`nested_dissection`]) and the other components join the lighter of its two sides. `None` if the
/// size is not a multiple of `block` or the graph has a single node's depth.
pub(crate) fn bisection(pattern: SymbolicSparseColMatRef<'_, usize>, block: usize) -> Option<Bisection> {
    let n = pattern.ncols();
    if block == 0 || n % block != 0 || n == 0 {
        return None;
    }
    let (ptr, adj) = node_graph(pattern, block);
    let n_nodes = n / block;
    let mut d = Dissector::new(&ptr, &adj);
    // Connected components, largest first (ties by first node, so the result is deterministic).
    let mut seen = vec![false; n_nodes];
    let mut components: Vec<Vec<usize>> = Vec::new();
    for start in 0..n_nodes {
        if !seen[start] {
            let component = d.bfs(start, 0);
            for &v in &component {
                seen[v] = true;
            }
            components.push(component);
        }
    }
    components.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
    let mut rest = components.into_iter();
    let largest = rest.next()?;
    let (mut a, mut b, separator) = if 2 * largest.len() > n_nodes {
        match metis_separator(&ptr, &adj, &largest).map_or_else(|| d.cut(&largest, 0), Cut::from) {
            Cut::Separated { a, b, separator } => (a, b, separator),
            Cut::Shallow | Cut::Disconnected => return None,
        }
    } else {
        (largest, Vec::new(), Vec::new())
    };
    for component in rest {
        if a.len() <= b.len() {
            a.extend(component);
        } else {
            b.extend(component);
        }
    }
    let unknowns = |mut nodes: Vec<usize>| {
        nodes.sort_unstable();
        nodes
            .iter()
            .flat_map(|&v| (0..block).map(move |c| v * block + c))
            .collect::<Vec<_>>()
    };
    Some(Bisection {
        parts: [unknowns(a), unknowns(b)],
        separator: unknowns(separator),
    })
}

/// METIS's vertex separator of the connected subgraph on `nodes`: the two sides and the separator.
fn metis_separator(ptr: &[usize], adj: &[u32], nodes: &[usize]) -> Option<[Vec<usize>; 3]> {
    let part = MetisGraph::induced(ptr, adj, nodes)?.vertex_separator()?;
    let mut sides: [Vec<usize>; 3] = Default::default();
    for (&v, &p) in nodes.iter().zip(&part) {
        sides[usize::from(p)].push(v);
    }
    (!sides[0].is_empty() && !sides[1].is_empty()).then_some(sides)
}

impl From<[Vec<usize>; 3]> for Cut {
    fn from([a, b, separator]: [Vec<usize>; 3]) -> Self {
        Cut::Separated { a, b, separator }
    }
}

/// The upper structure (each pair stored once at `(min, max)`, plus the diagonal) of an `n × n`
/// symmetric matrix with the given off-diagonal pairs, rows unsorted.
pub(crate) fn upper_structure(n: usize, pairs: &[(u32, u32)]) -> SymbolicSparseColMat<usize> {
    let mut col_ptr = vec![0usize; n + 1];
    for &(r, c) in pairs {
        col_ptr[r.max(c) as usize + 1] += 1;
    }
    for c in 0..n {
        col_ptr[c + 1] += col_ptr[c] + 1;
    }
    let mut next: Vec<usize> = col_ptr[..n].to_vec();
    let mut row_idx = vec![0usize; col_ptr[n]];
    for (c, slot) in next.iter_mut().enumerate() {
        row_idx[*slot] = c;
        *slot += 1;
    }
    for &(r, c) in pairs {
        let (lo, hi) = (r.min(c) as usize, r.max(c) as usize);
        row_idx[next[hi]] = lo;
        next[hi] += 1;
    }
    SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx)
}

/// `Σ c_j²` of the Cholesky factor of the symmetric matrix with off-diagonal `pairs` (local
/// numbering) factorised in `order`, from its column counts.
pub(crate) fn factor_operations(order: &[usize], pairs: &[(u32, u32)]) -> Result<f64, LinearSolveError> {
    let m = order.len();
    let mut position = vec![0u32; m];
    for (k, &l) in order.iter().enumerate() {
        position[l] = k as u32;
    }
    let permuted: Vec<(u32, u32)> = pairs
        .iter()
        .map(|&(r, c)| (position[r as usize], position[c as usize]))
        .collect();
    let upper = upper_structure(m, &permuted);
    drop(permuted);
    let mut etree = vec![0isize; m];
    let mut counts = vec![0usize; m];
    let nnz = upper.row_idx().len();
    let mut mem = MemBuffer::try_new(simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(m, nnz))
        .map_err(|_| out_of_memory())?;
    simplicial::prefactorize_symbolic_cholesky(&mut etree, &mut counts, upper.as_ref(), MemStack::new(&mut mem));
    Ok(counts.iter().map(|&c| (c as f64) * (c as f64)).sum())
}

/// The off-diagonal entries of a pattern as `(row, column)` pairs.
pub(crate) fn off_diagonal_pairs(pattern: &UpperPattern) -> Vec<(u32, u32)> {
    pattern
        .row_idx()
        .iter()
        .zip(pattern.col_idx())
        .filter(|(r, c)| r != c)
        .map(|(&r, &c)| (r as u32, c as u32))
        .collect()
}

/// The fill-reducing order of the whole matrix (`perm[new] = old`) that [`FillOrdering::Auto`] uses,
/// with its factor's operations `Σ c_j²`: AMD's or, with `nested_dissection`, METIS's nested
/// dissection on node blocks of [`NODE_BLOCK`] unknowns, nested dissection if its factor needs at most
/// [`NESTED_DISSECTION_SHARE`] of AMD's operations (exact column counts, in near-linear time).
/// Nested dissection wins on large meshes and on surfaces pressed together by contact; AMD on small
/// and on strip-like meshes.
///
/// [`FillOrdering::Auto`]: crate::FillOrdering::Auto
pub(crate) fn whole_order(
    pattern: &UpperPattern,
    nested_dissection: bool,
) -> Result<(Vec<usize>, f64), LinearSolveError> {
    let pairs = off_diagonal_pairs(pattern);
    let amd = amd_order(pattern.as_ref())?;
    let amd_operations = factor_operations(&amd, &pairs)?;
    if nested_dissection && let Some(nd) = nested_dissection_of_pairs(pattern.n(), &pairs) {
        let nd_operations = factor_operations(&nd, &pairs)?;
        if nd_operations <= NESTED_DISSECTION_SHARE * amd_operations {
            return Ok((nd, nd_operations));
        }
    }
    Ok((amd, amd_operations))
}

/// faer's AMD ordering (`perm[new] = old`) of the symmetric pattern `upper` (one triangle suffices).
pub(crate) fn amd_order(upper: SymbolicSparseColMatRef<'_, usize>) -> Result<Vec<usize>, LinearSolveError> {
    let n = upper.ncols();
    let mut perm = vec![0usize; n];
    if n == 0 {
        return Ok(perm);
    }
    let mut perm_inv = vec![0usize; n];
    let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, upper.row_idx().len()))
        .map_err(|_| out_of_memory())?;
    amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        upper,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|source| LinearSolveError::Faer {
        stage: LinearSolveStage::SymmetricSymbolic,
        source,
    })?;
    Ok(perm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::SymbolicSparseColMat;

    /// The upper pattern of a 5-point Laplacian on an `m × m` grid with `block` unknowns per node.
    fn grid(m: usize, block: usize) -> SymbolicSparseColMat<usize> {
        let n = m * m;
        let mut col_ptr = vec![0];
        let mut rows = Vec::new();
        for b in 0..n {
            let (i, j) = (b % m, b / m);
            let mut nbrs = vec![b];
            if i > 0 {
                nbrs.push(b - 1);
            }
            if j > 0 {
                nbrs.push(b - m);
            }
            nbrs.sort_unstable();
            for c in 0..block {
                for &a in &nbrs {
                    let last = if a == b { c + 1 } else { block };
                    rows.extend((0..last).map(|r| a * block + r));
                }
                col_ptr.push(rows.len());
            }
        }
        SymbolicSparseColMat::new_checked(n * block, n * block, col_ptr, None, rows)
    }

    /// The node graph of scalar pairs equals the one from sorting and deduplicating every node pair:
    /// each node's neighbours once, ascending, whatever the order and repetition of the pairs.
    #[test]
    fn node_graph_of_pairs_lists_each_neighbour_once_in_order() {
        let g = grid(4, NODE_BLOCK);
        let mut pairs: Vec<(u32, u32)> = (0..g.ncols())
            .flat_map(|c| g.row_idx_of_col(c).filter(move |&r| r != c).map(move |r| (r as u32, c as u32)))
            .collect();
        pairs.reverse();
        pairs.extend_from_within(..10);
        let n_nodes = g.ncols() / NODE_BLOCK;
        let (ptr, adj) = node_graph_of_pairs(n_nodes, &pairs);
        let node = |u: u32| u / NODE_BLOCK as u32;
        let mut edges: Vec<(u32, u32)> = pairs
            .iter()
            .filter(|&&(r, c)| node(r) != node(c))
            .flat_map(|&(r, c)| [(node(r), node(c)), (node(c), node(r))])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let listed: Vec<(u32, u32)> = (0..n_nodes)
            .flat_map(|v| adj[ptr[v]..ptr[v + 1]].iter().map(move |&w| (v as u32, w)))
            .collect();
        assert_eq!(listed, edges);
        // An interior node of the 4 × 4 grid has four neighbours.
        assert_eq!(ptr[6] - ptr[5], 4);
    }

    #[test]
    fn ordering_is_a_permutation_that_keeps_blocks_together() {
        let g = grid(30, 3);
        let perm = nested_dissection(g.as_ref(), 3).unwrap();
        let mut seen = vec![false; perm.len()];
        for &p in &perm {
            assert!(!seen[p]);
            seen[p] = true;
        }
        assert!(seen.iter().all(|&s| s));
        for chunk in perm.chunks(3) {
            assert_eq!((chunk[0] % 3, chunk[1], chunk[2]), (0, chunk[0] + 1, chunk[0] + 2));
        }
        assert!(nested_dissection(g.as_ref(), 7).is_none()); // 2700 unknowns are not 7-blocks
    }

    /// Whether any stored entry couples the two parts.
    fn parts_coupled(g: &SymbolicSparseColMat<usize>, b: &Bisection) -> bool {
        let mut part = vec![2u8; g.ncols()];
        for (p, unknowns) in b.parts.iter().enumerate() {
            for &u in unknowns {
                part[u] = p as u8;
            }
        }
        (0..g.ncols()).any(|c| g.row_idx_of_col(c).any(|r| part[r] + part[c] == 1))
    }

    #[test]
    fn bisection_separates_balanced_parts_and_deals_out_separate_bodies() {
        let g = grid(30, 3);
        let b = bisection(g.as_ref(), 3).unwrap();
        let mut all: Vec<usize> = b.parts.iter().flatten().chain(&b.separator).copied().collect();
        all.sort_unstable();
        assert_eq!(all, (0..g.ncols()).collect::<Vec<_>>());
        assert!(!parts_coupled(&g, &b));
        let (a, c) = (b.parts[0].len(), b.parts[1].len());
        assert!(a.min(c) * 3 >= a.max(c), "unbalanced parts {a} and {c}");
        // A cut of a 30 × 30 grid needs at least 30 nodes and a level set has at most 59.
        assert!(
            (90..=3 * 59).contains(&b.separator.len()),
            "separator {}",
            b.separator.len()
        );

        // Two copies of a grid side by side: one body per part, nothing to separate.
        let n = g.ncols();
        let col_ptr: Vec<usize> = g
            .col_ptr()
            .iter()
            .chain(&g.col_ptr()[1..].iter().map(|p| p + g.col_ptr()[n]).collect::<Vec<_>>())
            .copied()
            .collect();
        let rows: Vec<usize> = g.row_idx().iter().copied().chain(g.row_idx().iter().map(|r| r + n)).collect();
        let twice = SymbolicSparseColMat::new_checked(2 * n, 2 * n, col_ptr, None, rows);
        let b = bisection(twice.as_ref(), 3).unwrap();
        assert!(b.separator.is_empty());
        assert_eq!((b.parts[0].len(), b.parts[1].len()), (n, n));
        assert!(!parts_coupled(&twice, &b));
    }

    /// The upper pattern of a 7-point Laplacian on an `m × m × m` grid with three unknowns per node
    /// (a closed surface pressed together by contact is nearly three-dimensional).
    fn grid3(m: usize) -> SymbolicSparseColMat<usize> {
        let id = |i: usize, j: usize, k: usize| (i * m + j) * m + k;
        let n = m * m * m;
        let mut col_ptr = vec![0];
        let mut rows = Vec::new();
        for b in 0..n {
            let (i, j, k) = (b / (m * m), (b / m) % m, b % m);
            let mut nbrs = vec![b];
            if i > 0 {
                nbrs.push(id(i - 1, j, k));
            }
            if j > 0 {
                nbrs.push(id(i, j - 1, k));
            }
            if k > 0 {
                nbrs.push(id(i, j, k - 1));
            }
            nbrs.sort_unstable();
            for c in 0..3 {
                for &a in &nbrs {
                    let last = if a == b { c + 1 } else { 3 };
                    rows.extend((0..last).map(|d| 3 * a + d));
                }
                col_ptr.push(rows.len());
            }
        }
        SymbolicSparseColMat::new_checked(3 * n, 3 * n, col_ptr, None, rows)
    }

    #[test]
    fn automatic_order_takes_nested_dissection_where_it_needs_far_fewer_operations() {
        let operations = |g: SymbolicSparseColMat<usize>| {
            let pattern = UpperPattern::try_new(g.as_ref()).unwrap();
            let pairs = off_diagonal_pairs(&pattern);
            let amd = factor_operations(&amd_order(g.as_ref()).unwrap(), &pairs).unwrap();
            let nd = factor_operations(&nested_dissection(g.as_ref(), 3).unwrap(), &pairs).unwrap();
            let (order, chosen) = whole_order(&pattern, true).unwrap();
            assert_eq!(factor_operations(&order, &pairs).unwrap(), chosen);
            (amd, nd, chosen)
        };
        // In three dimensions nested dissection's separators (n^(2/3)) beat minimum degree by far.
        let (amd, nd, chosen) = operations(grid3(20));
        assert!(
            nd <= NESTED_DISSECTION_SHARE * amd,
            "nested dissection {nd:e}, AMD {amd:e}"
        );
        assert_eq!(chosen, nd);
        // On a two-dimensional grid AMD is about as good: the automatic order keeps it unless nested
        // dissection saves a quarter.
        let (amd, nd, chosen) = operations(grid(40, 3));
        assert!(nd > 0.5 * amd, "nested dissection {nd:e}, AMD {amd:e}");
        assert_eq!(chosen, if nd <= NESTED_DISSECTION_SHARE * amd { nd } else { amd });
    }
}

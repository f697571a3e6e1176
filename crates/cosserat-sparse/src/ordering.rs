//! Nested-dissection fill-reducing ordering for the symmetric factorisations.
//!
//! Shell meshes are two-dimensional: their matrices have small separators (a cut across the mesh), and
//! ordering each separator after the two parts it separates, recursively, gives far less fill and far
//! larger dense supernodes than minimum degree on large meshes (O(n^1.5) operations). faer 0.24 has no
//! nested dissection, so this module computes one on the *node* graph (blocks of `block` unknowns that
//! share one sparsity structure, three per node here) with George–Liu level-structure bisection: from a
//! pseudo-peripheral node, breadth-first levels are cut at the middle level, which becomes the
//! separator. Small parts are ordered by reverse Cuthill–McKee, which keeps their factors banded.
//!
//! The first cut alone ([`bisection`], with separate bodies dealt whole to the two sides) is what the
//! two-domain Cholesky (`two_domain.rs`) factorises in parallel.
//!
//! Measured on the plate-under-load strips (Tri6/Tri3, docs/performance.md), this ordering needs about
//! 1.4× the operations of faer's AMD: breadth-first level sets of a mesh whose elements are 9-node
//! cliques are thicker and more oblique than the best geometric cuts, and AMD is already close to
//! optimal on these strips. AMD therefore stays the default; nested dissection is kept as an option for
//! comparisons and for meshes where it wins.

use faer::sparse::SymbolicSparseColMatRef;

/// Parts with at most this many nodes are not dissected further.
const LEAF: usize = 16;

/// The node adjacency (CSR) of a symmetric pattern given by its upper triangle with `block`-sized
/// node blocks.
fn node_graph(pattern: SymbolicSparseColMatRef<'_, usize>, block: usize) -> (Vec<usize>, Vec<u32>) {
    let n_nodes = pattern.ncols() / block;
    let mut degree = vec![0usize; n_nodes];
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for b in 0..n_nodes {
        // The first column of a block carries the block's off-diagonal structure.
        let j = b * block;
        let mut last = usize::MAX;
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let a = i / block;
            if a != b && a != last {
                edges.push((a as u32, b as u32));
                degree[a] += 1;
                degree[b] += 1;
                last = a;
            }
        }
    }
    let mut ptr = vec![0usize; n_nodes + 1];
    for v in 0..n_nodes {
        ptr[v + 1] = ptr[v] + degree[v];
    }
    let mut fill = ptr.clone();
    let mut adj = vec![0u32; ptr[n_nodes]];
    for (a, b) in edges {
        adj[fill[a as usize]] = b;
        fill[a as usize] += 1;
        adj[fill[b as usize]] = a;
        fill[b as usize] += 1;
    }
    (ptr, adj)
}

/// The outcome of one level-structure cut.
enum Cut {
    /// Fewer than three levels: nothing to separate.
    Shallow,
    /// The part is disconnected: one component and the rest.
    Components(Vec<usize>, Vec<usize>),
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
    order: Vec<usize>,
    next_label: u32,
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
            order: Vec::with_capacity(n_nodes),
            next_label: 0,
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

    /// Orders the nodes of part `label` (`nodes` lists them) and appends them to `order`.
    fn dissect(&mut self, nodes: Vec<usize>, label: u32) {
        if nodes.len() <= LEAF {
            self.order_leaf(&nodes, label);
            return;
        }
        match self.cut(&nodes, label) {
            Cut::Shallow => self.order_leaf(&nodes, label),
            Cut::Components(visited, rest) => {
                let (a, b) = (self.relabel(&visited), self.relabel(&rest));
                self.dissect(visited, a);
                self.dissect(rest, b);
            }
            Cut::Separated { a, b, separator } => {
                for &v in &separator {
                    self.part[v] = u32::MAX;
                }
                let (la, lb) = (self.relabel(&a), self.relabel(&b));
                self.dissect(a, la);
                self.dissect(b, lb);
                self.order.extend(separator);
            }
        }
    }

    /// Splits the connected part `label` (`nodes` lists it) at the middle breadth-first level from a
    /// pseudo-peripheral node. Leaves labels unchanged.
    fn cut(&mut self, nodes: &[usize], label: u32) -> Cut {
        let mut root = nodes[0];
        let mut visited = self.bfs(root, label);
        if visited.len() < nodes.len() {
            let s = self.stamp;
            let rest: Vec<usize> = nodes.iter().copied().filter(|&v| self.mark[v] != s).collect();
            return Cut::Components(visited, rest);
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

    fn relabel(&mut self, nodes: &[usize]) -> u32 {
        self.next_label += 1;
        for &v in nodes {
            self.part[v] = self.next_label;
        }
        self.next_label
    }

    /// Reverse Cuthill–McKee order of a small part.
    fn order_leaf(&mut self, nodes: &[usize], label: u32) {
        let mut local = Vec::with_capacity(nodes.len());
        for &start in nodes {
            if self.part[start] == label {
                let visited = self.bfs(start, label);
                for &v in &visited {
                    self.part[v] = u32::MAX;
                }
                local.extend(visited);
            }
        }
        local.reverse();
        self.order.extend(local);
    }
}

/// A nested-dissection permutation of the unknowns of a pattern whose unknowns come in node blocks of
/// `block` (`perm[new] = old`). Returns `None` if the size is not a multiple of `block`.
pub(crate) fn nested_dissection(pattern: SymbolicSparseColMatRef<'_, usize>, block: usize) -> Option<Vec<usize>> {
    let n = pattern.ncols();
    if block == 0 || n % block != 0 {
        return None;
    }
    let (ptr, adj) = node_graph(pattern, block);
    let n_nodes = n / block;
    let mut d = Dissector::new(&ptr, &adj);
    d.dissect((0..n_nodes).collect(), 0);
    debug_assert_eq!(d.order.len(), n_nodes);
    Some(d.order.iter().flat_map(|&v| (0..block).map(move |c| v * block + c)).collect())
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
        match d.cut(&largest, 0) {
            Cut::Separated { a, b, separator } => (a, b, separator),
            Cut::Shallow | Cut::Components(..) => return None,
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
}

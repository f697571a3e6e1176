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

impl Dissector<'_> {
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
        let mut root = nodes[0];
        let mut visited = self.bfs(root, label);
        if visited.len() < nodes.len() {
            // Disconnected part: order each component on its own.
            let s = self.stamp;
            let rest: Vec<usize> = nodes.iter().copied().filter(|&v| self.mark[v] != s).collect();
            let (a, b) = (self.relabel(&visited), self.relabel(&rest));
            self.dissect(visited, a);
            self.dissect(rest, b);
            return;
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
            self.order_leaf(&nodes, label);
            return;
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
        let mut kept = Vec::with_capacity(sep.len());
        for v in sep {
            let touches_b = adj[ptr[v]..ptr[v + 1]]
                .iter()
                .any(|&w| self.part[w as usize] == label && self.level[w as usize] == cut + 1);
            if touches_b { kept.push(v) } else { a.push(v) }
        }
        for &v in &kept {
            self.part[v] = u32::MAX;
        }
        let (la, lb) = (self.relabel(&a), self.relabel(&b));
        self.dissect(a, la);
        self.dissect(b, lb);
        self.order.extend(kept);
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
    let mut d = Dissector {
        ptr: &ptr,
        adj: &adj,
        part: vec![0; n_nodes],
        level: vec![0; n_nodes],
        mark: vec![0; n_nodes],
        stamp: 0,
        order: Vec::with_capacity(n_nodes),
        next_label: 0,
    };
    d.dissect((0..n_nodes).collect(), 0);
    debug_assert_eq!(d.order.len(), n_nodes);
    Some(d.order.iter().flat_map(|&v| (0..block).map(move |c| v * block + c)).collect())
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
}

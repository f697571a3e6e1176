//! METIS's multilevel graph algorithms on a node graph: nested-dissection orderings and vertex
//! separators.
//!
//! Multilevel coarsening with refinement finds far smaller separators than a level structure on the
//! irregular surfaces of real scenes, and a closed surface pressed together by contact is nearly
//! three-dimensional, where a good separator matters most. The `metis` crate wraps METIS's
//! partitioning only, so the two routines used here are called through its system bindings
//! (`metis-sys`, which builds the vendored METIS). METIS's default options use a fixed random seed:
//! the same graph gives the same result on every run and for any number of threads.

use metis_sys::{METIS_NOPTIONS, idx_t, rstatus_et_METIS_OK};

/// An undirected graph in compressed rows with METIS's 32-bit indices (no self loops, each edge in
/// both rows).
#[derive(Debug, Clone)]
pub(crate) struct MetisGraph {
    xadj: Vec<idx_t>,
    adjncy: Vec<idx_t>,
}

impl MetisGraph {
    /// The graph of the rows `ptr` and adjacency `adj` (as [`crate::ordering`]'s node graph), or
    /// `None` if it is empty or too large for 32-bit indices.
    pub(crate) fn new(ptr: &[usize], adj: &[u32]) -> Option<Self> {
        let n = ptr.len().checked_sub(1).filter(|&n| n > 0)?;
        idx_t::try_from(n).ok()?;
        let xadj = ptr.iter().map(|&p| idx_t::try_from(p).ok()).collect::<Option<Vec<_>>>()?;
        let adjncy = adj.iter().map(|&a| idx_t::try_from(a).ok()).collect::<Option<Vec<_>>>()?;
        Some(Self { xadj, adjncy })
    }

    /// The subgraph induced by `nodes` (renumbered in the given order).
    pub(crate) fn induced(ptr: &[usize], adj: &[u32], nodes: &[usize]) -> Option<Self> {
        let mut local = vec![u32::MAX; ptr.len() - 1];
        for (l, &v) in nodes.iter().enumerate() {
            local[v] = l as u32;
        }
        let mut sub_ptr = Vec::with_capacity(nodes.len() + 1);
        let mut sub_adj = Vec::new();
        sub_ptr.push(0);
        for &v in nodes {
            sub_adj.extend(
                adj[ptr[v]..ptr[v + 1]]
                    .iter()
                    .map(|&w| local[w as usize])
                    .filter(|&w| w != u32::MAX),
            );
            sub_ptr.push(sub_adj.len());
        }
        Self::new(&sub_ptr, &sub_adj)
    }

    fn n(&self) -> usize {
        self.xadj.len() - 1
    }

    /// A fill-reducing nested-dissection order of the nodes (`perm[new] = old`), or `None` if METIS
    /// fails.
    pub(crate) fn nested_dissection(&self) -> Option<Vec<usize>> {
        let n = self.n();
        let (mut perm, mut iperm) = (vec![0; n], vec![0; n]);
        let (mut xadj, mut adjncy) = (self.xadj.clone(), self.adjncy.clone());
        let status = node_nd(&mut xadj, &mut adjncy, &mut perm, &mut iperm);
        (status == rstatus_et_METIS_OK).then(|| perm.iter().map(|&v| v as usize).collect())
    }

    /// A vertex separator: each node's side (0 or 1) or 2 for the separator, or `None` if METIS fails.
    pub(crate) fn vertex_separator(&self) -> Option<Vec<u8>> {
        let n = self.n();
        let mut part = vec![0; n];
        let (mut xadj, mut adjncy) = (self.xadj.clone(), self.adjncy.clone());
        let status = compute_vertex_separator(&mut xadj, &mut adjncy, &mut part);
        (status == rstatus_et_METIS_OK).then(|| part.iter().map(|&p| p.clamp(0, 2) as u8).collect())
    }
}

fn default_options() -> [idx_t; METIS_NOPTIONS as usize] {
    // METIS reads -1 as "the default" for every option.
    [-1; METIS_NOPTIONS as usize]
}

/// `METIS_NodeND`.
#[allow(unsafe_code)]
fn node_nd(xadj: &mut [idx_t], adjncy: &mut [idx_t], perm: &mut [idx_t], iperm: &mut [idx_t]) -> i32 {
    let n = xadj.len() - 1;
    assert!(perm.len() == n && iperm.len() == n && xadj[n] as usize == adjncy.len());
    let mut nvtxs = n as idx_t;
    let mut options = default_options();
    // SAFETY: METIS reads `nvtxs + 1` offsets ending at the adjacency's length and the adjacency
    // entries, all node indices below `nvtxs` ([`MetisGraph`] is built so); it writes `nvtxs` entries of
    // `perm` and `iperm`; the options array has `METIS_NOPTIONS` entries; no vertex weights (null).
    unsafe {
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    }
}

/// `METIS_ComputeVertexSeparator`.
#[allow(unsafe_code)]
fn compute_vertex_separator(xadj: &mut [idx_t], adjncy: &mut [idx_t], part: &mut [idx_t]) -> i32 {
    let n = xadj.len() - 1;
    assert!(part.len() == n && xadj[n] as usize == adjncy.len());
    let mut nvtxs = n as idx_t;
    let mut options = default_options();
    let mut sepsize: idx_t = 0;
    // SAFETY: as in `node_nd`; METIS writes `sepsize` and `nvtxs` entries of `part`.
    unsafe {
        metis_sys::METIS_ComputeVertexSeparator(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            &mut sepsize,
            part.as_mut_ptr(),
        )
    }
}

//! Candidate pairs kept between broad phases while the motion stays inside the boxes they were found
//! for.
//!
//! A step asks for candidate pairs many times over motions that differ little: the predicted sweep at
//! the start of the step, one CCD step bound per Newton iteration and line-search extension, the
//! coverage check of the converged state, the obstacles' motion fractions. The cache keeps, for each
//! contact vertex, a reference box (the hull of its positions in the motion that last queried the
//! hierarchies, grown by a margin), and the pairs whose primitives' reference boxes, inflated for the
//! largest reach it serves, overlap. For a motion `start → end` whose vertices all stay inside their
//! reference boxes, each primitive's swept box lies inside its inflated reference box (also in
//! floating point: rounding is monotone), so every pair whose swept boxes overlap is among the kept
//! pairs. The answer is the kept pairs whose swept boxes overlap: exactly the list [`candidate_pairs`]
//! returns (same boxes, same test, same sorted order). The candidate sets, and with them every
//! trajectory, are therefore the same as with a broad phase per query; only the cost changes.
//!
//! A motion that leaves the reference boxes queries the hierarchies again with boxes around its own
//! motion, grown by a margin of a fraction of its largest displacement, clamped between a small and a
//! large fraction of the median edge length (the number of kept pairs grows quickly once the margin
//! exceeds the spacing of the mesh). The hierarchies are refitted (same topology, new boxes) instead of
//! rebuilt, unless refitting has made their surface-area cost grow too much.

use crate::broad_phase::{CandidatePairs, PrimitiveBoxes, candidate_pairs, overlapping_pairs};
use crate::bvh::Bvh;
use crate::mesh::ContactMesh;
use cosserat_assembly::Parallelism;
use nalgebra::Vector3;
use rayon::prelude::*;

/// The margin of a re-query is this fraction of the largest displacement of the motion that caused it,
/// so that Newton iterates overshooting the motion a little stay inside.
const MARGIN_PER_DISPLACEMENT: f64 = 0.05;
/// The smallest margin, as a fraction of the median edge length.
const MIN_MARGIN_PER_EDGE: f64 = 0.1;
/// The largest margin, as a fraction of the median edge length.
const MAX_MARGIN_PER_EDGE: f64 = 0.5;
/// A refitted hierarchy whose surface-area cost grew beyond this factor of its build's is rebuilt.
const REBUILD_AREA_RATIO: f64 = 2.0;

/// Counters of the cache.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CacheCounters {
    /// Candidate queries answered.
    pub queries: usize,
    /// Queries that needed a new query of the hierarchies (the motion left the margin).
    pub requeries: usize,
    /// Of those, hierarchies built from scratch (the others were refitted).
    pub builds: usize,
    /// Queries answered by an uncached broad phase (a reach beyond the cache's).
    pub uncached: usize,
}

/// The hierarchies of the last re-query and the surface-area cost they had when built.
#[derive(Debug, Clone)]
struct Trees {
    triangles: Bvh,
    edges: Bvh,
    built_area: f64,
}

/// Candidate pairs kept for reference boxes around a motion, for the broad phases of a
/// [`ContactMesh`] (see the module documentation).
#[derive(Debug, Clone)]
pub struct CandidateCache {
    max_reach: f64,
    min_margin: f64,
    max_margin: f64,
    /// Lower and upper corners of the vertices' reference boxes.
    lower: Vec<Vector3<f64>>,
    upper: Vec<Vector3<f64>>,
    pairs: CandidatePairs,
    trees: Option<Trees>,
    counters: CacheCounters,
}

impl CandidateCache {
    /// A cache for queries with a reach up to `max_reach` \[m\] on a mesh whose median edge length is
    /// `edge_length` \[m\] (it sets the margins).
    pub fn new(max_reach: f64, edge_length: f64) -> Self {
        Self {
            max_reach,
            min_margin: MIN_MARGIN_PER_EDGE * edge_length,
            max_margin: MAX_MARGIN_PER_EDGE * edge_length,
            lower: Vec::new(),
            upper: Vec::new(),
            pairs: CandidatePairs::default(),
            trees: None,
            counters: CacheCounters::default(),
        }
    }

    /// The counters so far.
    pub fn counters(&self) -> CacheCounters {
        self.counters
    }

    /// The same pairs as [`candidate_pairs`]`(mesh, start, end, reach, par)`, from the kept pairs when
    /// the motion stays inside the reference boxes.
    ///
    /// # Panics
    /// If `start` or `end` does not have one position per contact vertex (programmer error).
    #[track_caller]
    pub fn candidate_pairs(
        &mut self,
        mesh: &ContactMesh,
        start: &[Vector3<f64>],
        end: &[Vector3<f64>],
        reach: f64,
        par: Parallelism,
    ) -> CandidatePairs {
        assert_eq!(start.len(), mesh.n_vertices(), "one start position per contact vertex");
        assert_eq!(end.len(), mesh.n_vertices(), "one end position per contact vertex");
        self.counters.queries += 1;
        if !(reach <= self.max_reach) {
            self.counters.uncached += 1;
            return candidate_pairs(mesh, start, end, reach, par);
        }
        if !self.covers(start, end) {
            let displacement = max_distance(start, end);
            let margin = (MARGIN_PER_DISPLACEMENT * displacement).clamp(self.min_margin, self.max_margin);
            self.requery(mesh, start, end, margin, par);
        }
        self.filter(mesh, start, end, reach, par)
    }

    /// Whether every vertex stays inside its reference box at `start` and `end`.
    fn covers(&self, start: &[Vector3<f64>], end: &[Vector3<f64>]) -> bool {
        let inside = |v: usize, p: &Vector3<f64>| (0..3).all(|k| self.lower[v][k] <= p[k] && p[k] <= self.upper[v][k]);
        self.lower.len() == start.len() && (0..start.len()).all(|v| inside(v, &start[v]) && inside(v, &end[v]))
    }

    /// New reference boxes, around the motion `start → end` grown by `margin`, and their kept pairs.
    fn requery(
        &mut self,
        mesh: &ContactMesh,
        start: &[Vector3<f64>],
        end: &[Vector3<f64>],
        margin: f64,
        par: Parallelism,
    ) {
        self.counters.requeries += 1;
        self.lower = start.iter().zip(end).map(|(a, b)| a.inf(b).add_scalar(-margin)).collect();
        self.upper = start.iter().zip(end).map(|(a, b)| a.sup(b).add_scalar(margin)).collect();
        let max_reach = self.max_reach;
        // A primitive's box over the corners of its vertices' boxes is the hull of those boxes.
        let boxes = PrimitiveBoxes::new(mesh, &self.lower, &self.upper, |thickness| thickness + 0.5 * max_reach);
        let refitted = self.trees.take().and_then(|mut trees| {
            trees.triangles.refit(boxes.triangles.clone());
            trees.edges.refit(boxes.edges.clone());
            let area = trees.triangles.surface_area() + trees.edges.surface_area();
            (area <= REBUILD_AREA_RATIO * trees.built_area).then_some(trees)
        });
        let trees = refitted.unwrap_or_else(|| {
            self.counters.builds += 1;
            let (triangles, edges) = match par {
                Parallelism::Sequential => (Bvh::build(boxes.triangles.clone()), Bvh::build(boxes.edges.clone())),
                Parallelism::Rayon => rayon::join(
                    || Bvh::build(boxes.triangles.clone()),
                    || Bvh::build(boxes.edges.clone()),
                ),
            };
            let built_area = triangles.surface_area() + edges.surface_area();
            Trees {
                triangles,
                edges,
                built_area,
            }
        });
        self.pairs = overlapping_pairs(mesh, &trees.triangles, &trees.edges, &boxes, par);
        self.trees = Some(trees);
    }

    /// The kept pairs whose swept boxes over `start → end` (inflated as [`candidate_pairs`] does)
    /// overlap, in the kept (sorted) order.
    fn filter(
        &self,
        mesh: &ContactMesh,
        start: &[Vector3<f64>],
        end: &[Vector3<f64>],
        reach: f64,
        par: Parallelism,
    ) -> CandidatePairs {
        let boxes = PrimitiveBoxes::new(mesh, start, end, |thickness| thickness + 0.5 * reach);
        let keep_pt = |p: &&[u32; 2]| boxes.points[p[0] as usize].overlaps(&boxes.triangles[p[1] as usize]);
        let keep_ee = |p: &&[u32; 2]| boxes.edges[p[0] as usize].overlaps(&boxes.edges[p[1] as usize]);
        let (pt, ee) = (&self.pairs.point_triangle, &self.pairs.edge_edge);
        match par {
            Parallelism::Sequential => CandidatePairs {
                point_triangle: pt.iter().filter(keep_pt).copied().collect(),
                edge_edge: ee.iter().filter(keep_ee).copied().collect(),
            },
            // Rayon's collect keeps the order of the input, so the lists stay sorted.
            Parallelism::Rayon => CandidatePairs {
                point_triangle: pt.par_iter().filter(keep_pt).copied().collect(),
                edge_edge: ee.par_iter().filter(keep_ee).copied().collect(),
            },
        }
    }
}

/// The largest coordinate difference between corresponding points (maximum norm over all points);
/// infinite if a difference is not a number.
fn max_distance(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).amax())
        .fold(0.0, |m, d| if d.is_nan() { f64::INFINITY } else { m.max(d) })
}

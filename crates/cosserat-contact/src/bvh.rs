//! Axis-aligned boxes and a bounding-volume hierarchy over them, for the broad phases.
//!
//! The hierarchy is a binary tree built top-down by splitting the box centroids at the median of their
//! widest axis, with up to four boxes per leaf. Queries return the indices of all boxes overlapping a
//! query box, sorted, so callers get the same order whatever the traversal.

use nalgebra::Vector3;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vector3<f64>,
    /// Upper corner.
    pub max: Vector3<f64>,
}

impl Aabb {
    /// The empty box (contains nothing, overlaps nothing).
    pub fn empty() -> Self {
        Self {
            min: Vector3::repeat(f64::INFINITY),
            max: Vector3::repeat(f64::NEG_INFINITY),
        }
    }

    /// The smallest box containing the points.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vector3<f64>>) -> Self {
        let mut b = Self::empty();
        for p in points {
            b.grow(p);
        }
        b
    }

    /// Extends the box to contain `p`.
    pub fn grow(&mut self, p: &Vector3<f64>) {
        self.min = self.min.inf(p);
        self.max = self.max.sup(p);
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &Self) -> Self {
        Self {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }

    /// The box grown by `r` in every direction.
    pub fn inflated(&self, r: f64) -> Self {
        Self {
            min: self.min.add_scalar(-r),
            max: self.max.add_scalar(r),
        }
    }

    /// Whether the closed boxes overlap.
    #[inline]
    pub fn overlaps(&self, other: &Self) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }

    /// The surface area (0 for the empty box).
    pub fn surface_area(&self) -> f64 {
        let e = (self.max - self.min).map(|c| c.max(0.0));
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    fn centroid(&self) -> Vector3<f64> {
        (self.min + self.max) * 0.5
    }
}

#[derive(Debug, Clone, Copy)]
struct Node {
    aabb: Aabb,
    /// Leaves: `[start, end)` into `items`; inner nodes: `start` = left child, `end` = right child.
    start: u32,
    end: u32,
    leaf: bool,
}

/// A bounding-volume hierarchy over a set of boxes.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
    boxes: Vec<Aabb>,
}

const LEAF_SIZE: usize = 4;

impl Bvh {
    /// Builds the hierarchy of `boxes` (indices are positions in the slice).
    pub fn build(boxes: Vec<Aabb>) -> Self {
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1);
        if !boxes.is_empty() {
            let centroids: Vec<Vector3<f64>> = boxes.iter().map(Aabb::centroid).collect();
            build_node(&boxes, &centroids, &mut items, 0, &mut nodes);
        }
        Self { nodes, items, boxes }
    }

    /// Replaces the boxes by `boxes` (one per box of the build, same indices) and recomputes every
    /// node's bounds bottom-up, keeping the tree's topology. Queries stay exact (every node bounds its
    /// subtree); only their cost grows if the boxes moved far from where the tree was built, which
    /// [`Bvh::surface_area`] measures.
    ///
    /// # Panics
    /// If `boxes` does not have one box per box of the build (programmer error).
    #[track_caller]
    pub fn refit(&mut self, boxes: Vec<Aabb>) {
        assert_eq!(
            boxes.len(),
            self.boxes.len(),
            "refit needs one box per box of the build"
        );
        self.boxes = boxes;
        // Nodes are stored in pre-order, so every child comes after its parent.
        for n in (0..self.nodes.len()).rev() {
            let node = self.nodes[n];
            let aabb = if node.leaf {
                self.items[node.start as usize..node.end as usize]
                    .iter()
                    .fold(Aabb::empty(), |acc, &i| acc.union(&self.boxes[i as usize]))
            } else {
                self.nodes[node.start as usize].aabb.union(&self.nodes[node.end as usize].aabb)
            };
            self.nodes[n].aabb = aabb;
        }
    }

    /// The bounds of all boxes (the empty box if there are none).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::empty(), |n| n.aabb)
    }

    /// The sum of the surface areas of the nodes' boxes: proportional to the expected cost of a query
    /// (the surface-area heuristic), so a refitted tree whose sum grew far beyond that of a fresh build
    /// is worth rebuilding.
    pub fn surface_area(&self) -> f64 {
        self.nodes.iter().map(|n| n.aabb.surface_area()).sum()
    }

    /// Number of boxes.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// Whether there are no boxes.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Indices of all boxes overlapping `query`, appended to `out` in increasing order.
    pub fn query(&self, query: &Aabb, out: &mut Vec<u32>) {
        self.query_with(query, out, &mut Vec::new());
    }

    /// [`Bvh::query`] with a caller-owned traversal stack, so that a batch of queries allocates nothing.
    pub fn query_with(&self, query: &Aabb, out: &mut Vec<u32>, stack: &mut Vec<u32>) {
        let first = out.len();
        if self.nodes.is_empty() {
            return;
        }
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !node.aabb.overlaps(query) {
                continue;
            }
            if node.leaf {
                for &i in &self.items[node.start as usize..node.end as usize] {
                    if self.boxes[i as usize].overlaps(query) {
                        out.push(i);
                    }
                }
            } else {
                stack.push(node.start);
                stack.push(node.end);
            }
        }
        out[first..].sort_unstable();
    }
}

/// Builds the subtree over `items` (whose first entry has global offset `offset`) and returns its index.
/// `centroids` are the boxes' centres, computed once per build rather than in every comparison of
/// every level's median selection.
fn build_node(
    boxes: &[Aabb],
    centroids: &[Vector3<f64>],
    items: &mut [u32],
    offset: usize,
    nodes: &mut Vec<Node>,
) -> u32 {
    let aabb = items.iter().fold(Aabb::empty(), |acc, &i| acc.union(&boxes[i as usize]));
    let index = nodes.len() as u32;
    if items.len() <= LEAF_SIZE {
        nodes.push(Node {
            aabb,
            start: offset as u32,
            end: (offset + items.len()) as u32,
            leaf: true,
        });
        return index;
    }
    nodes.push(Node {
        aabb,
        start: 0,
        end: 0,
        leaf: false,
    });
    let bounds = Aabb::from_points(items.iter().map(|&i| &centroids[i as usize]));
    let extent = bounds.max - bounds.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |&a, &b| {
        let (ca, cb) = (centroids[a as usize][axis], centroids[b as usize][axis]);
        ca.total_cmp(&cb).then(a.cmp(&b))
    });
    let (left_items, right_items) = items.split_at_mut(mid);
    let left = build_node(boxes, centroids, left_items, offset, nodes);
    let right = build_node(boxes, centroids, right_items, offset + mid, nodes);
    nodes[index as usize].start = left;
    nodes[index as usize].end = right;
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn queries_match_a_linear_scan() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let boxes: Vec<Aabb> = (0..300)
            .map(|_| {
                let c = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let h = Vector3::from_fn(|_, _| rng.random_range(0.0..0.1));
                Aabb { min: c - h, max: c + h }
            })
            .collect();
        let bvh = Bvh::build(boxes.clone());
        for q in boxes.iter().take(50) {
            let q = q.inflated(0.05);
            let mut found = Vec::new();
            bvh.query(&q, &mut found);
            let expected: Vec<u32> = (0..boxes.len() as u32).filter(|&i| boxes[i as usize].overlaps(&q)).collect();
            assert_eq!(found, expected);
        }
    }

    fn random_boxes(rng: &mut ChaCha8Rng, n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|_| {
                let c = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let h = Vector3::from_fn(|_, _| rng.random_range(0.0..0.1));
                Aabb { min: c - h, max: c + h }
            })
            .collect()
    }

    /// Every node's box after a refit is the union of the boxes below it, as a build over the same
    /// topology computes it: checked against the union of the leaf boxes, and queries against a scan.
    #[test]
    fn refit_bounds_equal_rebuilt_bounds() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let before = random_boxes(&mut rng, 257);
        // Move every box far (the tree was built for other places) and change its size.
        let after: Vec<Aabb> = before
            .iter()
            .map(|b| {
                let shift = Vector3::from_fn(|_, _| rng.random_range(-0.5..0.5));
                Aabb {
                    min: b.min + shift,
                    max: b.max + shift + Vector3::repeat(rng.random_range(0.0..0.05)),
                }
            })
            .collect();
        let mut refitted = Bvh::build(before);
        refitted.refit(after.clone());
        let rebuilt = Bvh::build(after.clone());
        assert_eq!(refitted.bounds(), rebuilt.bounds());
        let all = after.iter().fold(Aabb::empty(), |acc, b| acc.union(b));
        assert_eq!(refitted.bounds(), all);
        for node in &refitted.nodes {
            let below = subtree_items(&refitted, node)
                .iter()
                .fold(Aabb::empty(), |acc, &i| acc.union(&after[i as usize]));
            assert_eq!(node.aabb, below);
        }
        for q in after.iter().take(60) {
            let q = q.inflated(0.05);
            let (mut a, mut b) = (Vec::new(), Vec::new());
            refitted.query(&q, &mut a);
            rebuilt.query(&q, &mut b);
            let expected: Vec<u32> = (0..after.len() as u32).filter(|&i| after[i as usize].overlaps(&q)).collect();
            assert_eq!(a, expected);
            assert_eq!(b, expected);
        }
    }

    fn subtree_items(bvh: &Bvh, node: &Node) -> Vec<u32> {
        if node.leaf {
            return bvh.items[node.start as usize..node.end as usize].to_vec();
        }
        let mut out = subtree_items(bvh, &bvh.nodes[node.start as usize]);
        out.extend(subtree_items(bvh, &bvh.nodes[node.end as usize]));
        out
    }
}

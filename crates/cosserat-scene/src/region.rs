//! Regions: how a scene names nodes, resolved against a shell's rest positions.
//!
//! A [`Region`] is resolved twice, once against the displacement nodes and once against the rotation
//! nodes, each by their own rest positions ([`ShellNodes`]); the caller decides which of the two sets
//! it needs and reports an empty one as an error. Kinds:
//! - [`Region::Box`]: an axis-aligned box given by centre and full size; faces included, as in the
//!   paper's scenes (`|p − c| ≤ size/2` per axis, computed as `c − size/2 ≤ p ≤ c + size/2`);
//! - [`Region::Predicate`]: a boolean expression of `x, y, z` ([`crate::expr::Predicate`]);
//! - [`Region::Vertices`]: corner vertices by index (the order of the generator or OBJ file), with the
//!   displacement and rotation nodes at those vertices and, for quadratic elements, the mid-edge nodes
//!   of every edge whose two corners are listed (so listing the vertices of an edge selects the whole
//!   edge, as a clamp needs);
//! - [`Region::Group`]: the vertices of a named group of the mesh file (a Gmsh physical group, an OBJ
//!   `g` or `o` group), selected as a vertex list;
//! - [`Region::BoundaryLoop`]: the nodes on boundary loop `k` (corner vertices and, for quadratic
//!   elements, the mid-edge nodes of its edges); loops are numbered as
//!   [`cosserat_fem::mesh::Topology::boundary_loops`] returns them (by their first edge in the sorted
//!   edge list);
//! - [`Region::Nearest`]: the single displacement node and the single rotation node nearest to a point
//!   (ties go to the lower index); the point must lie within the shell's bounding box grown by 1 % of
//!   its diagonal, so a mistyped point is reported instead of snapping to a far node;
//! - [`Region::All`]: every node.

use crate::error::{Num, RegionError};
use crate::expr::Predicate;
use crate::gmsh::MeshGroup;
use crate::mesh_source::{bounding_box, tri6_edge_nodes};
use cosserat_assembly::{ElementPair, ShellMesh};
use cosserat_fem::mesh::Topology;
use cosserat_fem::{ElementKind, MeshError, Tri6Mesh};
use nalgebra::Vector3;

/// The nodes of one shell, as regions see them.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellNodes {
    name: String,
    disp_positions: Vec<Vector3<f64>>,
    rot_positions: Vec<Vector3<f64>>,
    vertex_disp: Vec<usize>,
    vertex_rot: Vec<usize>,
    /// Per boundary loop: its displacement and rotation nodes (sorted).
    loops: Vec<(Vec<usize>, Vec<usize>)>,
    /// Boundary edges as corner-vertex pairs.
    boundary_edges: Vec<[usize; 2]>,
    /// Quadratic meshes: every edge as its corner-vertex pair and its mid-edge node.
    mid_edge_nodes: Vec<([usize; 2], usize)>,
    /// Whether the rotation nodes are the displacement nodes (a quadratic rotation element).
    rot_is_tri6: bool,
    /// Named vertex sets of the mesh file.
    groups: Vec<MeshGroup>,
    /// The displacement and rotation elements, by node.
    disp_elements: Vec<Vec<usize>>,
    rot_elements: Vec<Vec<usize>>,
    bbox: (Vector3<f64>, Vector3<f64>),
}

impl ShellNodes {
    /// The nodes of a shell mesh for the given element pair.
    ///
    /// # Errors
    /// [`RegionError::Topology`] if the boundary cannot be traced (non-manifold edges), or if the mesh
    /// is inconsistent: indices out of range, a missing Tri6 mesh for a quadratic pair, or a Tri6 mesh
    /// whose elements or corner nodes do not match the corner mesh.
    pub fn new(name: &str, mesh: &ShellMesh, pair: ElementPair) -> Result<Self, RegionError> {
        let topology_error = |source: MeshError| RegionError::Topology {
            shell: name.to_string(),
            source,
        };
        let tri6 = checked_tri6(mesh, pair).map_err(topology_error)?;
        let n_vertices = mesh.corners.n_nodes();
        let (disp_positions, vertex_disp) = match tri6 {
            Some(t) => (t.nodes.clone(), mesh.corner_nodes.clone()),
            None => (mesh.corners.nodes.clone(), (0..n_vertices).collect()),
        };
        let rot_is_tri6 = pair.rotation() == ElementKind::Tri6;
        let (rot_positions, vertex_rot) = if rot_is_tri6 {
            (disp_positions.clone(), vertex_disp.clone())
        } else {
            (mesh.corners.nodes.clone(), (0..n_vertices).collect())
        };
        let topology = Topology::new(&mesh.corners);
        let vertex_loops = topology.boundary_loops().map_err(topology_error)?;
        let edge_nodes = tri6.map(|t| tri6_edge_nodes(&topology, t));
        let loops = vertex_loops
            .iter()
            .map(|cycle| {
                let disp = loop_nodes(cycle, &topology, &vertex_disp, edge_nodes.as_deref());
                let rot_edge_nodes = if rot_is_tri6 { edge_nodes.as_deref() } else { None };
                let rot = loop_nodes(cycle, &topology, &vertex_rot, rot_edge_nodes);
                (disp, rot)
            })
            .collect();
        let bbox = bounding_box(&disp_positions);
        let boundary_edges = topology.boundary_edges().into_iter().map(|e| topology.edges()[e]).collect();
        let mid_edge_nodes = edge_nodes
            .map(|nodes| topology.edges().iter().copied().zip(nodes).collect())
            .unwrap_or_default();
        let corner_elements = |map: &[usize]| -> Vec<Vec<usize>> {
            mesh.corners.elements.iter().map(|e| e.map(|v| map[v]).to_vec()).collect()
        };
        let disp_elements = match tri6 {
            Some(t) => t.elements.iter().map(|e| e.to_vec()).collect(),
            None => corner_elements(&vertex_disp),
        };
        let rot_elements = if rot_is_tri6 {
            disp_elements.clone()
        } else {
            corner_elements(&vertex_rot)
        };
        Ok(Self {
            name: name.to_string(),
            groups: Vec::new(),
            disp_elements,
            rot_elements,
            disp_positions,
            rot_positions,
            vertex_disp,
            vertex_rot,
            loops,
            boundary_edges,
            mid_edge_nodes,
            rot_is_tri6,
            bbox,
        })
    }

    /// The number of boundary edges whose two end nodes are both in `selected` (displacement nodes, or
    /// rotation nodes if `rotation`); a line load needs at least one.
    pub fn count_boundary_edges(&self, selected: &[usize], rotation: bool) -> usize {
        let map = if rotation { &self.vertex_rot } else { &self.vertex_disp };
        let has = |node: usize| selected.binary_search(&node).is_ok();
        self.boundary_edges.iter().filter(|[a, b]| has(map[*a]) && has(map[*b])).count()
    }

    /// These nodes with the named vertex sets of the mesh file, for [`Region::Group`].
    pub fn with_groups(mut self, groups: Vec<MeshGroup>) -> Self {
        self.groups = groups;
        self
    }

    /// The names of the mesh file's groups.
    pub fn group_names(&self) -> Vec<&str> {
        self.groups.iter().map(|g| g.name.as_str()).collect()
    }

    /// The number of elements whose nodes are all in `selected` (displacement nodes, or rotation nodes
    /// if `rotation`); a load over an area needs at least one.
    pub fn count_covered_elements(&self, selected: &[usize], rotation: bool) -> usize {
        let elements = if rotation {
            &self.rot_elements
        } else {
            &self.disp_elements
        };
        let has = |node: &usize| selected.binary_search(node).is_ok();
        elements.iter().filter(|e| e.iter().all(has)).count()
    }

    /// The shell's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Rest positions of the displacement nodes.
    pub fn disp_positions(&self) -> &[Vector3<f64>] {
        &self.disp_positions
    }

    /// Rest positions of the rotation nodes.
    pub fn rot_positions(&self) -> &[Vector3<f64>] {
        &self.rot_positions
    }

    /// Number of boundary loops.
    pub fn n_boundary_loops(&self) -> usize {
        self.loops.len()
    }

    /// The bounding box `(min, max)` of the displacement nodes.
    pub fn bounding_box(&self) -> (Vector3<f64>, Vector3<f64>) {
        self.bbox
    }

    /// Checks that `p` lies in the bounding box grown by 1 % of its diagonal.
    ///
    /// # Errors
    /// [`RegionError::PointOutsideMesh`] otherwise.
    pub fn check_inside(&self, p: &Vector3<f64>) -> Result<(), RegionError> {
        let (min, max) = self.bbox;
        let margin = 0.01 * (max - min).norm();
        let inside = (0..3).all(|i| p[i] >= min[i] - margin && p[i] <= max[i] + margin);
        if inside {
            Ok(())
        } else {
            Err(RegionError::PointOutsideMesh {
                point: [p.x, p.y, p.z],
                shell: self.name.clone(),
                min: [min.x, min.y, min.z],
                max: [max.x, max.y, max.z],
            })
        }
    }

    /// The displacement and rotation nodes at which `test` holds.
    fn select_where(&self, test: &dyn Fn(&Vector3<f64>) -> Result<bool, RegionError>) -> Result<Selected, RegionError> {
        let filter = |positions: &[Vector3<f64>]| {
            let mut out = Vec::new();
            for (i, p) in positions.iter().enumerate() {
                if test(p)? {
                    out.push(i);
                }
            }
            Ok::<_, RegionError>(out)
        };
        Ok(Selected {
            disp_nodes: filter(&self.disp_positions)?,
            rot_nodes: filter(&self.rot_positions)?,
        })
    }

    /// The nodes at the listed corner vertices and, for quadratic elements, the mid-edge nodes of the
    /// edges whose two corners are listed.
    fn at_vertices(&self, list: &[usize]) -> Result<Selected, RegionError> {
        let n_vertices = self.vertex_disp.len();
        if let Some(&vertex) = list.iter().find(|&&v| v >= n_vertices) {
            return Err(RegionError::VertexOutOfRange {
                vertex,
                shell: self.name.clone(),
                n_vertices,
            });
        }
        let mut disp_nodes: Vec<usize> = list.iter().map(|&v| self.vertex_disp[v]).collect();
        let mut rot_nodes: Vec<usize> = list.iter().map(|&v| self.vertex_rot[v]).collect();
        let mut listed = list.to_vec();
        sort_unique(&mut listed);
        let is_listed = |v: usize| listed.binary_search(&v).is_ok();
        for &([a, b], mid) in &self.mid_edge_nodes {
            if is_listed(a) && is_listed(b) {
                disp_nodes.push(mid);
                if self.rot_is_tri6 {
                    rot_nodes.push(mid);
                }
            }
        }
        sort_unique(&mut disp_nodes);
        sort_unique(&mut rot_nodes);
        Ok(Selected { disp_nodes, rot_nodes })
    }
}

/// The Tri6 mesh of a quadratic displacement element (`None` for a linear one), checked against the
/// corner mesh: indices in range, the same elements, and a corner-node map that fits both.
fn checked_tri6(mesh: &ShellMesh, pair: ElementPair) -> Result<Option<&Tri6Mesh>, MeshError> {
    let mismatch = |reason: &str| MeshError::CornerMeshMismatch {
        reason: reason.to_string(),
    };
    mesh.corners.check_indices()?;
    match (pair.displacement(), &mesh.tri6) {
        (ElementKind::Tri6, Some(t)) => {
            t.check_indices()?;
            if t.n_elements() != mesh.corners.n_elements() {
                return Err(mismatch("the Tri6 and corner meshes have different element counts"));
            }
            if mesh.corner_nodes.len() != mesh.corners.n_nodes() || mesh.corner_nodes.iter().any(|&i| i >= t.n_nodes())
            {
                return Err(mismatch("the corner-node map does not fit the meshes"));
            }
            Ok(Some(t))
        }
        (ElementKind::Tri6, None) => Err(mismatch("the element pair needs a Tri6 mesh")),
        _ => Ok(None),
    }
}

/// The nodes of one boundary loop of corner vertices, sorted: the vertices' nodes (`vertex_node`)
/// and, for a quadratic element (`edge_nodes`, the mid-edge node of each edge), those of its edges.
fn loop_nodes(cycle: &[usize], topology: &Topology, vertex_node: &[usize], edge_nodes: Option<&[usize]>) -> Vec<usize> {
    let mut nodes: Vec<usize> = cycle.iter().map(|&v| vertex_node[v]).collect();
    if let Some(edge_nodes) = edge_nodes {
        for k in 0..cycle.len() {
            let (a, b) = (cycle[k], cycle[(k + 1) % cycle.len()]);
            if let Some(e) = topology.find_edge(a, b) {
                nodes.push(edge_nodes[e]);
            }
        }
    }
    sort_unique(&mut nodes);
    nodes
}

/// A set of nodes named by a scene.
#[derive(Debug, Clone)]
pub enum Region {
    /// An axis-aligned box, faces included.
    Box {
        /// Centre \[m\].
        center: Vector3<f64>,
        /// Full size per axis \[m\] (non-negative).
        size: Vector3<f64>,
    },
    /// The nodes where a predicate holds.
    Predicate(Predicate),
    /// The nodes at these corner vertices.
    Vertices(Vec<usize>),
    /// The vertices of a named group of the mesh file, selected as [`Region::Vertices`].
    Group(String),
    /// The nodes of one boundary loop.
    BoundaryLoop(usize),
    /// The nearest displacement node and the nearest rotation node to a point.
    Nearest(Vector3<f64>),
    /// Every node.
    All,
}

/// The nodes a region selects (local indices, sorted, unique).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Selected {
    /// Displacement nodes.
    pub disp_nodes: Vec<usize>,
    /// Rotation nodes.
    pub rot_nodes: Vec<usize>,
}

impl Region {
    /// A short description for messages, e.g. `box centre (0, 0, 0) size (1, 1, 1)`.
    pub fn describe(&self) -> String {
        let v = |p: &Vector3<f64>| format!("({}, {}, {})", Num(p.x), Num(p.y), Num(p.z));
        match self {
            Region::Box { center, size } => format!("box centre {} size {}", v(center), v(size)),
            Region::Predicate(p) => format!("predicate `{}`", p.text()),
            Region::Vertices(list) => format!("{} listed vertices", list.len()),
            Region::Group(name) => format!("group `{name}`"),
            Region::BoundaryLoop(k) => format!("boundary loop {k}"),
            Region::Nearest(p) => format!("nearest to {}", v(p)),
            Region::All => "all nodes".into(),
        }
    }

    /// The displacement and rotation nodes of `nodes` that the region selects.
    ///
    /// # Errors
    /// [`RegionError::VertexOutOfRange`], [`RegionError::LoopOutOfRange`],
    /// [`RegionError::PointOutsideMesh`] (nearest) and [`RegionError::Predicate`] for a predicate that
    /// is not boolean at some node. An empty selection is not an error here.
    pub fn select(&self, nodes: &ShellNodes) -> Result<Selected, RegionError> {
        match self {
            Region::Box { center, size } => {
                let lo = center - size * 0.5;
                let hi = center + size * 0.5;
                nodes.select_where(&|p| Ok((0..3).all(|i| lo[i] <= p[i] && p[i] <= hi[i])))
            }
            Region::Predicate(predicate) => nodes.select_where(&|p| predicate.test(p).map_err(RegionError::from)),
            Region::Vertices(list) => nodes.at_vertices(list),
            Region::Group(name) => {
                let group = nodes
                    .groups
                    .iter()
                    .find(|g| &g.name == name)
                    .ok_or_else(|| RegionError::UnknownGroup {
                        group: name.clone(),
                        shell: nodes.name.clone(),
                        available: nodes.group_names().join(", "),
                    })?;
                Region::Vertices(group.vertices.clone()).select(nodes)
            }
            Region::BoundaryLoop(k) => {
                let (disp, rot) = nodes.loops.get(*k).ok_or_else(|| RegionError::LoopOutOfRange {
                    index: *k,
                    shell: nodes.name.clone(),
                    n_loops: nodes.loops.len(),
                })?;
                Ok(Selected {
                    disp_nodes: disp.clone(),
                    rot_nodes: rot.clone(),
                })
            }
            Region::Nearest(point) => {
                nodes.check_inside(point)?;
                Ok(Selected {
                    disp_nodes: nearest(&nodes.disp_positions, point).into_iter().collect(),
                    rot_nodes: nearest(&nodes.rot_positions, point).into_iter().collect(),
                })
            }
            Region::All => Ok(Selected {
                disp_nodes: (0..nodes.disp_positions.len()).collect(),
                rot_nodes: (0..nodes.rot_positions.len()).collect(),
            }),
        }
    }
}

/// The index of the point nearest to `p` (the lowest index among ties), `None` for no points.
fn nearest(points: &[Vector3<f64>], p: &Vector3<f64>) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, q) in points.iter().enumerate() {
        let d = (q - p).norm_squared();
        if best.is_none_or(|(_, b)| d < b) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| i)
}

fn sort_unique(v: &mut Vec<usize>) {
    v.sort_unstable();
    v.dedup();
}

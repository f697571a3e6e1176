//! Where a shell's rest mesh comes from and how it is shaped: a procedural generator or an OBJ file,
//! refinement, the element upgrade, projections, a similarity transform, and initial positions that
//! differ from the rest pose.
//!
//! [`build_mesh`] runs a [`MeshRecipe`] through a fixed pipeline:
//! 1. **source**: a [`Generator`] (with its exact surface), an OBJ file ([`crate::obj`]) or a Gmsh file
//!    ([`crate::gmsh`], whose 6-node triangles keep their own mid-edge nodes in step 3);
//! 2. **refine** `n` times: on the exact surface for generators, at chord midpoints for OBJ input
//!    (the Dumpling's procedure);
//! 3. **element upgrade** to the displacement element: Tri6 nodes on the exact surface for
//!    generators (curved elements), on the chords for OBJ input;
//! 4. **project to a sphere** (every node, corners and Tri6 nodes, radially; the Dumpling);
//! 5. **flatten a cap** (every node projected onto the sphere of the given radius about the origin,
//!    flattened to `z = 0`, and boundary nodes pushed radially onto the circle of that radius: the
//!    Buckling circle's flat disk with curved, isoparametric boundary edges);
//! 6. **transform**: rotations about the origin, then centring of the bounding box (of the corner
//!    vertices), then uniform scaling (to a height along z, or by a factor), then a translation (the
//!    Bunny and the Armadillos); similarity transforms commute with chord and surface placement, so
//!    doing this last equals transforming the input;
//! 7. **initial positions** (optional): a rigid motion of the final rest positions of the
//!    displacement nodes (the Buckling circle's 1.5° tilt and 1 cm lift); the rest pose is unchanged.
//!
//! The result is validated (no degenerate or folded element) before it is returned.

use crate::error::{MeshSourceError, ObjError};
use crate::gmsh::{MeshGroup, read_gmsh};
use crate::obj::read_obj;
use crate::ply::read_ply;
use cosserat_assembly::{ElementPair, ShellMesh};
use cosserat_fem::mesh::procedural::{self, AnnulusSettings, GeneratedMesh, Surface};
use cosserat_fem::mesh::{NewNode, Topology, chord_placement};
use cosserat_fem::{ElementKind, MeshError, Tri3Mesh, TriMesh};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::path::PathBuf;

/// A procedural mesh and its parameters (lengths in metres).
#[derive(Debug, Clone, PartialEq)]
pub enum Generator {
    /// [`procedural::rectangle_grid`]: `lx × ly` centred at the origin, `nx × ny` quads with the
    /// paper's checkerboard diagonals.
    Rectangle {
        /// Size along x.
        lx: f64,
        /// Size along y.
        ly: f64,
        /// Quads along x.
        nx: usize,
        /// Quads along y.
        ny: usize,
    },
    /// A disk: [`procedural::annulus`] without a hole.
    Disk {
        /// Radius.
        radius: f64,
        /// Rings of quads.
        n_radial: usize,
        /// Vertices per ring.
        n_angular: usize,
    },
    /// [`procedural::annulus`].
    Annulus(AnnulusSettings),
    /// [`procedural::cylinder`] about the z axis.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
        /// Vertices per ring.
        n_around: usize,
        /// Rings of quads.
        n_along: usize,
    },
    /// [`procedural::icosphere`]: recursive midpoint subdivision, `level` times.
    Icosphere {
        /// Radius.
        radius: f64,
        /// Subdivision level.
        level: usize,
    },
    /// A cap of a geodesic icosphere of frequency `frequency`: every icosahedron face split into
    /// `frequency²` triangles on the flat face and projected onto the sphere (Blender's "Icosphere" with
    /// `log₂(frequency) + 1` subdivisions), rotated so that a vertex sits at the north pole and one of
    /// its neighbours at azimuth 0, keeping the faces whose three corners have `z ≥ min_z`.
    /// `radius = 1, frequency = 4, min_z = 0.25` reproduces the Buckling circle's
    /// `icosphere_cap_3.obj` (71 vertices, 120 triangles, 20 boundary edges).
    IcosphereCap {
        /// Radius.
        radius: f64,
        /// Subdivision frequency (≥ 1).
        frequency: usize,
        /// Lowest corner height of a kept face \[m\].
        min_z: f64,
    },
    /// [`procedural::uv_sphere`].
    UvSphere {
        /// Radius.
        radius: f64,
        /// Vertices per latitude ring.
        n_lon: usize,
        /// Latitude bands.
        n_lat: usize,
    },
    /// [`procedural::uv_hemisphere`], optionally with a polar hole ([`GeneratedMesh::with_polar_hole`]).
    Hemisphere {
        /// Radius.
        radius: f64,
        /// Vertices per latitude ring.
        n_lon: usize,
        /// Latitude bands.
        n_lat: usize,
        /// Polar angle of the hole \[rad\], if any.
        polar_hole: Option<f64>,
    },
    /// [`procedural::mobius_strip`].
    Mobius {
        /// Centre-line radius.
        radius: f64,
        /// Width.
        width: f64,
        /// Vertex columns along the band.
        n_along: usize,
        /// Quads across.
        n_across: usize,
    },
}

/// The largest mesh the pipeline builds (elements after refinement), about 100 times the largest mesh
/// of the paper's experiments; larger requests are reported instead of exhausting memory.
pub const MAX_ELEMENTS: usize = 10_000_000;

/// The most elements a mesh may have, and why: [`MAX_ELEMENTS`] by default, fewer when the caller
/// knows that a larger mesh could not be simulated in the memory at hand.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementBudget {
    /// Elements after refinement.
    pub max: usize,
    /// Where the limit comes from, for messages.
    pub source: String,
}

impl Default for ElementBudget {
    fn default() -> Self {
        Self {
            max: MAX_ELEMENTS,
            source: "the largest mesh the simulator builds".into(),
        }
    }
}

impl Generator {
    /// The number of triangles the generator makes (saturating; an upper bound for caps and holes).
    pub fn element_count(&self) -> usize {
        match *self {
            Generator::Rectangle { nx, ny, .. } => 2usize.saturating_mul(nx).saturating_mul(ny),
            Generator::Disk {
                n_radial, n_angular, ..
            } => 2usize.saturating_mul(n_radial).saturating_mul(n_angular),
            Generator::Annulus(s) => 2usize.saturating_mul(s.n_radial).saturating_mul(s.n_angular),
            Generator::Cylinder { n_around, n_along, .. } => 2usize.saturating_mul(n_around).saturating_mul(n_along),
            Generator::Icosphere { level, .. } => 20usize.saturating_mul(4usize.saturating_pow(level as u32)),
            Generator::IcosphereCap { frequency, .. } => 20usize.saturating_mul(frequency).saturating_mul(frequency),
            Generator::UvSphere { n_lon, n_lat, .. } | Generator::Hemisphere { n_lon, n_lat, .. } => {
                2usize.saturating_mul(n_lon).saturating_mul(n_lat)
            }
            Generator::Mobius { n_along, n_across, .. } => 2usize.saturating_mul(n_along).saturating_mul(n_across),
        }
    }

    /// The resolution parameter that contributes most to the element count (the one to name when the
    /// mesh is too large).
    pub fn resolution_key(&self) -> &'static str {
        let larger = |a: (&'static str, usize), b: (&'static str, usize)| if a.1 >= b.1 { a.0 } else { b.0 };
        match *self {
            Generator::Rectangle { nx, ny, .. } => larger(("nx", nx), ("ny", ny)),
            Generator::Disk {
                n_radial, n_angular, ..
            } => larger(("n_radial", n_radial), ("n_angular", n_angular)),
            Generator::Annulus(s) => larger(("n_radial", s.n_radial), ("n_angular", s.n_angular)),
            Generator::Cylinder { n_around, n_along, .. } => larger(("n_around", n_around), ("n_along", n_along)),
            Generator::Icosphere { .. } => "level",
            Generator::IcosphereCap { .. } => "frequency",
            Generator::UvSphere { n_lon, n_lat, .. } | Generator::Hemisphere { n_lon, n_lat, .. } => {
                larger(("n_lon", n_lon), ("n_lat", n_lat))
            }
            Generator::Mobius { n_along, n_across, .. } => larger(("n_along", n_along), ("n_across", n_across)),
        }
    }

    /// The named vertex sets a generator defines: the two sides of a slit annulus, `slit_start` (the
    /// vertices at angle 0, whose elements begin the sweep, above the +x axis) and `slit_end` (their
    /// duplicates at angle 2π, below it). Both sides lie at the same rest positions, so only these
    /// groups (or vertex lists) tell them apart.
    pub fn groups(&self) -> Vec<MeshGroup> {
        match self {
            Generator::Annulus(settings) => settings.slit_sides().map_or_else(Vec::new, |(start, end)| {
                // `slit_sides` lists each side inside out, in ascending order as a group's vertices are.
                let side = |name: &str, vertices| MeshGroup {
                    name: name.to_string(),
                    dim: 1,
                    vertices,
                };
                vec![side("slit_start", start), side("slit_end", end)]
            }),
            _ => Vec::new(),
        }
    }

    /// The generated mesh with its exact surface.
    ///
    /// # Errors
    /// [`MeshError::InvalidParameter`] for parameters out of range, [`MeshError::EmptyMesh`] for a cap
    /// that keeps no face.
    pub fn generate(&self) -> Result<GeneratedMesh, MeshError> {
        match *self {
            Generator::Rectangle { lx, ly, nx, ny } => procedural::rectangle_grid(lx, ly, nx, ny),
            Generator::Disk {
                radius,
                n_radial,
                n_angular,
            } => procedural::annulus(&AnnulusSettings {
                inner_radius: 0.0,
                outer_radius: radius,
                n_radial,
                n_angular,
                slit: false,
            })
            .map_err(|e| match e {
                MeshError::InvalidParameter {
                    parameter,
                    value,
                    reason,
                    ..
                } => MeshError::InvalidParameter {
                    generator: "disk",
                    parameter,
                    value,
                    reason,
                },
                e => e,
            }),
            Generator::Annulus(settings) => procedural::annulus(&settings),
            Generator::Cylinder {
                radius,
                length,
                n_around,
                n_along,
            } => procedural::cylinder(radius, length, n_around, n_along),
            Generator::Icosphere { radius, level } => procedural::icosphere(radius, level),
            Generator::IcosphereCap {
                radius,
                frequency,
                min_z,
            } => icosphere_cap(radius, frequency, min_z),
            Generator::UvSphere { radius, n_lon, n_lat } => procedural::uv_sphere(radius, n_lon, n_lat),
            Generator::Hemisphere {
                radius,
                n_lon,
                n_lat,
                polar_hole,
            } => {
                let mesh = procedural::uv_hemisphere(radius, n_lon, n_lat)?;
                match polar_hole {
                    Some(angle) => mesh.with_polar_hole(angle).map_err(|e| match e {
                        MeshError::EmptyMesh { .. } => MeshError::InvalidParameter {
                            generator: "hemisphere",
                            parameter: "polar_hole_degrees",
                            value: angle.to_degrees(),
                            reason: "leaves no face: the hole must be smaller than 90° less one latitude band \
                                     (90°/n_lat)",
                        },
                        e => e,
                    }),
                    None => Ok(mesh),
                }
            }
            Generator::Mobius {
                radius,
                width,
                n_along,
                n_across,
            } => procedural::mobius_strip(radius, width, n_along, n_across),
        }
    }
}

/// The input of the pipeline.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSource {
    /// A procedural mesh.
    Generator(Generator),
    /// An OBJ file (absolute, or already resolved against the scene's directory).
    Obj(PathBuf),
    /// A Gmsh MSH 4.1 file ([`crate::gmsh`]).
    Gmsh(PathBuf),
    /// A PLY file ([`crate::ply`]).
    Ply(PathBuf),
}

impl MeshSource {
    /// A mesh file by its extension, in any case: `.obj` is OBJ, `.msh` Gmsh, `.ply` PLY.
    ///
    /// # Errors
    /// [`MeshSourceError::Invalid`] (step `path`) for any other extension or none: reading such a file
    /// as one of the three would report its content as a broken mesh instead of a wrong format.
    pub fn file(path: PathBuf) -> Result<Self, MeshSourceError> {
        let extension = path.extension().map(|e| e.to_string_lossy().into_owned());
        match extension.as_deref().map(str::to_ascii_lowercase).as_deref() {
            Some("obj") => Ok(Self::Obj(path)),
            Some("msh") => Ok(Self::Gmsh(path)),
            Some("ply") => Ok(Self::Ply(path)),
            _ => {
                let found = match &extension {
                    Some(e) => format!("the extension `.{e}` is not a mesh format the simulator reads"),
                    None => format!("`{}` has no extension to tell its format", path.display()),
                };
                Err(MeshSourceError::Invalid {
                    step: "path",
                    reason: format!(
                        "{found}; use `.obj` (Wavefront OBJ), `.msh` (Gmsh MSH 4.1) or `.ply` (PLY), in any case"
                    ),
                })
            }
        }
    }
}

/// `x ↦ c + r (x − c)/|x − c|` for every node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereProjection {
    /// Centre \[m\].
    pub center: Vector3<f64>,
    /// Radius \[m\], positive.
    pub radius: f64,
}

/// How a mesh is scaled after rotation and centring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scaling {
    /// Scaled uniformly so that its extent along z is this height \[m\].
    Height(f64),
    /// Scaled uniformly by this factor.
    Factor(f64),
}

/// `x ↦ s (R x − c) + d`: rotation about the origin, optional centring of the bounding box
/// (`c` its centre after rotation, otherwise 0), uniform scaling, translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// The rotation `R`.
    pub rotation: Matrix3<f64>,
    /// Move the bounding-box centre to the origin before scaling.
    pub center: bool,
    /// The scaling, if any.
    pub scaling: Option<Scaling>,
    /// The translation `d` \[m\].
    pub translation: Vector3<f64>,
}

/// `x ↦ R (x − p) + p + d`: a rotation about the point `p`, then a translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    /// The rotation `R`.
    pub rotation: Matrix3<f64>,
    /// The fixed point `p` of the rotation \[m\].
    pub about: Vector3<f64>,
    /// The translation `d` \[m\].
    pub translation: Vector3<f64>,
}

impl RigidMotion {
    /// Applies the motion to a point.
    pub fn apply(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * (x - self.about) + self.about + self.translation
    }
}

/// Everything that defines a shell's rest mesh and initial positions.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRecipe {
    /// The input.
    pub source: MeshSource,
    /// The element pair; decides whether a Tri6 mesh is built.
    pub pair: ElementPair,
    /// Number of uniform refinements (each splits every triangle into four).
    pub refine: usize,
    /// OBJ input: merge vertices closer than this distance \[m\] before anything else.
    pub weld: Option<f64>,
    /// Radial projection of every node onto a sphere.
    pub project_to_sphere: Option<SphereProjection>,
    /// Flatten a spherical cap into a disk of this radius \[m\] (see the module docs).
    pub flatten_cap: Option<f64>,
    /// A similarity transform of the rest mesh.
    pub transform: Option<Transform>,
    /// Initial positions: the rest positions moved rigidly (the directors keep their rest orientation).
    pub initial: Option<RigidMotion>,
}

/// The mesh of a shell and its initial positions.
#[derive(Debug, Clone, PartialEq)]
pub struct BuiltMesh {
    /// The rest mesh, upgraded to the displacement element.
    pub mesh: ShellMesh,
    /// Initial displacement-node positions, if they differ from the rest positions.
    pub initial_positions: Option<Vec<Vector3<f64>>>,
    /// What the input does that is allowed but probably not meant (see
    /// [`ObjMesh::warnings`](crate::obj::ObjMesh::warnings)).
    pub warnings: Vec<String>,
    /// The named vertex sets of a mesh file (Gmsh physical groups, OBJ groups) or of a generator
    /// ([`Generator::groups`]); empty after refinement (which the groups would not follow).
    pub groups: Vec<MeshGroup>,
}

/// Runs the pipeline of the module docs.
///
/// # Errors
/// [`MeshSourceError::Generator`] for bad generator parameters, [`MeshSourceError::Obj`] for an OBJ
/// file that cannot be read or used, [`MeshSourceError::Invalid`] for a step that cannot be applied
/// (a node at a projection centre, a flat mesh scaled to a height, a Tri3/Tri6 pair), and
/// [`MeshSourceError::Result`] if the final mesh has a degenerate or folded element.
pub fn build_mesh(recipe: &MeshRecipe) -> Result<BuiltMesh, MeshSourceError> {
    build_mesh_within(recipe, &ElementBudget::default())
}

/// [`build_mesh`] with a given limit on the number of elements, checked before anything is built.
///
/// # Errors
/// As [`build_mesh`].
pub fn build_mesh_within(recipe: &MeshRecipe, budget: &ElementBudget) -> Result<BuiltMesh, MeshSourceError> {
    let (mut mesh, warnings, groups) = source_mesh(recipe, budget)?;
    shape(&mut mesh, recipe)?;
    if let Some(transform) = &recipe.transform {
        apply_transform(&mut mesh, transform)?;
    }
    mesh.corners.validate().map_err(MeshSourceError::Result)?;
    if let Some(tri6) = &mesh.tri6 {
        tri6.validate().map_err(MeshSourceError::Result)?;
    }
    let initial_positions = recipe.initial.map(|motion| {
        let rest = if recipe.pair.displacement() == ElementKind::Tri6 {
            mesh.tri6.as_ref().map_or(&mesh.corners.nodes, |t| &t.nodes)
        } else {
            &mesh.corners.nodes
        };
        rest.iter().map(|x| motion.apply(x)).collect()
    });
    Ok(BuiltMesh {
        mesh,
        initial_positions,
        warnings,
        groups,
    })
}

/// The input mesh, refined and upgraded to the element pair, with the input's warnings and groups;
/// sizes are checked against the budget before anything is generated or refined.
fn source_mesh(
    recipe: &MeshRecipe,
    budget: &ElementBudget,
) -> Result<(ShellMesh, Vec<String>, Vec<MeshGroup>), MeshSourceError> {
    let refined_count = |n_elements: usize| 4usize.saturating_pow(recipe.refine as u32).saturating_mul(n_elements);
    let limit = || format!("more than the limit of {} ({})", budget.max, budget.source);
    let too_large = |n: usize| MeshSourceError::Invalid {
        step: "refine",
        reason: format!("the mesh would have {} elements, {}", count(n), limit()),
    };
    let mut warnings = Vec::new();
    let mut groups = Vec::new();
    let mesh = match &recipe.source {
        MeshSource::Generator(generator) => {
            let generated = generator.element_count();
            if generated > budget.max {
                return Err(MeshSourceError::Invalid {
                    step: generator.resolution_key(),
                    reason: format!("the generator would make {} triangles, {}", count(generated), limit()),
                });
            }
            let n = refined_count(generated);
            if n > budget.max {
                return Err(too_large(n));
            }
            let mut generated = generator.generate().map_err(MeshSourceError::Generator)?;
            for _ in 0..recipe.refine {
                generated = generated.refine_on_surface();
            }
            if recipe.refine == 0 {
                groups = generator.groups();
            }
            ShellMesh::from_tri3(generated.mesh.clone(), recipe.pair, |node| generated.place(node))
        }
        MeshSource::Obj(path) => {
            let mut obj = read_obj(path).map_err(MeshSourceError::Obj)?;
            if let Some(tolerance) = recipe.weld {
                obj = obj.welded(tolerance, path).map_err(|e| weld_error(tolerance, e))?.0;
            }
            warnings = obj.warnings(path);
            let mut corners: Tri3Mesh = obj.mesh;
            let n = refined_count(corners.n_elements());
            if n > budget.max {
                return Err(too_large(n));
            }
            for _ in 0..recipe.refine {
                corners = corners.refine_uniform();
            }
            if recipe.refine == 0 {
                groups = obj.groups;
            }
            ShellMesh::from_tri3(corners, recipe.pair, chord_placement)
        }
        MeshSource::Ply(path) => {
            let check = |n: usize| {
                if refined_count(n) > budget.max {
                    Err(too_large(refined_count(n)))
                } else {
                    Ok(())
                }
            };
            let (mesh, g) = ply_mesh(path, recipe, &check)?;
            groups = g;
            mesh
        }
        MeshSource::Gmsh(path) => {
            let check = |n: usize| {
                if refined_count(n) > budget.max {
                    Err(too_large(refined_count(n)))
                } else {
                    Ok(())
                }
            };
            let (mesh, g) = gmsh_mesh(path, recipe, &check)?;
            groups = g;
            mesh
        }
    };
    Ok((mesh, warnings, groups))
}

/// A PLY file's mesh, refined and upgraded, with its groups (none after refinement); `check` refuses
/// an element count over the budget.
fn ply_mesh(
    path: &std::path::Path,
    recipe: &MeshRecipe,
    check: &dyn Fn(usize) -> Result<(), MeshSourceError>,
) -> Result<(ShellMesh, Vec<MeshGroup>), MeshSourceError> {
    let ply = read_ply(path).map_err(MeshSourceError::File)?;
    if recipe.weld.is_some() {
        return Err(MeshSourceError::Invalid {
            step: "weld",
            reason: "`weld` applies to OBJ input only; a PLY file shares its vertices between faces".into(),
        });
    }
    check(ply.mesh.n_elements())?;
    let mut corners = ply.mesh;
    for _ in 0..recipe.refine {
        corners = corners.refine_uniform();
    }
    let groups = if recipe.refine == 0 { ply.groups } else { Vec::new() };
    Ok((ShellMesh::from_tri3(corners, recipe.pair, chord_placement), groups))
}

/// A Gmsh file's mesh, refined (3-node files only) and upgraded with the file's own mid-edge nodes,
/// with its groups (none after refinement); `check` refuses an element count over the budget.
fn gmsh_mesh(
    path: &std::path::Path,
    recipe: &MeshRecipe,
    check: &dyn Fn(usize) -> Result<(), MeshSourceError>,
) -> Result<(ShellMesh, Vec<MeshGroup>), MeshSourceError> {
    let gmsh = read_gmsh(path).map_err(MeshSourceError::File)?;
    if recipe.weld.is_some() {
        return Err(MeshSourceError::Invalid {
            step: "weld",
            reason: "a Gmsh mesh shares its nodes between elements already; remove `weld`".into(),
        });
    }
    if recipe.refine > 0 && gmsh.mid_edge.is_some() {
        return Err(MeshSourceError::Invalid {
            step: "refine",
            reason: "a 6-node Gmsh mesh cannot be refined here (the new nodes would leave its curved geometry); \
                     refine it in Gmsh"
                .into(),
        });
    }
    check(gmsh.mesh.n_elements())?;
    let mut corners = gmsh.mesh;
    for _ in 0..recipe.refine {
        corners = corners.refine_uniform();
    }
    let groups = if recipe.refine == 0 { gmsh.groups } else { Vec::new() };
    let mesh = match gmsh.mid_edge {
        // The file's own mid-edge nodes, so curved elements stay curved.
        Some(mid) => ShellMesh::from_tri3(corners, recipe.pair, |node| match node {
            NewNode::Edge { vertices, .. } => mid.get(&vertices).copied().unwrap_or_else(|| node.chord()),
            NewNode::Interior { .. } => node.chord(),
        }),
        None => ShellMesh::from_tri3(corners, recipe.pair, chord_placement),
    };
    Ok((mesh, groups))
}

/// The shaping steps of the recipe: projection onto a sphere, flattening of a cap.
fn shape(mesh: &mut ShellMesh, recipe: &MeshRecipe) -> Result<(), MeshSourceError> {
    if let Some(projection) = recipe.project_to_sphere {
        map_nodes(mesh, |x, _| {
            let d = x - projection.center;
            let r = d.norm();
            if r > 0.0 {
                Ok(projection.center + d * (projection.radius / r))
            } else {
                Err(MeshSourceError::Invalid {
                    step: "project_to_sphere",
                    reason: "a node lies at the sphere's centre, where the radial direction is undefined".into(),
                })
            }
        })?;
    }
    if let Some(radius) = recipe.flatten_cap {
        map_nodes(mesh, |x, on_boundary| {
            let r = x.norm();
            if r == 0.0 {
                return Err(MeshSourceError::Invalid {
                    step: "flatten_cap",
                    reason: "a node lies at the origin, where the radial direction is undefined".into(),
                });
            }
            let on_sphere = x * (radius / r);
            let flat = Vector3::new(on_sphere.x, on_sphere.y, 0.0);
            let rho = flat.norm();
            if on_boundary {
                if rho == 0.0 {
                    return Err(MeshSourceError::Invalid {
                        step: "flatten_cap",
                        reason: "a boundary node lies on the z axis, so it cannot be pushed onto the circle".into(),
                    });
                }
                Ok(flat * (radius / rho))
            } else {
                Ok(flat)
            }
        })?;
    }
    Ok(())
}

/// For each edge of `topology` (built on `corners`), the Tri6 node on it.
pub(crate) fn tri6_edge_nodes(topology: &Topology, tri6: &TriMesh<6>) -> Vec<usize> {
    let mut nodes = vec![usize::MAX; topology.n_edges()];
    for f in 0..topology.n_faces() {
        for (k, e) in topology.face_edges(f).into_iter().enumerate() {
            nodes[e] = tri6.elements[f][3 + k];
        }
    }
    nodes
}

/// Applies `f(position, on_boundary)` to every node of the corner mesh and of the Tri6 mesh, so the
/// two stay consistent (a corner vertex and its Tri6 node get the same new position).
fn map_nodes(
    mesh: &mut ShellMesh,
    mut f: impl FnMut(&Vector3<f64>, bool) -> Result<Vector3<f64>, MeshSourceError>,
) -> Result<(), MeshSourceError> {
    let topology = Topology::new(&mesh.corners);
    let mut vertex_on_boundary = vec![false; mesh.corners.n_nodes()];
    let boundary = topology.boundary_edges();
    for &e in &boundary {
        for v in topology.edges()[e] {
            vertex_on_boundary[v] = true;
        }
    }
    for (v, x) in mesh.corners.nodes.iter_mut().enumerate() {
        *x = f(x, vertex_on_boundary[v])?;
    }
    if let Some(tri6) = &mut mesh.tri6 {
        let mut node_on_boundary = vec![false; tri6.n_nodes()];
        for (v, &node) in mesh.corner_nodes.iter().enumerate() {
            node_on_boundary[node] = vertex_on_boundary[v];
        }
        let edge_nodes = tri6_edge_nodes(&topology, tri6);
        for &e in &boundary {
            node_on_boundary[edge_nodes[e]] = true;
        }
        for (i, x) in tri6.nodes.iter_mut().enumerate() {
            *x = f(x, node_on_boundary[i])?;
        }
    }
    Ok(())
}

fn apply_transform(mesh: &mut ShellMesh, transform: &Transform) -> Result<(), MeshSourceError> {
    let rotated: Vec<Vector3<f64>> = mesh.corners.nodes.iter().map(|x| transform.rotation * x).collect();
    let (min, max) = bounding_box(&rotated);
    let center = if transform.center {
        (min + max) * 0.5
    } else {
        Vector3::zeros()
    };
    let scale = match transform.scaling {
        None => 1.0,
        Some(Scaling::Factor(s)) => s,
        Some(Scaling::Height(h)) => {
            let extent = max.z - min.z;
            if extent <= 0.0 {
                return Err(MeshSourceError::Invalid {
                    step: "transform.height",
                    reason: "the mesh has no extent along z, so it cannot be scaled to a height".into(),
                });
            }
            h / extent
        }
    };
    let map = |x: &Vector3<f64>| (transform.rotation * x - center) * scale + transform.translation;
    map_nodes(mesh, |x, _| Ok(map(x)))
}

/// An element count as messages show it: the counts saturate (an icosphere of level 40 has 20·4⁴⁰
/// triangles), and the saturated value is no count, so it reads as a bound.
fn count(n: usize) -> String {
    if n == usize::MAX {
        format!("at least {n}")
    } else {
        n.to_string()
    }
}

/// A failure of welding, which the file passed without it: the weld distance is the field to
/// change (a distance larger than a face collapses it), so the error names `weld`, with the file's
/// own message.
fn weld_error(tolerance: f64, error: ObjError) -> MeshSourceError {
    MeshSourceError::Invalid {
        step: "weld",
        reason: format!("merging the vertices closer than {tolerance:e} m breaks the mesh: {error}"),
    }
}

/// The axis-aligned bounding box of a non-empty point set.
pub(crate) fn bounding_box(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    let mut min = Vector3::repeat(f64::INFINITY);
    let mut max = Vector3::repeat(f64::NEG_INFINITY);
    for p in points {
        min = min.inf(p);
        max = max.sup(p);
    }
    (min, max)
}

/// See [`Generator::IcosphereCap`].
fn icosphere_cap(radius: f64, frequency: usize, min_z: f64) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "icosphere_cap";
    if !(radius.is_finite() && radius > 0.0) {
        return Err(MeshError::InvalidParameter {
            generator: NAME,
            parameter: "radius",
            value: radius,
            reason: "must be positive and finite",
        });
    }
    if !(1..=64).contains(&frequency) {
        return Err(MeshError::InvalidParameter {
            generator: NAME,
            parameter: "frequency",
            value: frequency as f64,
            reason: "must lie in 1..=64",
        });
    }
    if !min_z.is_finite() {
        return Err(MeshError::InvalidParameter {
            generator: NAME,
            parameter: "min_z",
            value: min_z,
            reason: "must be finite",
        });
    }
    let sphere = geodesic_icosphere(radius, frequency);
    let cap = GeneratedMesh {
        mesh: sphere,
        surface: Surface::Sphere { radius },
    };
    // The faces around the pole reach down to below `radius`; a `min_z` above all of them keeps
    // nothing, which `retain_faces` can only report as an empty result, not as this parameter.
    cap.retain_faces(|_, x| x.iter().all(|p| p.z >= min_z))
        .map_err(|_| MeshError::InvalidParameter {
            generator: NAME,
            parameter: "min_z",
            value: min_z,
            reason: "keeps no triangle: every triangle has a corner below it (it must lie below the radius, by at \
                     least the height of the triangles around the pole at this frequency)",
        })
}

/// The class-I geodesic sphere of the given frequency, a vertex at the north pole and a neighbour of
/// it at azimuth 0, outward normals.
fn geodesic_icosphere(radius: f64, frequency: usize) -> Tri3Mesh {
    let base = procedural::icosphere(1.0, 0).expect("the unit icosahedron is valid");
    // Vertex 5 = (0, 1, φ)/|·| goes to the pole, its neighbour 1 = (1, φ, 0)/|·| to azimuth 0.
    let pole = base.mesh.nodes[5];
    let neighbour = base.mesh.nodes[1];
    let x_axis = (neighbour - pole * neighbour.dot(&pole)).normalize();
    let y_axis = pole.cross(&x_axis);
    let rotation = Matrix3::from_rows(&[x_axis.transpose(), y_axis.transpose(), pole.transpose()]);
    let corners: Vec<Vector3<f64>> = base.mesh.nodes.iter().map(|p| rotation * p).collect();
    let n = frequency;
    let mut nodes: Vec<Vector3<f64>> = corners.iter().map(|p| p * radius).collect();
    // Vertices on icosahedron edges, keyed by (smaller corner, larger corner, steps from the smaller).
    let mut edge_vertices: HashMap<(usize, usize, usize), usize> = HashMap::new();
    let mut elements = Vec::with_capacity(20 * n * n);
    for face in &base.mesh.elements {
        let [a, b, c] = *face;
        // Grid point (i, j): barycentric ((n − i − j), i, j)/n with respect to (a, b, c).
        let mut grid = vec![vec![usize::MAX; n + 1]; n + 1];
        for i in 0..=n {
            for j in 0..=n - i {
                let k = n - i - j;
                let id = match (i, j, k) {
                    (0, 0, _) => a,
                    (_, 0, 0) => b,
                    (0, _, 0) => c,
                    _ => {
                        let on_edge = |p: usize, q: usize, steps_from_p: usize| {
                            if p < q {
                                (p, q, steps_from_p)
                            } else {
                                (q, p, n - steps_from_p)
                            }
                        };
                        let key = if j == 0 {
                            Some(on_edge(a, b, i))
                        } else if i == 0 {
                            Some(on_edge(a, c, j))
                        } else if k == 0 {
                            Some(on_edge(b, c, j))
                        } else {
                            None
                        };
                        let flat = (corners[a] * k as f64 + corners[b] * i as f64 + corners[c] * j as f64) / n as f64;
                        let position = flat.normalize() * radius;
                        match key {
                            Some(key) => *edge_vertices.entry(key).or_insert_with(|| {
                                nodes.push(position);
                                nodes.len() - 1
                            }),
                            None => {
                                nodes.push(position);
                                nodes.len() - 1
                            }
                        }
                    }
                };
                grid[i][j] = id;
            }
        }
        for i in 0..n {
            for j in 0..n - i {
                elements.push([grid[i][j], grid[i + 1][j], grid[i][j + 1]]);
                if i + j + 1 < n {
                    elements.push([grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]]);
                }
            }
        }
    }
    let mut mesh = TriMesh { nodes, elements };
    // Orient every face outwards.
    for f in 0..mesh.n_elements() {
        let x = mesh.element_nodes(f);
        let normal = (x[1] - x[0]).cross(&(x[2] - x[0]));
        if normal.dot(&(x[0] + x[1] + x[2])) < 0.0 {
            mesh.elements[f].swap(1, 2);
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geodesic_icosphere_has_the_class_one_counts_and_unit_vertices() {
        for n in 1..=4 {
            let mesh = geodesic_icosphere(2.0, n);
            assert_eq!(mesh.n_nodes(), 10 * n * n + 2, "frequency {n}");
            assert_eq!(mesh.n_elements(), 20 * n * n, "frequency {n}");
            assert!(mesh.nodes.iter().all(|p| (p.norm() - 2.0).abs() < 1e-12));
            mesh.validate().unwrap();
            assert_eq!(Topology::new(&mesh).boundary_edges().len(), 0);
        }
    }

    #[test]
    fn geodesic_icosphere_has_a_pole_vertex_and_a_neighbour_at_azimuth_zero() {
        let mesh = geodesic_icosphere(1.0, 1);
        assert!(mesh.nodes.iter().any(|p| (p - Vector3::z()).norm() < 1e-14));
        // The upper ring of the icosahedron: z = 1/√5, azimuths 0, ±72°, ±144°.
        let ring: Vec<f64> = mesh
            .nodes
            .iter()
            .filter(|p| (p.z - 1.0 / 5.0_f64.sqrt()).abs() < 1e-12)
            .map(|p| p.y.atan2(p.x).to_degrees())
            .collect();
        assert_eq!(ring.len(), 5);
        for expected in [0.0, 72.0, 144.0, -72.0, -144.0] {
            assert!(ring.iter().any(|a| (a - expected).abs() < 1e-9), "{ring:?}");
        }
    }
}

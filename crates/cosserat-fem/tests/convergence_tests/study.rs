//! The curvature refinement study: errors of |H| and K at the quadrature points of four
//! discretisations on a sphere and a cylinder, against the closed forms.
//!
//! Shared by the convergence tests and by `examples/curvature_convergence.rs`, which prints the tables
//! of `docs/curvature-convergence.md`.

use cosserat_fem::element::ShapeFunctions;
use cosserat_fem::mesh::procedural::{self, GeneratedMesh};
use cosserat_fem::mesh::{
    CurvatureSettings, CurvatureSource, MeshElement, NewNode, NormalWeighting, RestGeometry, Topology, rest_geometry,
};
use cosserat_fem::{QuadratureRule, Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// The ways of carrying curvature that the study compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discretisation {
    /// (a) Tri3 elements with angle-weighted averaged nodal normals, supplement 3-point rule.
    Tri3Averaged,
    /// (a′) As (a), with Max's weights (the crate's default weighting).
    Tri3AveragedMax,
    /// (b) Straight-edged Tri6 (chord midpoints) with averaged nodal normals of the corner mesh (Max's
    /// weights), supplement 3-point rule (the Tri6/Tri3 pairing).
    Tri6StraightAveraged,
    /// (c) Curved Tri6 (nodes on the surface) with the exact element normal, supplement 3-point rule.
    Tri6CurvedExact,
    /// (d) Curved Tri10 (nodes on the surface) with the exact element normal, degree-6 rule.
    Tri10CurvedExact,
}

impl Discretisation {
    /// All of them, in the order of the document.
    pub const ALL: [Self; 5] = [
        Self::Tri3Averaged,
        Self::Tri3AveragedMax,
        Self::Tri6StraightAveraged,
        Self::Tri6CurvedExact,
        Self::Tri10CurvedExact,
    ];

    /// A short label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::Tri3Averaged => "(a) Tri3, averaged normals, angle weights",
            Self::Tri3AveragedMax => "(a') Tri3, averaged normals, Max's weights",
            Self::Tri6StraightAveraged => "(b) straight Tri6, averaged normals, Max's weights",
            Self::Tri6CurvedExact => "(c) curved Tri6, exact normal",
            Self::Tri10CurvedExact => "(d) curved Tri10, exact normal",
        }
    }
}

/// The test surfaces with their exact curvatures (outward normals).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Unit sphere, icosphere levels 1–4: |H| = 1, K = 1.
    Sphere,
    /// Unit-radius cylinder of length 2, `12·2^k × 4·2^k` grids: |H| = ½, K = 0.
    Cylinder,
    /// Torus with radii `R = 1`, `r = 0.4` on a `24·2^k × 8·2^k` parameter grid whose vertices are
    /// jittered randomly (seeded) by up to 20 % of the spacing: curvature varies and changes sign, and
    /// the mesh has no symmetry to hide behind.
    JitteredTorus,
}

/// Torus radii of [`Shape::JitteredTorus`].
const TORUS: (f64, f64) = (1.0, 0.4);

fn torus_point(u: f64, v: f64) -> Vector3<f64> {
    let (big, small) = TORUS;
    let rho = big + small * v.cos();
    Vector3::new(rho * u.cos(), rho * u.sin(), small * v.sin())
}

/// The torus parameters of a point on (or near) the torus.
fn torus_parameters(p: &Vector3<f64>) -> (f64, f64) {
    (p.y.atan2(p.x), p.z.atan2(p.xy().norm() - TORUS.0))
}

impl Shape {
    /// The exact |H| and K at a point of the surface.
    pub fn exact_at(self, p: &Vector3<f64>) -> (f64, f64) {
        match self {
            Self::Sphere => (1.0, 1.0),
            Self::Cylinder => (0.5, 0.0),
            Self::JitteredTorus => {
                // Principal curvatures 1/r (around the tube) and cos v / (R + r cos v).
                let (big, small) = TORUS;
                let (_, v) = torus_parameters(p);
                let k2 = v.cos() / (big + small * v.cos());
                (0.5 * (1.0 / small + k2), k2 / small)
            }
        }
    }

    /// The generated mesh at refinement `level` (0 is the coarsest of the study) with the placement of
    /// new nodes on the exact surface.
    pub fn mesh(self, level: usize) -> Placed {
        match self {
            Self::Sphere => Placed::Generated(procedural::icosphere(1.0, level + 1).expect("valid parameters")),
            Self::Cylinder => {
                let k = 1 << level;
                Placed::Generated(procedural::cylinder(1.0, 2.0, 12 * k, 4 * k).expect("valid parameters"))
            }
            Self::JitteredTorus => Placed::Torus(jittered_torus(24 << level, 8 << level, 1000 + level as u64)),
        }
    }
}

/// A Tri3 mesh that knows how to place new nodes on its exact surface.
pub enum Placed {
    /// A mesh of the crate's generators.
    Generated(GeneratedMesh),
    /// A torus mesh with the torus parameters `(u, v)` of its vertices.
    Torus((Tri3Mesh, Vec<(f64, f64)>)),
}

impl Placed {
    fn mesh(&self) -> &Tri3Mesh {
        match self {
            Self::Generated(g) => &g.mesh,
            Self::Torus((m, _)) => m,
        }
    }

    /// Places a new node on the exact surface by interpolating surface parameters.
    fn place(&self, node: NewNode) -> Vector3<f64> {
        match self {
            Self::Generated(g) => g.place(node),
            Self::Torus((_, params)) => {
                let (vertices, weights): (Vec<usize>, Vec<f64>) = match node {
                    NewNode::Edge { vertices, t, .. } => (vertices.to_vec(), vec![1.0 - t, t]),
                    NewNode::Interior {
                        vertices, barycentric, ..
                    } => (vertices.to_vec(), barycentric.to_vec()),
                };
                let unwrap = |a: f64, reference: f64| a + TAU * ((reference - a) / TAU).round();
                let (u0, v0) = params[vertices[0]];
                let (mut u, mut v) = (0.0, 0.0);
                for (&i, &w) in vertices.iter().zip(&weights) {
                    u += w * unwrap(params[i].0, u0);
                    v += w * unwrap(params[i].1, v0);
                }
                torus_point(u, v)
            }
        }
    }

    fn to_tri6(&self) -> Tri6Mesh {
        self.mesh().to_tri6_with(|n| self.place(n))
    }

    fn to_tri10(&self) -> Tri10Mesh {
        self.mesh().to_tri10_with(|n| self.place(n))
    }
}

/// A periodic `n_u × n_v` grid on the torus with checkerboard diagonals, outward normals, and every
/// vertex moved in parameter space by a seeded random offset of up to 20 % of the spacing.
fn jittered_torus(n_u: usize, n_v: usize, seed: u64) -> (Tri3Mesh, Vec<(f64, f64)>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (du, dv) = (TAU / n_u as f64, TAU / n_v as f64);
    let mut params = Vec::with_capacity(n_u * n_v);
    for i in 0..n_u {
        for j in 0..n_v {
            let (ju, jv): (f64, f64) = (rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2));
            params.push(((i as f64 + ju) * du, (j as f64 + jv) * dv));
        }
    }
    let idx = |i: usize, j: usize| (i % n_u) * n_v + j % n_v;
    let mut elements = Vec::with_capacity(2 * n_u * n_v);
    for i in 0..n_u {
        for j in 0..n_v {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            if (i + j) % 2 == 0 {
                elements.extend([[a, b, c], [a, c, d]]);
            } else {
                elements.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let nodes = params.iter().map(|&(u, v)| torus_point(u, v)).collect();
    (Tri3Mesh::try_new(nodes, elements).expect("valid indices"), params)
}

/// Errors of one discretisation on one mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// The longest edge of the Tri3 mesh.
    pub h: f64,
    /// Max over quadrature points of ||H| − |H_exact||.
    pub max_h: f64,
    /// Area-weighted RMS over the surface of ||H| − |H_exact||.
    pub rms_h: f64,
    /// Max over quadrature points of |K − K_exact|.
    pub max_k: f64,
    /// Area-weighted RMS of |K − K_exact|.
    pub rms_k: f64,
}

fn longest_edge(mesh: &Tri3Mesh) -> f64 {
    Topology::new(mesh)
        .edges()
        .iter()
        .map(|&[a, b]| (mesh.nodes[a] - mesh.nodes[b]).norm())
        .fold(0.0, f64::max)
}

fn errors_of<const N: usize>(
    shape: Shape,
    mesh: &TriMesh<N>,
    geometry: &RestGeometry,
    rule: &QuadratureRule,
    h: f64,
) -> Errors
where
    TriMesh<N>: MeshElement<N>,
{
    let (mut max_h, mut max_k, mut sum_h, mut sum_k, mut area) = (0.0_f64, 0.0_f64, 0.0, 0.0, 0.0);
    for e in 0..geometry.n_elements() {
        let nodes = mesh.element_nodes(e);
        for (qp, (xi, w)) in rule.iter().enumerate() {
            let p = geometry.at(e, qp);
            let exact = shape.exact_at(&<TriMesh<N> as MeshElement<N>>::Element::position(&nodes, xi));
            let eh = (p.curvature.mean.abs() - exact.0).abs();
            let ek = (p.curvature.gaussian - exact.1).abs();
            let da = w * p.metric.area_element;
            max_h = max_h.max(eh);
            max_k = max_k.max(ek);
            sum_h += da * eh * eh;
            sum_k += da * ek * ek;
            area += da;
        }
    }
    Errors {
        h,
        max_h,
        rms_h: (sum_h / area).sqrt(),
        max_k,
        rms_k: (sum_k / area).sqrt(),
    }
}

/// Measures one discretisation on one mesh.
pub fn measure(shape: Shape, level: usize, discretisation: Discretisation) -> Errors {
    let placed = shape.mesh(level);
    let corner = placed.mesh();
    let h = longest_edge(corner);
    let p2 = QuadratureRule::interior_p2();
    let settings = |source| CurvatureSettings {
        source,
        ..CurvatureSettings::default()
    };
    let weighted = |weighting| CurvatureSettings {
        weighting,
        ..settings(CurvatureSource::AveragedNodalNormals)
    };
    let valid = "valid generated mesh";
    match discretisation {
        Discretisation::Tri3Averaged => {
            let g = rest_geometry(corner, corner, &p2, &weighted(NormalWeighting::Angle)).expect(valid);
            errors_of(shape, corner, &g, &p2, h)
        }
        Discretisation::Tri3AveragedMax => {
            let g = rest_geometry(corner, corner, &p2, &weighted(NormalWeighting::Max)).expect(valid);
            errors_of(shape, corner, &g, &p2, h)
        }
        Discretisation::Tri6StraightAveraged => {
            let tri6 = corner.to_tri6();
            let g = rest_geometry(&tri6, corner, &p2, &weighted(NormalWeighting::Max)).expect(valid);
            errors_of(shape, &tri6, &g, &p2, h)
        }
        Discretisation::Tri6CurvedExact => {
            let tri6 = placed.to_tri6();
            let g = rest_geometry(&tri6, corner, &p2, &settings(CurvatureSource::Auto)).expect(valid);
            errors_of(shape, &tri6, &g, &p2, h)
        }
        Discretisation::Tri10CurvedExact => {
            let p6 = QuadratureRule::dunavant_p6();
            let tri10 = placed.to_tri10();
            let g = rest_geometry(&tri10, corner, &p6, &settings(CurvatureSource::Auto)).expect(valid);
            errors_of(shape, &tri10, &g, &p6, h)
        }
    }
}

/// The least-squares slope of `log(error)` against `log(h)`: the observed order of convergence.
pub fn fitted_order(h: &[f64], error: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = error.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

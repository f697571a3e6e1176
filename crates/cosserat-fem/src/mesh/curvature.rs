//! Rest curvature at every (element, quadrature point): the metric `SurfaceMetric` and the curvature
//! `Curvature` (b, H, K) the curved-shell energy needs.
//!
//! The tangent `G` always comes from the displacement element. The normal field comes from the choice
//! of [`CurvatureSource`]: the exact element normal for genuinely curved elements, averaged nodal
//! normals of the corner (rotation) mesh for flat ones. Piecewise-flat geometry has `b = 0` with the
//! exact normal (model.md §8.3), so `Auto` switches per element.

use super::normals::{AveragedNodalNormals, NormalSample, NormalWeighting, exact_normal};
use super::tri_mesh::{MeshElement, Tri3Mesh, TriMesh};
use crate::element::{ShapeFunctions, Tri3};
use crate::error::MeshError;
use crate::quadrature::QuadratureRule;
use cosserat_geometry::surface::{Curvature, SurfaceMetric};
use nalgebra::Vector3;

/// Which normal field defines the rest curvature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CurvatureSource {
    /// The element's own normal (exact for the element geometry). Zero curvature on flat elements.
    ExactElement,
    /// Averaged nodal normals of the corner mesh, interpolated linearly and normalised.
    AveragedNodalNormals,
    /// The exact element normal where the element is genuinely curved (some node off the affine map
    /// of its corners, see [`CurvatureSettings::curved_tolerance`]), averaged nodal normals elsewhere.
    #[default]
    Auto,
}

/// The normal field actually used for an element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalField {
    /// The exact element normal.
    ExactElement,
    /// Averaged nodal normals.
    AveragedNodalNormals,
}

/// Settings of [`rest_geometry`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureSettings {
    /// The normal field. Default: [`CurvatureSource::Auto`].
    pub source: CurvatureSource,
    /// Weighting of face normals for averaged nodal normals. Default: [`NormalWeighting::Max`].
    pub weighting: NormalWeighting,
    /// An element counts as curved when some node lies farther than this fraction of the element size
    /// (its longest corner edge) from the affine map of its corners. Default `1e-9`, far above
    /// round-off of chord midpoints and far below any intended curvature.
    pub curved_tolerance: f64,
}

impl Default for CurvatureSettings {
    fn default() -> Self {
        Self {
            source: CurvatureSource::Auto,
            weighting: NormalWeighting::Max,
            curved_tolerance: 1e-9,
        }
    }
}

/// Metric and curvature at one quadrature point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointGeometry {
    /// The metric from the element tangent `G`.
    pub metric: SurfaceMetric<f64>,
    /// `b` (tangential, symmetric), `H` and `K` from the chosen normal field.
    pub curvature: Curvature<f64>,
}

/// Per (element, quadrature point) rest geometry, stored flat: point `qp` of element `e` is entry
/// `e · n_points + qp`.
#[derive(Debug, Clone, PartialEq)]
pub struct RestGeometry {
    n_points: usize,
    points: Vec<PointGeometry>,
    fields: Vec<NormalField>,
}

impl RestGeometry {
    /// The number of quadrature points per element.
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// The number of elements.
    pub fn n_elements(&self) -> usize {
        self.fields.len()
    }

    /// The geometry of point `qp` of element `elem_idx`.
    ///
    /// # Panics
    /// If an index is out of range.
    #[track_caller]
    pub fn at(&self, elem_idx: usize, qp: usize) -> &PointGeometry {
        assert!(qp < self.n_points, "quadrature point {qp} out of range");
        &self.points[elem_idx * self.n_points + qp]
    }

    /// All points, element by element.
    pub fn points(&self) -> &[PointGeometry] {
        &self.points
    }

    /// The normal field used for each element.
    pub fn normal_fields(&self) -> &[NormalField] {
        &self.fields
    }
}

/// How far the nodes of an element lie from the affine map of its corners, relative to the longest
/// corner edge: `max_i |xᵢ − x_affine(ξᵢ)| / h`. Zero for Tri3 and for straight-edged upgrades (up to
/// round-off).
pub fn deviation_from_affine<E: ShapeFunctions<N>, const N: usize>(nodes: &[Vector3<f64>; N]) -> f64 {
    let corners = [nodes[0], nodes[1], nodes[2]];
    let h = (0..3).map(|k| (corners[(k + 1) % 3] - corners[k]).norm()).fold(0.0, f64::max);
    let deviation = E::nodes()
        .iter()
        .zip(nodes.iter())
        .map(|(&xi, x)| (Tri3::position(&corners, xi) - x).norm())
        .fold(0.0, f64::max);
    if h > 0.0 { deviation / h } else { 0.0 }
}

/// The rest metric and curvature at every quadrature point of `mesh`.
///
/// `corner_mesh` is the Tri3 rotation mesh of `mesh`: the same elements in the same order, with
/// vertices at the element corners (the upgraded-from Tri3 mesh, or [`TriMesh::corner_mesh`]). It
/// supplies the vertex adjacency of averaged nodal normals. Curvature uses
/// [`Curvature::from_normal_gradient`], i.e. the tangential symmetric part of `b = −∇_ξ n G⁺`.
///
/// # Errors
/// - [`MeshError::CornerMeshMismatch`] if `corner_mesh` has another element count or other corner
///   positions (relative tolerance 1e-9 of the element size);
/// - [`MeshError::DegenerateElement`] if the tangent is degenerate at a quadrature point (`area` is
///   ½ of the area element there);
/// - [`MeshError::NodeIndexOutOfRange`] for bad indices.
pub fn rest_geometry<const N: usize>(
    mesh: &TriMesh<N>,
    corner_mesh: &Tri3Mesh,
    rule: &QuadratureRule,
    settings: &CurvatureSettings,
) -> Result<RestGeometry, MeshError>
where
    TriMesh<N>: MeshElement<N>,
{
    rest_geometry_impl::<<TriMesh<N> as MeshElement<N>>::Element, N>(mesh, corner_mesh, rule, settings)
}

fn rest_geometry_impl<E: ShapeFunctions<N>, const N: usize>(
    mesh: &TriMesh<N>,
    corner_mesh: &Tri3Mesh,
    rule: &QuadratureRule,
    settings: &CurvatureSettings,
) -> Result<RestGeometry, MeshError> {
    mesh.check_indices()?;
    corner_mesh.check_indices()?;
    check_corner_mesh(mesh, corner_mesh)?;
    let fields: Vec<NormalField> = (0..mesh.n_elements())
        .map(|e| match settings.source {
            CurvatureSource::ExactElement => NormalField::ExactElement,
            CurvatureSource::AveragedNodalNormals => NormalField::AveragedNodalNormals,
            CurvatureSource::Auto => {
                if deviation_from_affine::<E, N>(&mesh.element_nodes(e)) > settings.curved_tolerance {
                    NormalField::ExactElement
                } else {
                    NormalField::AveragedNodalNormals
                }
            }
        })
        .collect();
    let averaged = if fields.contains(&NormalField::AveragedNodalNormals) {
        Some(AveragedNodalNormals::try_new(corner_mesh, settings.weighting)?)
    } else {
        None
    };
    let mut points = Vec::with_capacity(mesh.n_elements() * rule.n_points());
    for (elem_idx, field) in fields.iter().enumerate() {
        let nodes = mesh.element_nodes(elem_idx);
        for &xi in rule.points() {
            let tangent = E::tangent(&nodes, xi);
            let metric = SurfaceMetric::try_new(&tangent).map_err(|_| MeshError::DegenerateElement {
                elem_idx,
                area: 0.5 * tangent.column(0).cross(&tangent.column(1)).norm(),
            })?;
            let sample: NormalSample = match (field, &averaged) {
                (NormalField::AveragedNodalNormals, Some(avg)) => avg.evaluate(elem_idx, xi)?,
                // The metric exists at this point, so the exact normal does too.
                _ => exact_normal::<E, N>(&nodes, xi).map_err(|_| MeshError::DegenerateElement {
                    elem_idx,
                    area: 0.5 * metric.area_element,
                })?,
            };
            points.push(PointGeometry {
                metric,
                curvature: Curvature::from_normal_gradient(&metric, &sample.gradient),
            });
        }
    }
    Ok(RestGeometry {
        n_points: rule.n_points(),
        points,
        fields,
    })
}

fn check_corner_mesh<const N: usize>(mesh: &TriMesh<N>, corner_mesh: &Tri3Mesh) -> Result<(), MeshError> {
    if mesh.n_elements() != corner_mesh.n_elements() {
        return Err(MeshError::CornerMeshMismatch {
            reason: format!(
                "{} elements in the element mesh, {} in the corner mesh",
                mesh.n_elements(),
                corner_mesh.n_elements()
            ),
        });
    }
    for e in 0..mesh.n_elements() {
        let a = mesh.element_corners(e).map(|i| mesh.nodes[i]);
        let b = corner_mesh.element_nodes(e);
        let h = (0..3).map(|k| (a[(k + 1) % 3] - a[k]).norm()).fold(0.0, f64::max);
        let d = (0..3).map(|k| (a[k] - b[k]).norm()).fold(0.0, f64::max);
        if d.is_nan() || d > 1e-9 * h {
            return Err(MeshError::CornerMeshMismatch {
                reason: format!("the corners of element {e} differ by {d:e}"),
            });
        }
    }
    Ok(())
}

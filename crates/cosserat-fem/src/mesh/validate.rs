//! Mesh validation: finite coordinates, non-degenerate elements, no unreferenced nodes, manifold edges
//! and no doubled elements.
//!
//! A simulation must never start from a mesh that would produce a singular metric (and hence NaN) at
//! some quadrature point, so every element is checked at its nodes and at the quadrature points of
//! the rules the model uses for it.

use super::topology::Topology;
use super::tri_mesh::{MeshElement, TriMesh};
use crate::element::ShapeFunctions;
use crate::error::MeshError;
use crate::quadrature::QuadratureRule;
use cosserat_geometry::surface::SurfaceMetric;
use nalgebra::Vector3;
use std::collections::HashMap;

impl<const N: usize> TriMesh<N> {
    /// Checks that every node coordinate is finite.
    ///
    /// # Errors
    /// [`MeshError::NonFiniteNode`] for the first node with a NaN or infinite coordinate.
    pub fn check_finite(&self) -> Result<(), MeshError> {
        match self.nodes.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            None => Ok(()),
            Some(node_idx) => Err(MeshError::NonFiniteNode { node_idx }),
        }
    }

    /// Checks that every node is used by some element.
    ///
    /// # Errors
    /// [`MeshError::UnreferencedNode`] for the first unused node, and
    /// [`MeshError::NodeIndexOutOfRange`] if an element refers to a missing node.
    pub fn check_unreferenced(&self) -> Result<(), MeshError> {
        self.check_indices()?;
        let mut used = vec![false; self.n_nodes()];
        for elem in &self.elements {
            for &i in elem {
                used[i] = true;
            }
        }
        match used.iter().position(|&u| !u) {
            None => Ok(()),
            Some(node_idx) => Err(MeshError::UnreferencedNode { node_idx }),
        }
    }

    /// Checks that no edge (between corner nodes) is shared by more than two elements, and that no two
    /// elements have the same corners: a doubled triangle passes the edge count (each of its edges has
    /// two faces) but is no surface.
    ///
    /// # Errors
    /// [`MeshError::NonManifoldEdge`] for the first such edge, [`MeshError::DuplicateElement`] for the
    /// first element that repeats the corners of an earlier one, and
    /// [`MeshError::NodeIndexOutOfRange`] if an element refers to a missing node.
    pub fn check_manifold_edges(&self) -> Result<(), MeshError> {
        self.check_indices()?;
        Topology::new(self).check_manifold_edges()?;
        self.check_duplicate_elements()
    }

    /// The first element whose corner set (in any order or orientation) an earlier element has.
    fn check_duplicate_elements(&self) -> Result<(), MeshError> {
        let mut seen: HashMap<[usize; 3], usize> = HashMap::with_capacity(self.n_elements());
        for second in 0..self.n_elements() {
            let mut corners = self.element_corners(second);
            corners.sort_unstable();
            if let Some(&first) = seen.get(&corners) {
                return Err(MeshError::DuplicateElement { first, second });
            }
            seen.insert(corners, second);
        }
        Ok(())
    }
}

impl<const N: usize> TriMesh<N>
where
    TriMesh<N>: MeshElement<N>,
{
    /// Checks that no element is degenerate.
    ///
    /// The area element `|x,₁ × x,₂|` is evaluated at the element's nodes, at the supplement's
    /// 3-point rule and at the rule of degree `2·p` (`p` the element degree). An element fails when
    /// the tangent vectors are zero or parallel at one of those points (coincident or collinear
    /// nodes, see [`SurfaceMetric::try_new`]) or when its normal turns by more than 90° with respect
    /// to the normal at the centroid (a folded curved element, whose area element changes sign).
    ///
    /// # Errors
    /// [`MeshError::DegenerateElement`] for the first failing element. Its `area` is the area of a
    /// Tri3 element; for a curved element it is `½ J`, with `J` the smallest signed area element
    /// found (measured along the centroid normal).
    /// [`MeshError::NodeIndexOutOfRange`] and [`MeshError::NonFiniteNode`] are checked first.
    pub fn check_degenerate(&self) -> Result<(), MeshError> {
        self.check_indices()?;
        self.check_finite()?;
        check_elements::<<Self as MeshElement<N>>::Element, N>(self)
    }

    /// Runs every check: indices, finite coordinates, degenerate elements, unreferenced nodes and
    /// non-manifold edges, in that order.
    ///
    /// # Errors
    /// The first failure, as in the individual checks.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.check_degenerate()?;
        self.check_unreferenced()?;
        self.check_manifold_edges()
    }
}

fn check_elements<E: ShapeFunctions<N>, const N: usize>(mesh: &TriMesh<N>) -> Result<(), MeshError> {
    let high = QuadratureRule::for_degree(2 * E::DEGREE).unwrap_or_else(QuadratureRule::dunavant_p8);
    let samples: Vec<[f64; 2]> = E::nodes()
        .into_iter()
        .chain(QuadratureRule::interior_p2().points().iter().copied())
        .chain(high.points().iter().copied())
        .collect();
    for elem_idx in 0..mesh.n_elements() {
        check_element::<E, N>(elem_idx, &mesh.element_nodes(elem_idx), &samples)?;
    }
    Ok(())
}

fn check_element<E: ShapeFunctions<N>, const N: usize>(
    elem_idx: usize,
    nodes: &[Vector3<f64>; N],
    samples: &[[f64; 2]],
) -> Result<(), MeshError> {
    let centroid = [1.0 / 3.0, 1.0 / 3.0];
    let degenerate = |j: f64| MeshError::DegenerateElement {
        elem_idx,
        area: 0.5 * j,
    };
    let t0 = E::tangent(nodes, centroid);
    let reference = SurfaceMetric::try_new(&t0).map_err(|_| degenerate(t0.column(0).cross(&t0.column(1)).norm()))?;
    if E::DEGREE == 1 {
        // Constant tangent: the centroid check is the whole check, and the area is exact.
        return Ok(());
    }
    for &xi in samples {
        let t = E::tangent(nodes, xi);
        let signed = t.column(0).cross(&t.column(1)).dot(&reference.normal);
        let ok = SurfaceMetric::try_new(&t).map(|m| m.normal.dot(&reference.normal) > 0.0);
        if ok != Ok(true) {
            return Err(degenerate(signed));
        }
    }
    Ok(())
}

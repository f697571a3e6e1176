//! One contact pair: its barrier energy with derivatives, and its lagged friction potential.
//!
//! A point–triangle pair has energy `b(d − δ)`; an edge–edge pair `m(c) b(d − δ)` with IPC's mollifier
//! (see [`crate::mollifier`]). Derivatives come from the squared-distance jet of [`crate::distance`] by
//! the chain rule through `s ↦ b(√s − δ)` and the product rule with the mollifier's jet.
//!
//! Friction is lagged (IPC): the normal force `λ = |∂E/∂d|`, the closest-point weights `β` and the
//! tangent basis `T` are taken from the configuration at the start of the step and held fixed, so the
//! friction potential of the step is a function of the displacements alone (see [`crate::friction`]).

use crate::barrier::Barrier;
use crate::distance::{
    EdgeEdgeFeature, PointTriangleFeature, edge_edge_distance, edge_edge_jet, edge_edge_weights,
    point_triangle_distance, point_triangle_jet, point_triangle_weights,
};
use crate::friction::FrictionSmoothing;
use crate::jet::PairJet;
use crate::mollifier::{Mollifier, cross_squared, cross_squared_jet};
use nalgebra::{Matrix3x2, SMatrix, Vector2, Vector3};

/// The two kinds of contact pairs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PairKind {
    /// A point and a triangle: vertices `[p, t₀, t₁, t₂]`.
    PointTriangle,
    /// Two edges: vertices `[a₀, a₁, b₀, b₁]`.
    EdgeEdge,
}

impl PairKind {
    /// A name for messages.
    pub fn name(self) -> &'static str {
        match self {
            PairKind::PointTriangle => "point-triangle",
            PairKind::EdgeEdge => "edge-edge",
        }
    }
}

/// The closest features of a pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairFeature {
    /// Of a point–triangle pair.
    PointTriangle(PointTriangleFeature),
    /// Of an edge–edge pair.
    EdgeEdge(EdgeEdgeFeature),
}

/// A candidate contact pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    /// Point–triangle or edge–edge.
    pub kind: PairKind,
    /// The four contact vertices.
    pub vertices: [u32; 4],
    /// `(vertex, triangle)` or `(edge, edge)` in contact-mesh indices.
    pub primitives: [u32; 2],
    /// The sum of the two bodies' thicknesses `δ` \[m\].
    pub thickness: f64,
    /// The mollifier of an edge–edge pair.
    pub mollifier: Option<Mollifier>,
    /// Friction coefficient `μ` of the two bodies.
    pub friction: f64,
}

impl ContactPair {
    /// The closest features and the squared distance of the pair at positions `x`.
    pub fn classify(&self, x: &[Vector3<f64>; 4]) -> (PairFeature, f64) {
        match self.kind {
            PairKind::PointTriangle => {
                let (f, s) = point_triangle_distance(x);
                (PairFeature::PointTriangle(f), s)
            }
            PairKind::EdgeEdge => {
                let (f, s) = edge_edge_distance(x);
                (PairFeature::EdgeEdge(f), s)
            }
        }
    }

    /// The gap `d − δ` \[m\].
    pub fn gap(&self, x: &[Vector3<f64>; 4]) -> f64 {
        self.classify(x).1.sqrt() - self.thickness
    }

    fn mollifier_value(&self, x: &[Vector3<f64>; 4]) -> f64 {
        self.mollifier.map_or(1.0, |m| m.value(cross_squared(x)))
    }

    /// The barrier energy \[J\]: `+∞` if the gap is not positive, zero beyond the barrier width.
    pub fn energy(&self, x: &[Vector3<f64>; 4], barrier: &Barrier) -> f64 {
        let g = self.gap(x);
        if !barrier.is_active(g) {
            return 0.0;
        }
        let b = barrier.value(g);
        if b.is_finite() { b * self.mollifier_value(x) } else { b }
    }

    /// The barrier energy with its gradient and Hessian with respect to the twelve coordinates, or
    /// `None` when the pair is out of reach (zero energy). A non-positive gap gives an infinite value.
    pub fn energy_jet(&self, x: &[Vector3<f64>; 4], barrier: &Barrier) -> Option<PairJet> {
        let (feature, s) = self.classify(x);
        let g = s.sqrt() - self.thickness;
        if !barrier.is_active(g) {
            return None;
        }
        if !(g > 0.0) {
            let mut jet = PairJet::zeros();
            jet.value = f64::INFINITY;
            return Some(jet);
        }
        let distance = match feature {
            PairFeature::PointTriangle(f) => point_triangle_jet(x, f),
            PairFeature::EdgeEdge(f) => edge_edge_jet(x, f),
        };
        let (e, de, d2e) = barrier.of_squared_distance(s, self.thickness);
        let energy = distance.compose(e, de, d2e);
        match self.mollifier {
            Some(m) if m.is_active(cross_squared(x)) => {
                let c = cross_squared_jet(x);
                let (mv, dm, d2m) = m.derivatives(c.value);
                Some(PairJet::product(&energy, &c.compose(mv, dm, d2m)))
            }
            _ => Some(energy),
        }
    }

    /// The normal force magnitude `λ = m |b'(d − δ)|` \[N\] (zero out of reach).
    pub fn normal_force(&self, x: &[Vector3<f64>; 4], barrier: &Barrier) -> f64 {
        let g = self.gap(x);
        if !barrier.is_active(g) || !(g > 0.0) {
            return 0.0;
        }
        barrier.derivatives(g).1.abs() * self.mollifier_value(x)
    }

    /// Weights `β` with `Σ βᵢ xᵢ` = the vector between the pair's closest points.
    pub fn closest_weights(&self, x: &[Vector3<f64>; 4]) -> [f64; 4] {
        match self.classify(x).0 {
            PairFeature::PointTriangle(f) => point_triangle_weights(x, f),
            PairFeature::EdgeEdge(f) => edge_edge_weights(x, f),
        }
    }
}

/// The lagged friction data of one pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionPair {
    /// The four contact vertices.
    pub vertices: [u32; 4],
    /// Closest-point weights `β` of the lagged configuration.
    pub weights: [f64; 4],
    /// Orthonormal tangent basis `T` of the lagged configuration.
    pub basis: Matrix3x2<f64>,
    /// `μ λ` \[N\].
    pub force: f64,
}

/// An orthonormal basis of the plane normal to the unit vector `n`.
pub fn tangent_basis(n: &Vector3<f64>) -> Matrix3x2<f64> {
    let a = n.abs();
    let axis = if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let e1 = n.cross(&axis).normalize();
    let e2 = n.cross(&e1);
    Matrix3x2::from_columns(&[e1, e2])
}

impl FrictionPair {
    /// The lagged friction of `pair` at its start-of-step positions `x`, or `None` if the pair is out of
    /// reach, frictionless, or its closest points coincide.
    pub fn from_lagged(pair: &ContactPair, x: &[Vector3<f64>; 4], barrier: &Barrier) -> Option<Self> {
        if !(pair.friction > 0.0) {
            return None;
        }
        let lambda = pair.normal_force(x, barrier);
        if !(lambda > 0.0 && lambda.is_finite()) {
            return None;
        }
        let weights = pair.closest_weights(x);
        let normal: Vector3<f64> = (0..4).map(|i| x[i] * weights[i]).sum();
        let length = normal.norm();
        if !(length > 0.0) {
            return None;
        }
        Some(Self {
            vertices: pair.vertices,
            weights,
            basis: tangent_basis(&(normal / length)),
            force: pair.friction * lambda,
        })
    }

    /// The tangential relative displacement `z = Tᵀ Σ βᵢ Δxᵢ` \[m\].
    pub fn tangential(&self, dx: &[Vector3<f64>; 4]) -> Vector2<f64> {
        let rel: Vector3<f64> = (0..4).map(|i| dx[i] * self.weights[i]).sum();
        self.basis.transpose() * rel
    }

    /// The friction potential `μ λ f₀(|z|)` \[J\] for vertex displacements `dx` over the step.
    pub fn energy(&self, dx: &[Vector3<f64>; 4], smoothing: &FrictionSmoothing) -> f64 {
        self.force * smoothing.f0(self.tangential(dx).norm())
    }

    /// The friction potential with its gradient and Hessian with respect to the displacements.
    pub fn energy_jet(&self, dx: &[Vector3<f64>; 4], smoothing: &FrictionSmoothing) -> PairJet {
        let (f, g, h) = smoothing.potential(&self.tangential(dx));
        let tg = self.basis * g * self.force;
        let tht = self.basis * h * self.basis.transpose() * self.force;
        let mut jet = PairJet::zeros();
        jet.value = self.force * f;
        for i in 0..4 {
            jet.gradient.fixed_rows_mut::<3>(3 * i).copy_from(&(tg * self.weights[i]));
            for j in 0..4 {
                jet.hessian
                    .fixed_view_mut::<3, 3>(3 * i, 3 * j)
                    .copy_from(&(tht * (self.weights[i] * self.weights[j])));
            }
        }
        jet
    }
}

/// Projects a pair Hessian onto the positive semi-definite cone, after removing the rows and columns of
/// the points not in `keep` (obstacle vertices, which are not unknowns).
pub fn project_psd(h: &SMatrix<f64, 12, 12>, keep: [bool; 4]) -> SMatrix<f64, 12, 12> {
    let mut m = *h;
    for i in 0..12 {
        for j in 0..12 {
            if !keep[i / 3] || !keep[j / 3] {
                m[(i, j)] = 0.0;
            }
        }
    }
    let m = (m + m.transpose()) * 0.5;
    let eig = m.symmetric_eigen();
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return m;
    }
    let clamped = eig.eigenvalues.map(|l| l.max(0.0));
    eig.eigenvectors * SMatrix::<f64, 12, 12>::from_diagonal(&clamped) * eig.eigenvectors.transpose()
}

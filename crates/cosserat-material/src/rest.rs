//! The rest state of a shell: per quadrature point the shape data, the rest frame, the integration
//! weight and the density Hessian, computed once from the rest mesh.
//!
//! The displacement tangent `G` defines the rest frame `Q = [t₁ t₂ n₀]` and `P = G⁺ [t₁ t₂]`, which turns
//! reference gradients into derivatives along the orthonormal tangents. The curvature (`b`, `H`, `K`)
//! is computed only for the shell model, from a continuous normal field (`cosserat_fem::mesh::
//! rest_geometry`): the exact element normal on curved elements and averaged nodal normals on flat ones,
//! so a faceted (Tri3 or straight-edged Tri6) mesh of a curved surface still carries its curvature.
//! Points whose `b` vanishes share one density matrix with the plate terms; curved points get their own.

use crate::assumed::{
    AssumedParts, ElementTying, MembraneTying, N_TYING, PointBasis, TiedValues, TyingMap, TyingTwins,
    restabilize_shear_and_drilling, stabilize_shear_and_drilling, tying_maps, tying_points,
};
use crate::error::RestStateError;
use crate::kernel::PointShape;
use crate::model::{ModelOptions, ShellModel, TermSet};
use crate::parameters::Moduli;
use crate::projection::{StabilizationConstants, StrainInterpolation, StrainProjection};
use crate::strain_space::{DensityTable, StrainHessians, StrainMatrix, local_geometry, strain_hessian};
use cosserat_fem::mesh::{CurvatureSettings, MeshElement, Tri3Mesh, rest_geometry};
use cosserat_fem::{MeshError, QuadratureRule, ShapeFunctions, TriMesh};
use cosserat_geometry::surface::{Curvature, SurfaceMetric};
use nalgebra::{Matrix2, Matrix3, Vector3};
use rayon::prelude::*;
use std::borrow::Cow;

/// Options of the rest-state computation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestOptions {
    /// The model.
    pub model: ModelOptions,
    /// Where the rest curvature comes from (shell model only).
    pub curvature: CurvatureSettings,
    /// A point counts as flat when `|b|_F · √A_e` is below this (dimensionless; `A_e` the element's
    /// area). Default `1e-8`.
    pub flat_tolerance: f64,
    /// How the points' strains enter the energy. Default [`StrainInterpolation::Paper`].
    pub interpolation: StrainInterpolation,
    /// The constants of [`StrainInterpolation::Stabilized`] (those of
    /// [`StrainInterpolation::ReggeStabilized`] depend on the pair:
    /// [`StabilizationConstants::regge_stabilized`]).
    pub stabilization: StabilizationConstants,
    /// The parts that take assumed values under [`StrainInterpolation::Assumed`].
    pub assumed_parts: AssumedParts,
}

impl RestOptions {
    /// Default options for a model.
    pub fn new(model: ModelOptions) -> Self {
        Self {
            model,
            curvature: CurvatureSettings::default(),
            flat_tolerance: 1e-8,
            interpolation: StrainInterpolation::Paper,
            stabilization: StabilizationConstants::DEFAULT,
            assumed_parts: AssumedParts::ALL,
        }
    }
}

/// The rest state of one shell with `NU`-node displacement and `NR`-node rotation elements.
#[derive(Debug, Clone)]
pub struct ShellRest<const NU: usize, const NR: usize> {
    /// Points per element: its quadrature points, then (under [`StrainInterpolation::Assumed`]) its
    /// tying points, whose integration weights are zero.
    pub points_per_element: usize,
    /// Quadrature points per element.
    pub quadrature_points_per_element: usize,
    /// Shape data per point (element-major).
    pub shapes: Vec<PointShape<NU, NR>>,
    /// Rest position of each point.
    pub point_positions: Vec<Vector3<f64>>,
    /// Rest curvature of each point (zero under the plate model, where it is not computed).
    pub curvature: Vec<Curvature<f64>>,
    /// Density Hessian per point.
    pub densities: DensityTable,
    /// Names of the active energy terms (union over points).
    pub active_terms: Vec<String>,
    /// Whether the nonlinear volume term is active.
    pub nonlinear_volume: bool,
    /// Number of points treated as curved.
    pub n_curved_points: usize,
    /// Rest area of each element (sum of its point weights) \[m²\].
    pub element_areas: Vec<f64>,
    /// The strain projection of each element under [`StrainInterpolation::Stabilized`] (empty under
    /// [`StrainInterpolation::Paper`]).
    pub projections: Vec<StrainProjection>,
    /// The tying maps of each quadrature point under [`StrainInterpolation::Assumed`] (element-major,
    /// [`Self::quadrature_points_per_element`] per element; empty otherwise).
    pub tying_maps: Vec<TyingMap>,
    /// The tied values of each element under [`StrainInterpolation::Assumed`] (empty otherwise).
    pub tied_values: Vec<TiedValues>,
    /// The tying points that lie on quadrature points (the same for every element).
    pub tying_twins: TyingTwins,
    /// The shear and drilling factors stabilised into each element's tying maps under
    /// [`StrainInterpolation::ReggeStabilized`] (empty otherwise), which a stretched element raises
    /// ([`Self::element_tying_maps_in_tension`]).
    pub tying_stabilization: Vec<StrainProjection>,
}

impl<const NU: usize, const NR: usize> ShellRest<NU, NR> {
    /// The tying maps of element `e`'s quadrature points, under [`StrainInterpolation::Assumed`].
    pub fn element_tying_maps(&self, e: usize) -> Option<&[TyingMap]> {
        let n = self.quadrature_points_per_element;
        self.tying_maps.get(e * n..(e + 1) * n)
    }

    /// The assumed strains of element `e` with `maps` at its quadrature points (its rest maps or those
    /// in tension, [`Self::element_tying_maps_in_tension`]).
    pub fn element_tying<'a>(&'a self, e: usize, maps: &'a [TyingMap]) -> ElementTying<'a> {
        let first = e * self.points_per_element;
        let quadrature =
            (first..first + self.quadrature_points_per_element).map(|p| (self.shapes[p].weight, self.densities.get(p)));
        ElementTying::new(&self.tied_values[e], maps, self.tying_twins, NR == 6, quadrature)
    }

    /// The tying maps of element `e` under the membrane stress `tension` (of its mean stretch,
    /// [`crate::tension::membrane_tension`]): the rest maps, or under
    /// [`StrainInterpolation::ReggeStabilized`] those with the shear and drilling factors that keep the
    /// stretched element stable ([`StrainProjection::held_in_tension`]).
    pub fn element_tying_maps_in_tension(&self, e: usize, tension: f64) -> Option<Cow<'_, [TyingMap]>> {
        let maps = self.element_tying_maps(e)?;
        let Some(rest) = self.tying_stabilization.get(e) else {
            return Some(Cow::Borrowed(maps));
        };
        // The element's first quadrature point stands for its stiffness against a turn of the directors.
        let held = rest.held_in_tension(tension, self.densities.get(e * self.points_per_element));
        if held == *rest {
            return Some(Cow::Borrowed(maps));
        }
        let mut maps = maps.to_vec();
        restabilize_shear_and_drilling(&mut maps, rest, &held);
        Some(Cow::Owned(maps))
    }
}

/// Computes the rest state of a shell.
///
/// `disp` is the displacement mesh; `rot` the rotation mesh with the same elements in the same order;
/// `corner` the Tri3 corner mesh of `disp` (the rotation mesh itself for Tri3 rotations), used for
/// averaged nodal normals.
///
/// # Errors
/// Degenerate elements (named by index), mismatched meshes, invalid material or model.
pub fn shell_rest<const NU: usize, const NR: usize>(
    disp: &TriMesh<NU>,
    rot: &TriMesh<NR>,
    corner: &Tri3Mesh,
    rule: &QuadratureRule,
    options: &RestOptions,
    moduli: &Moduli,
) -> Result<ShellRest<NU, NR>, RestStateError>
where
    TriMesh<NU>: MeshElement<NU>,
    TriMesh<NR>: MeshElement<NR>,
{
    shell_rest_impl::<<TriMesh<NU> as MeshElement<NU>>::Element, <TriMesh<NR> as MeshElement<NR>>::Element, NU, NR>(
        disp, rot, corner, rule, options, moduli,
    )
}

fn shell_rest_impl<E: ShapeFunctions<NU>, F: ShapeFunctions<NR>, const NU: usize, const NR: usize>(
    disp: &TriMesh<NU>,
    rot: &TriMesh<NR>,
    corner: &Tri3Mesh,
    rule: &QuadratureRule,
    options: &RestOptions,
    moduli: &Moduli,
) -> Result<ShellRest<NU, NR>, RestStateError>
where
    TriMesh<NU>: MeshElement<NU>,
{
    // Long because one pass over the elements fills the point arrays that the rest state keeps in
    // step (shapes, positions, curvature, density index), and the density table needs all of them.
    let n_el = disp.n_elements();
    if rot.n_elements() != n_el {
        return Err(RestStateError::ElementCountMismatch {
            disp: n_el,
            rot: rot.n_elements(),
        });
    }
    let n_qp = rule.n_points();
    let tying_scheme = match options.interpolation {
        StrainInterpolation::Assumed => Some((options.assumed_parts, MembraneTying::Centroid)),
        StrainInterpolation::Regge | StrainInterpolation::ReggeStabilized => {
            Some((AssumedParts::MEMBRANE, MembraneTying::Moments))
        }
        StrainInterpolation::Paper | StrainInterpolation::Stabilized => None,
    };
    let tying: Vec<[f64; 2]> = if tying_scheme.is_some() {
        tying_points().to_vec()
    } else {
        Vec::new()
    };
    let n_points = n_qp + tying.len();
    let mut tying_map_list = Vec::new();
    let mut tying_stabilization = Vec::new();
    let mut tied_values = Vec::new();
    // The curvature is needed only by the shell model.
    let geometry = match options.model.model {
        ShellModel::Shell => Some(rest_geometry(disp, corner, rule, &options.curvature)?),
        ShellModel::Plate => None,
    };
    let flat_terms = TermSet::select(&options.model, moduli, false)?;
    let curved_terms = TermSet::select(&options.model, moduli, true)?;
    let flat_d = strain_hessian(
        &flat_terms,
        &local_geometry(&Matrix3::identity(), &Matrix3::zeros()),
        moduli,
    );
    let mut index = Vec::with_capacity(n_el * n_points);
    // The frame and b of each curved point, in point order: their density Hessians are computed below.
    let mut curved_points: Vec<(Matrix3<f64>, Matrix3<f64>)> = Vec::new();
    let mut shapes = Vec::with_capacity(n_el * n_points);
    let mut point_positions = Vec::with_capacity(n_el * n_points);
    let mut curvature = Vec::with_capacity(n_el * n_points);
    let mut element_areas = Vec::with_capacity(n_el);
    let mut n_curved_points = 0;
    let mut projections = Vec::new();
    for e in 0..n_el {
        let nodes = disp.element_nodes(e);
        if options.interpolation == StrainInterpolation::Stabilized {
            projections.push(StrainProjection::new(
                &options.stabilization,
                moduli.thickness,
                longest_edge(&nodes),
            ));
        }
        let mut area = 0.0;
        let mut bases = Vec::new();
        for (g, (xi, w)) in rule
            .iter()
            .enumerate()
            .chain(tying.iter().enumerate().map(|(t, xi)| (n_qp + t, (*xi, 0.0))))
        {
            let (shape, basis) = point_shape::<E, F, NU, NR>(&nodes, xi, w, e)?;
            area += shape.weight;
            bases.push(basis);
            shapes.push(shape);
            point_positions.push(E::position(&nodes, xi));
            let curv = match &geometry {
                Some(geo) if g < n_qp => geo.at(e, g).curvature,
                _ => Curvature::flat(),
            };
            curvature.push(curv);
        }
        if let Some((parts, interior)) = tying_scheme {
            let tied: [PointBasis; N_TYING] = std::array::from_fn(|t| bases[n_qp + t]);
            let (mut values, mut maps) = tying_maps(&tied, &bases[..n_qp], parts, interior);
            if options.interpolation == StrainInterpolation::ReggeStabilized {
                let constants = StabilizationConstants::regge_stabilized(NR, n_qp);
                let alpha = StrainProjection::new(&constants, moduli.thickness, longest_edge(&nodes));
                stabilize_shear_and_drilling(&mut values, &mut maps, alpha.shear, alpha.drilling);
                tying_stabilization.push(alpha);
            }
            tying_map_list.extend(maps);
            tied_values.push(values);
        }
        element_areas.push(area);
        for g in 0..n_points {
            let p = e * n_points + g;
            let curv = &curvature[p];
            let curved = g < n_qp && geometry.is_some() && curv.b.norm() * area.sqrt() > options.flat_tolerance;
            if curved {
                n_curved_points += 1;
                curved_points.push((shapes[p].frame, curv.b));
                index.push(curved_points.len() as u32);
            } else {
                index.push(0);
            }
        }
    }
    // One density Hessian per curved point (a large part of the set-up): independent, so they run in
    // parallel; the order of `matrices` follows `index` whatever the scheduling.
    let curved_hessians = StrainHessians::new(&curved_terms, moduli);
    let mut matrices: Vec<StrainMatrix> = Vec::with_capacity(1 + curved_points.len());
    matrices.push(flat_d);
    matrices.par_extend(
        curved_points
            .par_iter()
            .map(|(frame, b)| curved_hessians.at(&local_geometry(frame, b))),
    );
    let mut active_terms = Vec::new();
    if n_curved_points < n_el * n_qp {
        active_terms.extend(flat_terms.names());
    }
    if n_curved_points > 0 {
        for name in curved_terms.names() {
            if !active_terms.contains(&name) {
                active_terms.push(name);
            }
        }
    }
    let nonlinear_volume = flat_terms.contains(crate::model::EnergyTerm::NonlinearVolume);
    Ok(ShellRest {
        points_per_element: n_points,
        quadrature_points_per_element: n_qp,
        shapes,
        point_positions,
        curvature,
        densities: DensityTable::indexed(matrices, index),
        active_terms,
        nonlinear_volume,
        n_curved_points,
        element_areas,
        projections,
        tying_maps: tying_map_list,
        tied_values,
        tying_stabilization,
        tying_twins: if tying.is_empty() {
            TyingTwins::NONE
        } else {
            TyingTwins::of_rule(rule.points())
        },
    })
}

/// The longest straight edge between an element's corners: the element size `h_e` of the stabilised
/// interpolations.
fn longest_edge<const NU: usize>(nodes: &[Vector3<f64>; NU]) -> f64 {
    (0..3).map(|i| (nodes[(i + 1) % 3] - nodes[i]).norm()).fold(0.0, f64::max)
}

/// The shape data of a point of element `e` at reference coordinates `xi` with quadrature weight `w`,
/// and its covariant basis.
fn point_shape<E: ShapeFunctions<NU>, F: ShapeFunctions<NR>, const NU: usize, const NR: usize>(
    nodes: &[Vector3<f64>; NU],
    xi: [f64; 2],
    w: f64,
    e: usize,
) -> Result<(PointShape<NU, NR>, PointBasis), RestStateError> {
    let grad = E::gradients(xi);
    let tangent = E::tangent(nodes, xi);
    let metric = SurfaceMetric::try_new(&tangent).map_err(|_| MeshError::DegenerateElement {
        elem_idx: e,
        area: 0.5 * tangent.column(0).cross(&tangent.column(1)).norm(),
    })?;
    let frame = metric.orthonormal_frame();
    let p: Matrix2<f64> = metric.pinv * frame.fixed_columns::<2>(0);
    let shape = PointShape {
        disp_grad: p.transpose() * grad,
        rot_values: F::values(xi),
        rot_grad: p.transpose() * F::gradients(xi),
        frame,
        weight: w * metric.area_element,
    };
    let gt = Matrix2::from_fn(|a, i| frame.column(a).dot(&tangent.column(i)));
    Ok((shape, PointBasis { xi, gt }))
}

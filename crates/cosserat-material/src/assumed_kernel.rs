//! The assumed strains' part of the coupled element kernel ([`crate::coupled`]): the stresses and the
//! first-order Hessian of an element whose quadrature points' strains are
//! `s̃_p = (A_p F z + K_p s_p, Γ̂_p)`, with `z` the tied strains (`Ê` entries 0–5 of every tying point),
//! `F` the element's [`TiedValues`](crate::assumed::TiedValues), `A_p` and `K_p` the point's
//! [`TyingMap`] (`K_p` keeps the point's own values of the parts that are not assumed), and
//! `M_p = A_p F` the point's map on the tied strains.
//!
//! **Derivation.** The energy is `Σ_p w_p ½ s̃_p · D_p s̃_p` over the quadrature points. Its derivative
//! with respect to the raw strains `s_q` of every point of the element (quadrature and tying points) is
//! `σ̂_q`: at a quadrature point, the `Γ̂` part of `w_q D_q s̃_q` and `K_qᵀ` of its `Ê` part; at a tying
//! point, its slice of `Σ_p M_pᵀ (w_p D_p s̃_p)`. So the gradient and the second-order terms of each point's strain map
//! are the point kernel with `σ̂_q` (integration weight one). The first-order part is
//! `Σ_p w_p G̃_pᵀ D_p G̃_p`, where `G̃_p` takes its `Ê` columns from the tying points' Jacobians through
//! `M_p` plus its own through `K_p`, and its `Γ̂` columns from its own. The tying points' Jacobians are
//! combined into the Jacobians of the tied values once per element (`F` reads one or a few entries
//! of each tying point), and each point's columns from those through `A_p`.
//!
//! The element's points are its quadrature points followed by its [`N_TYING`] tying points, whose
//! weights are zero. A tying point that lies on a quadrature point ([`TyingTwins`]) takes that point's
//! strains, so its stress is added to the quadrature point's and its Jacobian is the quadrature point's.

use crate::assumed::{ElementTying, N_TIED, N_TYING, N_VALUES, TIED, TyingMap, TyingTwins};
use crate::kernel::PointShape;
use crate::kernel::strain_vector;
use crate::model::AxlVariant;
use crate::projected::{ElementPoint, FirstOrderPoint, ValuePoint, add_element_jacobian, add_first_order};
use crate::strain_space::StrainVector;
use nalgebra::{Matrix3, SMatrix, SVector};

/// The tied strains of an element from the raw strains of its points (tying points last).
fn tied(strains: &[StrainVector], twins: &TyingTwins) -> SVector<f64, N_TIED> {
    let first = strains.len() - N_TYING;
    SVector::from_fn(|i, _| strains[twins.source(i / TIED, first)][i % TIED])
}

/// The assumed strains of the quadrature points from the raw strains of all points and the tied values
/// `y` of the element.
fn assumed(strains: &[StrainVector], y: &SVector<f64, N_VALUES>, maps: &[TyingMap]) -> Vec<StrainVector> {
    strains
        .iter()
        .zip(maps)
        .map(|(s, m)| {
            // In place: the map is a 6 × 26 matrix, which a product by value would copy.
            let mut assumed = SVector::<f64, TIED>::zeros();
            assumed.gemv(1.0, &m.values, y, 0.0);
            assumed.gemv(1.0, &m.own, &s.fixed_rows::<TIED>(0), 1.0);
            let mut out = *s;
            out.fixed_rows_mut::<TIED>(0).copy_from(&assumed);
            out
        })
        .collect()
}

/// The strains its energy is a density of, at each quadrature point of an element (`maps.len()`
/// points, then the tying points), and the energy of the element's drilling hourglass term (J; see
/// [`crate::drilling_hourglass`]), zero where it has none.
pub fn element_strains_and_hourglass<const NU: usize, const NR: usize>(
    points: &[ValuePoint<'_, NU, NR>],
    node_r: [&Matrix3<f64>; NR],
    tying: &ElementTying<'_>,
    variant: AxlVariant,
) -> (Vec<StrainVector>, f64) {
    let (maps, twins) = (tying.maps, &tying.twins);
    let first = points.len() - N_TYING;
    let strains: Vec<StrainVector> = points
        .iter()
        .enumerate()
        .map(|(n, p)| {
            // A twin's strains are read at its quadrature point.
            if n >= first && twins.is_twin(n - first) {
                return StrainVector::zeros();
            }
            strain_vector(p.shape, &p.f_hat, &p.r, node_r, p.offset, variant)
        })
        .collect();
    let z = tied(&strains, twins);
    let hourglass = tying.hourglass().map_or(0.0, |h| h.energy(&z));
    (assumed(&strains, &tying.values.of(&z), maps), hourglass)
}

/// The derivatives `σ̂_q` of the element energy with respect to the raw `strains` of all its points,
/// and the energy (J, strain-quadratic part).
pub(crate) fn stresses<const NU: usize, const NR: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    strains: &[StrainVector],
    tying: &ElementTying<'_>,
) -> (f64, Vec<StrainVector>) {
    let (maps, twins) = (tying.maps, &tying.twins);
    let z = tied(strains, twins);
    let smoothed = assumed(strains, &tying.values.of(&z), maps);
    let mut value = 0.0;
    let mut sigma = vec![StrainVector::zeros(); points.len()];
    let mut value_stress = SVector::<f64, N_VALUES>::zeros();
    for ((p, s), (m, out)) in points.iter().zip(&smoothed).zip(maps.iter().zip(sigma.iter_mut())) {
        let ws = p.density.mul_vector(s) * p.shape.weight;
        value += 0.5 * s.dot(&ws);
        value_stress.gemv_tr(1.0, &m.values, &ws.fixed_rows::<TIED>(0), 1.0);
        *out = ws;
        out.fixed_rows_mut::<TIED>(0)
            .copy_from(&m.own.tr_mul(&ws.fixed_rows::<TIED>(0)));
    }
    let mut tied_stress = SVector::<f64, N_TIED>::zeros();
    tying.values.add_transposed(&value_stress, &mut tied_stress);
    if let Some(hourglass) = tying.hourglass() {
        value += hourglass.add_stress(&z, &mut tied_stress);
    }
    let first = points.len() - N_TYING;
    for t in 0..N_TYING {
        let mut out = sigma[twins.source(t, first)].fixed_rows_mut::<TIED>(0);
        out += tied_stress.fixed_rows::<TIED>(TIED * t);
    }
    (value, sigma)
}

/// The strain Jacobians of an element's points in its unknowns (transposed, row = unknown), as the
/// first-order part reads them: the tying maps read the columns of `Ê` of every point, and the columns
/// of `Γ̂` of the quadrature points only.
pub(crate) struct TiedJacobians<const NE: usize> {
    /// The columns of `Ê` of each point of the element (`None` for a point that no map reads).
    membrane: Vec<Option<SMatrix<f64, NE, TIED>>>,
    /// The columns of `Γ̂` of each quadrature point.
    curvature: Vec<SMatrix<f64, NE, 6>>,
}

impl<const NE: usize> TiedJacobians<NE> {
    /// No point yet, room for `points` points of which `quadrature` are quadrature points.
    pub(crate) fn with_capacity(points: usize, quadrature: usize) -> Self {
        Self {
            membrane: Vec::with_capacity(points),
            curvature: Vec::with_capacity(quadrature),
        }
    }

    /// The next point is read by no map.
    pub(crate) fn skip(&mut self) {
        self.membrane.push(None);
    }

    /// Adds the next point from its transposed Jacobian `jac_t` in its locals and `QᵀRᵀ` (see
    /// [`crate::kernel::strain_jacobian`]); the columns of `Γ̂` are kept for a `quadrature` point.
    pub(crate) fn push<const NU: usize, const NR: usize, const NL: usize>(
        &mut self,
        shape: &PointShape<NU, NR>,
        jac_t: &SMatrix<f64, NL, 12>,
        qrt: &Matrix3<f64>,
        dt: f64,
        quadrature: bool,
    ) {
        // Written in place: the matrices are large enough for the moves to count.
        self.membrane.push(Some(SMatrix::zeros()));
        let membrane = self.membrane.last_mut().and_then(Option::as_mut).expect("just added");
        add_element_jacobian(shape, jac_t, qrt, dt, 1.0, membrane);
        if quadrature {
            // `Γ̂` does not depend on the displacements, and its rotation rows are those of `jac_t`.
            self.curvature.push(SMatrix::zeros());
            let curvature = self.curvature.last_mut().expect("just added");
            for s in 0..6 {
                for r in 0..3 * NR {
                    curvature[(3 * NU + r, s)] = jac_t[(6 + r, 6 + s)];
                }
            }
        }
    }
}

/// Adds `Σ_p w_p G̃_pᵀ D_p G̃_p` to the upper block triangle of `h`.
pub(crate) fn add_assumed_first_order<const NU: usize, const NR: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    jacobians: &TiedJacobians<NE>,
    tying: &ElementTying<'_>,
    h: &mut SMatrix<f64, NE, NE>,
) {
    let (maps, twins) = (tying.maps, &tying.twins);
    let first = points.len() - N_TYING;
    let membrane = &jacobians.membrane;
    // The Jacobians of the tied values, `J_z Fᵀ`.
    let mut values = SMatrix::<f64, NE, N_VALUES>::zeros();
    for w in tying.values.weights() {
        let strain = usize::from(w.strain);
        let jt = membrane[twins.source(strain / TIED, first)]
            .as_ref()
            .expect("a tying point a value reads is evaluated");
        values
            .column_mut(usize::from(w.value))
            .axpy(w.weight, &jt.column(strain % TIED), 1.0);
    }
    let mut tied = vec![SMatrix::<f64, NE, TIED>::zeros(); maps.len()];
    for (q, (m, tied)) in maps.iter().zip(tied.iter_mut()).enumerate() {
        let own = membrane[q].as_ref().expect("a quadrature point is evaluated");
        // `Ê` columns of G̃_p: the values' Jacobians through `A_p`, plus the point's own through `K_p`.
        // Both maps are sparse (a membrane entry reads the membrane values only, a shear or drilling
        // entry its own part's, `K_p` keeps a part or none), so they are applied entry by entry.
        add_mapped_columns(tied, own, &m.own);
        add_mapped_columns(tied, &values, &m.values);
    }
    let tied_points: Vec<FirstOrderPoint<'_, NE>> = points
        .iter()
        .zip(&tied)
        .zip(&jacobians.curvature)
        .map(|((p, membrane), curvature)| FirstOrderPoint {
            density: p.density,
            membrane,
            curvature,
            weight: p.shape.weight,
        })
        .collect();
    add_first_order(&tied_points, 3 * NU, h);
    if let Some(hourglass) = tying.hourglass() {
        let jacobian = |t: usize| {
            membrane[twins.source(t, first)]
                .as_ref()
                .expect("an edge or interior tying point is evaluated")
        };
        hourglass.add_first_order(jacobian, h);
    }
}

/// `out += J Mᵀ` for Jacobian columns `J` in the element's unknowns (a point's `Ê` columns, or the
/// tied values'), over the nonzero entries of the map `M` to the `Ê` entries 0–5.
fn add_mapped_columns<const NE: usize, const C: usize>(
    out: &mut SMatrix<f64, NE, TIED>,
    jacobian: &SMatrix<f64, NE, C>,
    map: &SMatrix<f64, TIED, C>,
) {
    for j in 0..C {
        for i in 0..TIED {
            let v = map[(i, j)];
            if v != 0.0 {
                out.column_mut(i).axpy(v, &jacobian.column(j), 1.0);
            }
        }
    }
}

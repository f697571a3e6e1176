//! Assumed covariant strains at tying points (MITC6-style, [`StrainInterpolation::Assumed`]).
//!
//! The membrane, drilling and transverse-shear strains of a quadrature point (the entries of `Ê` that
//! carry the constraints a thin shell cannot satisfy point by point) are replaced by an assumed field
//! interpolated from the strains at fixed *tying points* of the reference triangle: the two Gauss
//! points of each edge and the centroid. The curvature strains `Γ` keep their point values.
//!
//! The assumed fields are written in covariant components (natural coordinates `r, s`, base vectors
//! `g_i = ∂X/∂ξ_i`), which do not depend on the point's orthonormal frame, so that tying values of
//! different points of a curved element can be combined:
//! - membrane, `C_ij = g_i · sym E g_j`: a linear symmetric tensor field (9 coefficients) tied to the
//!   edge-tangential components `τ · C τ` at the edge Gauss points and to the three components at the
//!   centroid (the lowest-order Regge space, as in MITC6's membrane);
//! - transverse shear, `c_i = n₀ · E g_i`: the second-order Nédélec space `P₁² ⊕ (−s, r)(α r + β s)`
//!   (8 coefficients) tied to the edge-tangential components at the edge Gauss points and to both
//!   components at the centroid (MITC6's shear space);
//! - drilling, the skew scalar `½ (Ê₁₂ − Ê₂₁)`: linear, tied to its mean over each edge's Gauss points.
//!
//! Each space contains the linear fields, so a strain field that is linear in `r, s` is reproduced
//! exactly (patch tests); the higher-order parts of the point strains, which on curved or thin
//! elements carry the locking constraints, are filtered out. The assumed strains at the quadrature
//! points are a constant linear map of the tying points' strains per element ([`TyingMap`]), so the
//! energy `Σ_p w_p Ψ(s̃_p)` keeps exact first and second derivatives by the chain rule
//! (`assumed_kernel`). The tying points are points of the element with a zero integration weight:
//! each carries its own rotation, advanced like a quadrature point's.
//!
//! [`StrainInterpolation::Regge`] assumes the membrane part only, in the same linear symmetric space,
//! but ties it to *moments* (Neunteufel and Schöberl, "Avoiding membrane locking with Regge
//! interpolation", CMAME 2021): the edge-tangential moments against linear functions (the two edge
//! Gauss points, exact for the quadratic tangential strain of a Tri6 edge) and the mean of the three
//! covariant components over the element (the three interior tying points at the degree-2 rule's
//! points, exact for quadratic fields). The edge moments are shared by the two elements of an edge,
//! and under a bending without stretching the interior moments are combinations of them, which the
//! centroid values of MITC6 are not: on a thin cantilever bent into an arc (Sze 3.1) the centroid ties
//! lock the element while the moments leave it free (docs/model-notes.md).
//!
//! [`StrainInterpolation::Assumed`]: crate::StrainInterpolation::Assumed
//! [`StrainInterpolation::Regge`]: crate::StrainInterpolation::Regge

use crate::drilling_hourglass::DrillingHourglass;
use crate::projection::StrainProjection;
use crate::strain_space::DensityMatrix;
use nalgebra::{DMatrix, Matrix2, SMatrix, SVector};

/// Number of tying points per element: two Gauss points per edge, the centroid, and the three points
/// of the interior degree-2 rule.
pub const N_TYING: usize = 10;
/// The first of the interior tying points (the degree-2 rule's points, equal weights).
pub(crate) const FIRST_INTERIOR: usize = 7;
/// Number of tied strain entries per tying point: `Ê` entries 0–5 (the tangential and normal rows of
/// its two variable columns).
pub const TIED: usize = 6;
/// Length of the tied strains of an element, `N_TYING × TIED`.
pub const N_TIED: usize = N_TYING * TIED;

/// Number of tied values of an element: the functionals of its tied strains that the assumed fields
/// are tied to (membrane 9, transverse shear 8, drilling 3; see [`TiedValues`]) and the means of `Ê`
/// entries 0–5 over the interior tying points that the stabilised parts read (6).
pub const N_VALUES: usize = 26;
/// The first membrane, shear, drilling and interior-mean value.
const MEMBRANE_VALUES: usize = 0;
const SHEAR_VALUES: usize = 9;
const DRILLING_VALUES: usize = 17;
const MEAN_VALUES: usize = 20;

/// The weight of one tied value on one tied strain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TiedWeight {
    /// The value, below [`N_VALUES`].
    pub value: u8,
    /// The tied strain, below [`N_TIED`]: `Ê` entry `strain % TIED` of tying point `strain / TIED`.
    pub strain: u8,
    /// The weight.
    pub weight: f64,
}

/// The tied values of an element, `y = F z` for its tied strains `z`: the edge-tangential strains and
/// the interior components or moments the assumed fields are tied to, and the interior means of the
/// stabilised parts. Every quadrature point's assumed strains are a combination of them
/// ([`TyingMap::values`]), and each reads a few entries of one or three tying points, so a map through
/// them costs a fraction of a map on all tied strains; only the values some map reads are kept.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TiedValues {
    /// Sorted by value.
    weights: Vec<TiedWeight>,
    /// Bit `t` set: some value reads tying point `t`.
    read_points: u16,
}

impl TiedValues {
    /// The values of `weights` (any order; several weights of a value on one strain add up).
    pub fn from_weights(mut weights: Vec<TiedWeight>) -> Self {
        weights.sort_by_key(|w| (w.value, w.strain));
        let mut values = Self {
            weights,
            read_points: 0,
        };
        values.update_read_points();
        values
    }

    /// The nonzero weights.
    pub fn weights(&self) -> &[TiedWeight] {
        &self.weights
    }

    /// The values of the tied strains `z`.
    pub fn of(&self, z: &SVector<f64, N_TIED>) -> SVector<f64, N_VALUES> {
        let mut y = SVector::zeros();
        for w in &self.weights {
            y[usize::from(w.value)] += w.weight * z[usize::from(w.strain)];
        }
        y
    }

    /// `out += Fᵀ y`: a derivative with respect to the values as one with respect to the tied strains.
    pub fn add_transposed(&self, y: &SVector<f64, N_VALUES>, out: &mut SVector<f64, N_TIED>) {
        for w in &self.weights {
            out[usize::from(w.strain)] += w.weight * y[usize::from(w.value)];
        }
    }

    /// Some value reads tying point `t`.
    pub fn reads(&self, t: usize) -> bool {
        self.read_points & (1 << t) != 0
    }

    fn update_read_points(&mut self) {
        self.read_points = self
            .weights
            .iter()
            .fold(0, |bits, w| bits | 1 << (usize::from(w.strain) / TIED));
    }

    /// `F` as a dense matrix.
    pub fn matrix(&self) -> SMatrix<f64, N_VALUES, N_TIED> {
        let mut f = SMatrix::zeros();
        for w in &self.weights {
            f[(usize::from(w.value), usize::from(w.strain))] += w.weight;
        }
        f
    }

    /// Appends the nonzero entries of `rows` as the values from `first` on.
    fn push_rows(&mut self, first: usize, rows: &DMatrix<f64>) {
        for r in 0..rows.nrows() {
            for (strain, &weight) in rows.row(r).iter().enumerate() {
                if weight != 0.0 {
                    self.push(first + r, strain, weight);
                }
            }
        }
    }

    fn push(&mut self, value: usize, strain: usize, weight: f64) {
        let (value, strain) = (value as u8, strain as u8);
        self.weights.push(TiedWeight { value, strain, weight });
        self.read_points |= 1 << (usize::from(strain) / TIED);
    }

    /// Drops the values that no map reads.
    fn retain_read_by(&mut self, maps: &[TyingMap]) {
        let read: [bool; N_VALUES] =
            std::array::from_fn(|v| maps.iter().any(|m| m.values.column(v).iter().any(|&x| x != 0.0)));
        self.weights.retain(|w| read[usize::from(w.value)]);
        self.update_read_points();
    }

    /// Adds the means over the interior tying points of the `Ê` entries the stabilised shear and
    /// drilling read, unless present; pushed after the others, so sorted again.
    fn add_interior_means(&mut self) {
        for k in [entry(1, 0), entry(2, 0), entry(0, 1), entry(2, 1)] {
            let value = MEAN_VALUES + k;
            if self.weights.iter().any(|w| usize::from(w.value) == value) {
                continue;
            }
            for t in FIRST_INTERIOR..N_TYING {
                self.push(value, TIED * t + k, 1.0 / (N_TYING - FIRST_INTERIOR) as f64);
            }
        }
        self.weights.sort_by_key(|w| (w.value, w.strain));
    }
}

/// The assumed entries 0–5 of one quadrature point's `Ê`: `values y + own s`, with `y` the element's
/// [`TiedValues`] and `s` the point's own entries 0–5 (for the parts that keep their point values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TyingMap {
    /// From the element's tied values.
    pub values: SMatrix<f64, TIED, N_VALUES>,
    /// From the point's own strains: the projector onto the parts that are not assumed.
    pub own: SMatrix<f64, TIED, TIED>,
}

impl TyingMap {
    /// The map from the element's tied strains, `values F`.
    pub fn tied(&self, values: &TiedValues) -> SMatrix<f64, TIED, N_TIED> {
        self.values * values.matrix()
    }
}

/// The assumed strains of one element: its tied values, its quadrature points' maps, the tying
/// points that lie on quadrature points and its drilling hourglass term, set up once per evaluation.
#[derive(Debug, Clone, Copy)]
pub struct ElementTying<'a> {
    /// The tied values.
    pub values: &'a TiedValues,
    /// The map of each quadrature point.
    pub maps: &'a [TyingMap],
    /// The tying points read at quadrature points.
    pub twins: TyingTwins,
    /// The drilling hourglass term, where the element has one.
    hourglass: Option<DrillingHourglass>,
}

impl<'a> ElementTying<'a> {
    /// The assumed strains of an element with `maps` at its quadrature points, whose weights and
    /// densities are `quadrature`; `quadratic_rotations` for Tri6 rotations (which have a drilling
    /// hourglass on the 3-point rule, [`crate::drilling_hourglass`]).
    pub fn new<'d>(
        values: &'a TiedValues,
        maps: &'a [TyingMap],
        twins: TyingTwins,
        quadratic_rotations: bool,
        quadrature: impl Iterator<Item = (f64, &'d DensityMatrix)>,
    ) -> Self {
        Self {
            values,
            maps,
            twins,
            hourglass: DrillingHourglass::of(quadratic_rotations, quadrature, maps, &twins),
        }
    }

    /// The drilling hourglass term, where the element has one.
    pub(crate) fn hourglass(&self) -> Option<&DrillingHourglass> {
        self.hourglass.as_ref()
    }
}

/// The tying points that lie on a quadrature point of the element's rule (the interior degree-2 rule's
/// points under the paper's Tri6/Tri3 rule). Such a point has the quadrature point's position and
/// rotation, so its strains, stresses and Jacobian are read at the quadrature point instead of being
/// evaluated twice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TyingTwins([Option<u8>; N_TYING]);

impl TyingTwins {
    /// No tying point on a quadrature point.
    pub const NONE: Self = Self([None; N_TYING]);

    /// The twins of the tying points among the `quadrature` points of a rule (reference coordinates).
    pub fn of_rule(quadrature: &[[f64; 2]]) -> Self {
        let points = tying_points();
        Self(std::array::from_fn(|t| {
            let [r, s] = points[t];
            quadrature
                .iter()
                .position(|q| (q[0] - r).abs() <= 1e-14 && (q[1] - s).abs() <= 1e-14)
                .and_then(|q| u8::try_from(q).ok())
        }))
    }

    /// Tying point `t` coincides with a quadrature point.
    pub fn is_twin(&self, t: usize) -> bool {
        self.0[t].is_some()
    }

    /// The index, among the element's points (quadrature points first, then the tying points from
    /// `first_tying`), of the point whose strains tying point `t` takes.
    pub fn source(&self, t: usize, first_tying: usize) -> usize {
        self.0[t].map_or(first_tying + t, usize::from)
    }
}

/// Which strain parts take assumed values (the others keep their point values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AssumedParts {
    /// The symmetric tangential block of `Ê`.
    pub membrane: bool,
    /// The skew tangential block of `Ê`.
    pub drilling: bool,
    /// The normal row of `Ê`.
    pub shear: bool,
}

impl AssumedParts {
    /// Every part assumed.
    pub const ALL: Self = Self {
        membrane: true,
        drilling: true,
        shear: true,
    };

    /// The membrane part only.
    pub const MEMBRANE: Self = Self {
        membrane: true,
        drilling: false,
        shear: false,
    };

    /// The projector onto the `Ê` entries 0–5 of the parts that keep their point values.
    fn kept(&self) -> SMatrix<f64, TIED, TIED> {
        let mut k = SMatrix::<f64, TIED, TIED>::zeros();
        if !self.membrane {
            k += membrane_projector();
        }
        if !self.drilling {
            k += drilling_projector();
        }
        if !self.shear {
            k += shear_projector();
        }
        k
    }
}

/// The projector onto the membrane part of `Ê` entries 0–5 (the symmetric tangential block).
fn membrane_projector() -> SMatrix<f64, TIED, TIED> {
    let mut p = SMatrix::<f64, TIED, TIED>::zeros();
    p[(0, 0)] = 1.0;
    p[(4, 4)] = 1.0;
    let (d01, d10) = (entry(0, 1), entry(1, 0));
    for (r, c) in [(d01, d01), (d01, d10), (d10, d01), (d10, d10)] {
        p[(r, c)] = 0.5;
    }
    p
}

/// The projector onto the drilling part of `Ê` entries 0–5 (the skew tangential block).
fn drilling_projector() -> SMatrix<f64, TIED, TIED> {
    let mut p = SMatrix::<f64, TIED, TIED>::zeros();
    let (d01, d10) = (entry(0, 1), entry(1, 0));
    for (r, c, v) in [(d01, d01, 0.5), (d01, d10, -0.5), (d10, d01, -0.5), (d10, d10, 0.5)] {
        p[(r, c)] = v;
    }
    p
}

/// The projector onto the transverse-shear part of `Ê` entries 0–5 (the normal row).
fn shear_projector() -> SMatrix<f64, TIED, TIED> {
    let mut p = SMatrix::<f64, TIED, TIED>::zeros();
    for r in [entry(2, 0), entry(2, 1)] {
        p[(r, r)] = 1.0;
    }
    p
}

const CORNERS: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// Natural directions of edges `k → k + 1`.
const EDGE_DIRECTIONS: [[f64; 2]; 3] = [[1.0, 0.0], [-1.0, 1.0], [0.0, -1.0]];

/// How the membrane field is tied inside the element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MembraneTying {
    /// The three covariant components at the centroid (MITC6).
    Centroid,
    /// The mean of the three covariant components over the element (Regge interpolation).
    Moments,
}

/// Reference coordinates of the tying points: the two Gauss points of edges 0→1, 1→2 and 2→0, the
/// centroid, then the three points of the interior degree-2 rule.
pub fn tying_points() -> [[f64; 2]; N_TYING] {
    let d = 0.5 / 3f64.sqrt();
    let mut out = [[1.0 / 3.0; 2]; N_TYING];
    out[FIRST_INTERIOR] = [1.0 / 6.0, 1.0 / 6.0];
    out[FIRST_INTERIOR + 1] = [2.0 / 3.0, 1.0 / 6.0];
    out[FIRST_INTERIOR + 2] = [1.0 / 6.0, 2.0 / 3.0];
    for k in 0..3 {
        for (j, t) in [0.5 - d, 0.5 + d].into_iter().enumerate() {
            let (a, e) = (CORNERS[k], EDGE_DIRECTIONS[k]);
            out[2 * k + j] = [a[0] + t * e[0], a[1] + t * e[1]];
        }
    }
    out
}

/// The rest geometry of a point that the covariant transformations need: `Gt = [t_a · g_i]` (frame
/// components of the natural base vectors) and its inverse `P` (`t_a = Σ_i P_ia g_i`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointBasis {
    /// Reference coordinates.
    pub xi: [f64; 2],
    /// `Gt[(a, i)] = t_a · g_i`.
    pub gt: Matrix2<f64>,
}

/// Membrane basis: component (0 = rr, 1 = ss, 2 = rs) times monomial (1, r, s).
fn membrane_basis(m: usize, xi: [f64; 2]) -> Matrix2<f64> {
    let mono = [1.0, xi[0], xi[1]][m % 3];
    match m / 3 {
        0 => Matrix2::new(mono, 0.0, 0.0, 0.0),
        1 => Matrix2::new(0.0, 0.0, 0.0, mono),
        _ => Matrix2::new(0.0, mono, mono, 0.0),
    }
}

/// Shear basis: `P₁²` and the two quadratic Nédélec fields.
fn shear_basis(m: usize, xi: [f64; 2]) -> [f64; 2] {
    let (r, s) = (xi[0], xi[1]);
    match m {
        0..=2 => [[1.0, r, s][m], 0.0],
        3..=5 => [0.0, [1.0, r, s][m - 3]],
        6 => [-s * r, r * r],
        _ => [-s * s, r * s],
    }
}

/// Barycentric coordinates.
fn barycentric(xi: [f64; 2]) -> [f64; 3] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]]
}

/// The functionals of the tied values (rows) on the tied strains (columns) and on the basis fields, for
/// one strain part.
struct Tying {
    /// Tied values from the tied strains.
    from_strains: DMatrix<f64>,
    /// Tied values of the basis fields.
    of_basis: DMatrix<f64>,
}

impl Tying {
    /// The coefficients of the assumed field as a map of the tied values.
    fn coefficients(&self) -> DMatrix<f64> {
        self.of_basis
            .clone()
            .try_inverse()
            .expect("the tying functionals are unisolvent on the reference triangle")
    }
}

/// `u_a = (Gt τ)_a`: the frame components of the natural direction `τ`.
fn frame_direction(gt: &Matrix2<f64>, tau: [f64; 2]) -> [f64; 2] {
    [
        gt[(0, 0)] * tau[0] + gt[(0, 1)] * tau[1],
        gt[(1, 0)] * tau[0] + gt[(1, 1)] * tau[1],
    ]
}

/// `Ê` entry of row `a`, column `b` (column-major).
const fn entry(a: usize, b: usize) -> usize {
    3 * b + a
}

fn membrane_tying(tying: &[PointBasis; N_TYING], interior: MembraneTying) -> Tying {
    let mut from_strains = DMatrix::zeros(9, N_TIED);
    let mut of_basis = DMatrix::zeros(9, 9);
    // Tied value as a quadratic form of the frame directions (u, v): u · sym Ê v.
    let mut put = |row: usize, t: usize, u: [f64; 2], v: [f64; 2]| {
        for a in 0..2 {
            for b in 0..2 {
                from_strains[(row, TIED * t + entry(a, b))] += 0.5 * (u[a] * v[b] + v[a] * u[b]);
            }
        }
    };
    for t in 0..6 {
        let tau = EDGE_DIRECTIONS[t / 2];
        let u = frame_direction(&tying[t].gt, tau);
        put(t, t, u, u);
    }
    // Interior ties: the covariant components at the centroid, or their mean over the element (the
    // degree-2 rule's points with weights 1/3; scaling both directions by 1/√3 gives the weight).
    let (points, scale) = match interior {
        MembraneTying::Centroid => (6..7, 1.0),
        MembraneTying::Moments => (FIRST_INTERIOR..N_TYING, 1.0 / 3f64.sqrt()),
    };
    for t in points {
        let gt = &tying[t].gt;
        let dir = |d: [f64; 2]| frame_direction(gt, d).map(|x| scale * x);
        let (gr, gs) = (dir([1.0, 0.0]), dir([0.0, 1.0]));
        put(6, t, gr, gr);
        put(7, t, gs, gs);
        put(8, t, gr, gs);
    }
    // The linear basis fields' interior ties are their centroid values in both cases (the mean of a
    // linear field is its centroid value).
    let c = &tying[6];
    for m in 0..9 {
        for t in 0..6 {
            let tau = nalgebra::Vector2::from(EDGE_DIRECTIONS[t / 2]);
            of_basis[(t, m)] = tau.dot(&(membrane_basis(m, tying[t].xi) * tau));
        }
        let b = membrane_basis(m, c.xi);
        of_basis[(6, m)] = b[(0, 0)];
        of_basis[(7, m)] = b[(1, 1)];
        of_basis[(8, m)] = b[(0, 1)];
    }
    Tying { from_strains, of_basis }
}

fn shear_tying(tying: &[PointBasis; N_TYING]) -> Tying {
    let mut from_strains = DMatrix::zeros(8, N_TIED);
    let mut of_basis = DMatrix::zeros(8, 8);
    // Tied value u · (n₀ row of Ê): Σ_γ u_γ Ê_2γ.
    let mut put = |row: usize, t: usize, u: [f64; 2]| {
        for (g, ug) in u.iter().enumerate() {
            from_strains[(row, TIED * t + entry(2, g))] += ug;
        }
    };
    for t in 0..6 {
        put(t, t, frame_direction(&tying[t].gt, EDGE_DIRECTIONS[t / 2]));
    }
    let c = &tying[6];
    put(6, 6, frame_direction(&c.gt, [1.0, 0.0]));
    put(7, 6, frame_direction(&c.gt, [0.0, 1.0]));
    for m in 0..8 {
        for t in 0..6 {
            let tau = EDGE_DIRECTIONS[t / 2];
            let b = shear_basis(m, tying[t].xi);
            of_basis[(t, m)] = tau[0] * b[0] + tau[1] * b[1];
        }
        let b = shear_basis(m, c.xi);
        of_basis[(6, m)] = b[0];
        of_basis[(7, m)] = b[1];
    }
    Tying { from_strains, of_basis }
}

/// The drilling edge values (mean of the orientation-corrected skew scalar over each edge's Gauss
/// points) from the tied strains.
fn drilling_edges(tying: &[PointBasis; N_TYING]) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(3, N_TIED);
    for t in 0..6 {
        let sign = tying[t].gt.determinant().signum();
        out[(t / 2, TIED * t + entry(0, 1))] += 0.25 * sign;
        out[(t / 2, TIED * t + entry(1, 0))] -= 0.25 * sign;
    }
    out
}

/// The tied values of an element and the tying maps of its quadrature points, from the bases of its
/// tying points and of its quadrature points.
pub fn tying_maps(
    tying: &[PointBasis; N_TYING],
    quadrature: &[PointBasis],
    parts: AssumedParts,
    interior: MembraneTying,
) -> (TiedValues, Vec<TyingMap>) {
    let own = parts.kept();
    let assumed = SMatrix::<f64, TIED, TIED>::identity() - own;
    let membrane_tying = membrane_tying(tying, interior);
    let shear_tying = shear_tying(tying);
    let (membrane, shear) = (membrane_tying.coefficients(), shear_tying.coefficients());
    let maps = quadrature
        .iter()
        .map(|q| {
            let p = q.gt.try_inverse().unwrap_or_else(Matrix2::zeros);
            let mut out = SMatrix::<f64, TIED, N_VALUES>::zeros();
            // Membrane: Ê_ab = Σ_ij P_ia P_jb C̃_ij.
            for m in 0..9 {
                let c = membrane_basis(m, q.xi);
                let e = p.transpose() * c * p;
                for a in 0..2 {
                    for b in 0..2 {
                        for v in 0..9 {
                            out[(entry(a, b), MEMBRANE_VALUES + v)] += e[(a, b)] * membrane[(m, v)];
                        }
                    }
                }
            }
            // Drilling: Ê_01 += k̃, Ê_10 −= k̃, k̃ = sign Σ_k d_k (1 − 2 λ_{k+2}).
            let lambda = barycentric(q.xi);
            let sign = q.gt.determinant().signum();
            for k in 0..3 {
                let f = sign * (1.0 - 2.0 * lambda[(k + 2) % 3]);
                out[(entry(0, 1), DRILLING_VALUES + k)] += f;
                out[(entry(1, 0), DRILLING_VALUES + k)] -= f;
            }
            // Shear: Ê_2γ = Σ_i P_iγ c̃_i.
            for m in 0..8 {
                let c = shear_basis(m, q.xi);
                for g in 0..2 {
                    let f = p[(0, g)] * c[0] + p[(1, g)] * c[1];
                    for v in 0..8 {
                        out[(entry(2, g), SHEAR_VALUES + v)] += f * shear[(m, v)];
                    }
                }
            }
            TyingMap {
                values: assumed * out,
                own,
            }
        })
        .collect::<Vec<_>>();
    let mut values = TiedValues::default();
    values.push_rows(MEMBRANE_VALUES, &membrane_tying.from_strains);
    values.push_rows(SHEAR_VALUES, &shear_tying.from_strains);
    values.push_rows(DRILLING_VALUES, &drilling_edges(tying));
    values.retain_read_by(&maps);
    (values, maps)
}

/// Replaces the transverse-shear and drilling parts of an element's maps by their stabilised element
/// means, `s̃_q = s̄ + α (s_q − s̄)` with `s̄` the mean over the interior tying points (exact for the
/// quadratic strains of the pair) and `α` per part
/// ([`StrainInterpolation::ReggeStabilized`](crate::StrainInterpolation::ReggeStabilized)). The maps
/// must keep both parts at their point values (as [`AssumedParts::MEMBRANE`] does); a constant strain
/// is reproduced, so the patch tests hold.
pub fn stabilize_shear_and_drilling(
    values: &mut TiedValues,
    maps: &mut [TyingMap],
    alpha_shear: f64,
    alpha_drilling: f64,
) {
    values.add_interior_means();
    remove_shear_and_drilling(maps, 1.0 - alpha_shear, 1.0 - alpha_drilling);
}

/// Changes the shear and drilling factors of maps stabilised with `from` to those of `to`: the maps are
/// linear in the factors, so this is the stabilisation by the difference.
pub fn restabilize_shear_and_drilling(maps: &mut [TyingMap], from: &StrainProjection, to: &StrainProjection) {
    remove_shear_and_drilling(maps, from.shear - to.shear, from.drilling - to.drilling);
}

/// Moves the fractions `shear` and `drilling` of the point values of those parts to the element mean
/// (the interior-mean values, which [`stabilize_shear_and_drilling`] adds).
fn remove_shear_and_drilling(maps: &mut [TyingMap], shear: f64, drilling: f64) {
    let removed = shear_projector() * shear + drilling_projector() * drilling;
    for m in maps.iter_mut() {
        m.own -= removed;
        let mut block = m.values.fixed_columns_mut::<TIED>(MEAN_VALUES);
        block += removed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn basis(xi: [f64; 2], gt: Matrix2<f64>) -> PointBasis {
        PointBasis { xi, gt }
    }

    /// With no part assumed, every quadrature point keeps its own strains: the paper's element.
    #[test]
    fn no_assumed_part_keeps_the_point_strains() {
        let none = AssumedParts {
            membrane: false,
            drilling: false,
            shear: false,
        };
        let gt = Matrix2::new(1.1, 0.2, 0.1, 0.8);
        let tp = tying_points();
        let tying: [PointBasis; N_TYING] = std::array::from_fn(|t| basis(tp[t], gt));
        let (values, maps) = tying_maps(&tying, &[basis([0.3, 0.3], gt)], none, MembraneTying::Centroid);
        assert_eq!(maps[0].own, SMatrix::<f64, TIED, TIED>::identity());
        assert!(maps[0].tied(&values).amax() < 1e-15);
        assert!(values.weights().is_empty(), "no value is read");
        let (_, all) = tying_maps(
            &tying,
            &[basis([0.3, 0.3], gt)],
            AssumedParts::ALL,
            MembraneTying::Centroid,
        );
        assert_eq!(all[0].own, SMatrix::<f64, TIED, TIED>::zeros());
    }

    /// A strain field linear in `r, s` (tangential block and shear row, in covariant components) is
    /// reproduced exactly at any point, for a distorted (affine) element.
    #[test]
    fn linear_covariant_fields_are_reproduced() {
        let gt = Matrix2::new(1.3, 0.4, -0.2, 0.9);
        let p = gt.try_inverse().unwrap();
        let covariant = |xi: [f64; 2]| {
            let (r, s) = (xi[0], xi[1]);
            let c = Matrix2::new(
                0.1 + 0.3 * r - 0.2 * s,
                0.05 - 0.4 * r + 0.7 * s,
                -0.3 + 0.2 * r,
                0.4 * s,
            );
            let shear = [0.2 - 0.5 * r + 0.1 * s, -0.1 + 0.3 * r + 0.6 * s];
            (c, shear)
        };
        // Point strains in the frame: Ê_tan = Pᵀ C P, Ê_2γ = Σ_i P_iγ c_i.
        let strains = |xi: [f64; 2]| {
            let (c, sh) = covariant(xi);
            let e = p.transpose() * c * p;
            let mut v = [0.0; TIED];
            for a in 0..2 {
                for b in 0..2 {
                    v[entry(a, b)] = e[(a, b)];
                }
            }
            for g in 0..2 {
                v[entry(2, g)] = p[(0, g)] * sh[0] + p[(1, g)] * sh[1];
            }
            v
        };
        let tp = tying_points();
        let tying: [PointBasis; N_TYING] = std::array::from_fn(|t| basis(tp[t], gt));
        let quad = [basis([0.2, 0.3], gt), basis([0.7, 0.1], gt), basis([0.1, 0.8], gt)];
        let tied = nalgebra::SVector::<f64, N_TIED>::from_fn(|i, _| strains(tp[i / TIED])[i % TIED]);
        for interior in [MembraneTying::Centroid, MembraneTying::Moments] {
            let (values, maps) = tying_maps(&tying, &quad, AssumedParts::ALL, interior);
            for (q, m) in quad.iter().zip(&maps) {
                let got = m.tied(&values) * tied;
                let want = strains(q.xi);
                for i in 0..TIED {
                    assert!(
                        (got[i] - want[i]).abs() < 1e-13,
                        "{interior:?} {i}: {} vs {}",
                        got[i],
                        want[i]
                    );
                }
            }
        }
    }

    /// The Regge interpolant of a quadratic covariant membrane field keeps its edge-tangential moments
    /// against `1` and the edge parameter, and its mean over the element (moments computed here from
    /// closed-form integrals and a 3-point Gauss rule, not the tying points).
    #[test]
    fn regge_membrane_keeps_the_edge_and_interior_moments_of_a_quadratic_field() {
        let gt = Matrix2::new(1.3, 0.4, -0.2, 0.9);
        let p = gt.try_inverse().unwrap();
        // A quadratic covariant field: coefficients of 1, r, s, r², rs, s² per component (rr, ss, rs).
        let k = [
            [0.1, 0.3, -0.2, 0.7, -0.4, 0.2],
            [0.05, -0.4, 0.7, 0.3, 0.5, -0.6],
            [-0.3, 0.2, 0.1, -0.5, 0.8, 0.4],
        ];
        let covariant = |xi: [f64; 2]| {
            let (r, s) = (xi[0], xi[1]);
            let m = [1.0, r, s, r * r, r * s, s * s];
            let c: Vec<f64> = k.iter().map(|row| row.iter().zip(&m).map(|(a, b)| a * b).sum()).collect();
            Matrix2::new(c[0], c[2], c[2], c[1])
        };
        let strains = |xi: [f64; 2]| {
            let e = p.transpose() * covariant(xi) * p;
            let mut v = [0.0; TIED];
            for a in 0..2 {
                for b in 0..2 {
                    v[entry(a, b)] = e[(a, b)];
                }
            }
            v
        };
        let tp = tying_points();
        let tying: [PointBasis; N_TYING] = std::array::from_fn(|t| basis(tp[t], gt));
        let tied = nalgebra::SVector::<f64, N_TIED>::from_fn(|i, _| strains(tp[i / TIED])[i % TIED]);
        let parts = AssumedParts {
            membrane: true,
            drilling: false,
            shear: false,
        };
        // The assumed covariant field at a point: C̃ = Gtᵀ Ê Gt.
        let assumed = |xi: [f64; 2]| {
            let (values, maps) = tying_maps(&tying, &[basis(xi, gt)], parts, MembraneTying::Moments);
            let v = maps[0].tied(&values) * tied;
            let e = Matrix2::new(v[entry(0, 0)], v[entry(0, 1)], v[entry(1, 0)], v[entry(1, 1)]);
            gt.transpose() * e * gt
        };
        // Mean over the reference triangle (area 1/2): ∫ r = ∫ s = 1/6, ∫ r² = ∫ s² = 1/12, ∫ rs = 1/24.
        let integrals = [0.5, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 12.0, 1.0 / 24.0, 1.0 / 12.0];
        let mean: Vec<f64> = k
            .iter()
            .map(|row| 2.0 * row.iter().zip(&integrals).map(|(a, b)| a * b).sum::<f64>())
            .collect();
        let c = assumed([1.0 / 3.0, 1.0 / 3.0]);
        for (got, want) in [(c[(0, 0)], mean[0]), (c[(1, 1)], mean[1]), (c[(0, 1)], mean[2])] {
            assert!((got - want).abs() < 1e-13, "mean: {got} vs {want}");
        }
        let gauss3 = [
            (0.5 - 0.15f64.sqrt(), 5.0 / 18.0),
            (0.5, 8.0 / 18.0),
            (0.5 + 0.15f64.sqrt(), 5.0 / 18.0),
        ];
        for k in 0..3 {
            let (a, e) = (CORNERS[k], EDGE_DIRECTIONS[k]);
            let tau = nalgebra::Vector2::from(e);
            for weight in [|_: f64| 1.0, |t: f64| t] {
                let moment = |f: &dyn Fn([f64; 2]) -> Matrix2<f64>| -> f64 {
                    gauss3
                        .iter()
                        .map(|&(t, w)| w * weight(t) * tau.dot(&(f([a[0] + t * e[0], a[1] + t * e[1]]) * tau)))
                        .sum()
                };
                let (got, want) = (moment(&assumed), moment(&covariant));
                assert!((got - want).abs() < 1e-13, "edge {k}: {got} vs {want}");
            }
        }
    }

    /// The stabilised shear and drilling strains of a point are the mean over the interior tying points
    /// plus `α` times the point's own deviation from it (means computed here from the strains, not the
    /// maps); the membrane part keeps its Regge interpolant.
    #[test]
    fn stabilized_shear_and_drilling_are_the_mean_plus_a_scaled_fluctuation() {
        let gt = Matrix2::new(1.2, 0.3, -0.1, 0.9);
        let tp = tying_points();
        let tying: [PointBasis; N_TYING] = std::array::from_fn(|t| basis(tp[t], gt));
        // The quadrature points are the interior tying points (the pair's degree-2 rule).
        let quad: Vec<PointBasis> = (FIRST_INTERIOR..N_TYING).map(|t| tying[t]).collect();
        let strain = |t: usize, k: usize| ((7 * t + 3 * k) % 11) as f64 / 11.0 - 0.4 + 0.05 * (t * k) as f64;
        let tied = nalgebra::SVector::<f64, N_TIED>::from_fn(|i, _| strain(i / TIED, i % TIED));
        let (regge_values, regge) = tying_maps(&tying, &quad, AssumedParts::MEMBRANE, MembraneTying::Moments);
        let (mut values, mut maps) = (regge_values.clone(), regge.clone());
        let (alpha_shear, alpha_drilling) = (0.3, 0.6);
        stabilize_shear_and_drilling(&mut values, &mut maps, alpha_shear, alpha_drilling);
        let skew = |v: &[f64]| 0.5 * (v[entry(0, 1)] - v[entry(1, 0)]);
        let sym = |v: &[f64]| 0.5 * (v[entry(0, 1)] + v[entry(1, 0)]);
        let own = |q: usize| -> Vec<f64> { (0..TIED).map(|k| strain(FIRST_INTERIOR + q, k)).collect() };
        let mean = |f: &dyn Fn(&[f64]) -> f64| (0..3).map(|q| f(&own(q))).sum::<f64>() / 3.0;
        for q in 0..3 {
            let s = own(q);
            let sv = nalgebra::SVector::<f64, TIED>::from_column_slice(&s);
            let got = maps[q].tied(&values) * tied + maps[q].own * sv;
            let before = regge[q].tied(&regge_values) * tied + regge[q].own * sv;
            for r in [entry(2, 0), entry(2, 1)] {
                let m = mean(&|v: &[f64]| v[r]);
                let want = m + alpha_shear * (s[r] - m);
                assert!((got[r] - want).abs() < 1e-14, "shear {r}: {} vs {want}", got[r]);
            }
            let m = mean(&skew);
            let want = m + alpha_drilling * (skew(&s) - m);
            assert!((skew(got.as_slice()) - want).abs() < 1e-14, "drilling");
            for (g, b) in [
                (got[0], before[0]),
                (got[4], before[4]),
                (sym(got.as_slice()), sym(before.as_slice())),
            ] {
                assert!((g - b).abs() < 1e-14, "membrane: {g} vs {b}");
            }
        }
    }
}

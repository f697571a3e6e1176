//! The strain space of a point and the density's constant Hessian on it.
//!
//! At a quadrature point the strains are expressed in the orthonormal rest frame `Q = [t₁ t₂ n₀]`:
//! `Ê = Qᵀ E Q` and `Γ̂ = Qᵀ Γ Q`. Since `E n₀` and `Γ n₀` do not depend on the unknowns, only the first two
//! columns of each vary: 12 of the 18 numbers. The density is frame invariant, so in this frame the
//! alternating tensor is the constant `ĉ = −[e₃]×`, and a flat plate's density Hessian is one matrix per
//! material.
//!
//! Layout of a [`StrainVector`]: `Ê` column-major in entries 0–8, `Γ̂` column-major in 9–17.
//! [`VARIABLE_STRAINS`] lists the 12 entries that depend on the unknowns.

use crate::density::PointGeometry;
use crate::model::{EnergyTerm, TermSet};
use crate::parameters::Moduli;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The 18 strain numbers `(vec Ê, vec Γ̂)`.
pub type StrainVector = SVector<f64, 18>;
/// The constant Hessian of the density with respect to a [`StrainVector`].
pub type StrainMatrix = SMatrix<f64, 18, 18>;

/// Indices of the strain entries that depend on the unknowns: the first two columns of `Ê` and `Γ̂`.
pub const VARIABLE_STRAINS: [usize; 12] = [0, 1, 2, 3, 4, 5, 9, 10, 11, 12, 13, 14];

/// Splits a strain vector into `(Ê, Γ̂)`.
pub fn unpack<T: nalgebra::Scalar + Copy>(s: &SVector<T, 18>) -> (Matrix3<T>, Matrix3<T>) {
    (
        Matrix3::from_fn(|r, c| s[3 * c + r]),
        Matrix3::from_fn(|r, c| s[9 + 3 * c + r]),
    )
}

/// Packs `(Ê, Γ̂)` into a strain vector.
pub fn pack(e: &Matrix3<f64>, gamma: &Matrix3<f64>) -> StrainVector {
    StrainVector::from_fn(|i, _| {
        if i < 9 {
            e[(i % 3, i / 3)]
        } else {
            gamma[((i - 9) % 3, (i - 9) / 3)]
        }
    })
}

/// The rest geometry of a point in its own orthonormal frame `Q`: `b̂ = Qᵀ b Q`, `ĉ = −[e₃]×`.
pub fn local_geometry(frame: &Matrix3<f64>, b_world: &Matrix3<f64>) -> PointGeometry {
    let b = frame.transpose() * b_world * frame;
    let t = b.trace();
    PointGeometry {
        b,
        mean: 0.5 * t,
        gaussian: 0.5 * (t * t - (b * b).trace()),
        c: -cosserat_geometry::rotation::skew(&Vector3::z()),
    }
}

/// The constant strain offset `(Â, Γ̂_rest)` subtracted from the variable strains:
/// `Â = Qᵀ A Q` with the rest metric `A` (default `a = I − n₀ ⊗ n₀`, i.e. `diag(1, 1, 0)`), and the rest
/// curvature `Γ̂_rest = Qᵀ Γ_rest Q`.
pub fn strain_offset(
    frame: &Matrix3<f64>,
    rest_metric: Option<&Matrix3<f64>>,
    rest_curvature: Option<&Matrix3<f64>>,
) -> StrainVector {
    let a = match rest_metric {
        Some(a) => frame.transpose() * a * frame,
        None => Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0)),
    };
    let g = rest_curvature.map_or_else(Matrix3::zeros, |g| frame.transpose() * g * frame);
    pack(&a, &g)
}

/// The Hessian `D` of the strain-quadratic density with respect to the strain vector, in closed form.
///
/// Each strain-quadratic term of eqs. 1–7 is `f W(A, B)`: a scalar factor `f` of the thickness and the
/// rest curvature, one of the isotropic bilinear forms of eqs. 4–7, `W(A, B) = vec(A)ᵀ M vec(B)`, and
/// arguments linear in the strain vector, `vec A = L_A s` (with `vec(X Y Z) = (Zᵀ ⊗ X) vec Y`). Its
/// Hessian is `f (L_Aᵀ M L_B + L_Bᵀ M L_A)`. The density is a homogeneous quadratic form, so
/// `Ψ(s) = ½ sᵀ D s` exactly; [`crate::oracle::density_hessian`] differentiates
/// [`density`](crate::density::density) instead, and the tests compare the two.
pub fn strain_hessian(terms: &TermSet, geom: &PointGeometry, moduli: &Moduli) -> StrainMatrix {
    StrainHessians::new(terms, moduli).at(geom)
}

/// [`strain_hessian`] for the many points of one material and term set: the isotropic forms of the
/// terms are built once, and [`Self::at`] forms a point's matrix from its rest geometry.
pub struct StrainHessians<'a> {
    terms: &'a TermSet,
    moduli: &'a Moduli,
    forms: Forms,
}

impl<'a> StrainHessians<'a> {
    /// The forms of `terms` with `moduli`.
    pub fn new(terms: &'a TermSet, moduli: &'a Moduli) -> Self {
        Self {
            terms,
            moduli,
            forms: Forms::of(moduli),
        }
    }

    /// The density Hessian at a point of rest geometry `geom`.
    pub fn at(&self, geom: &PointGeometry) -> StrainMatrix {
        let mut d = StrainMatrix::zeros();
        for t in self.terms.terms() {
            if let Some(form) = TermForm::of(t.term, geom, self.moduli, &self.forms) {
                form.add_hessian(t.factor, &mut d);
            }
        }
        // Symmetric by construction up to round-off; make it exact.
        (d + d.transpose()) * 0.5
    }
}

/// An isotropic bilinear form on `vec` of 3 × 3 tensors.
type Form = SMatrix<f64, 9, 9>;

/// A block of an argument map: the matrix of `vec X ↦ vec(L X R)` on `Ê` or on `Γ̂`. The blocks are
/// kept apart because most terms read only one of the two parts, and the products skip the other.
// The matrix variant is large, but a block lives only on the stack of one point's set-up.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy)]
enum Block {
    Zero,
    Identity,
    Matrix(Form),
}

/// The blocks are Kronecker products of 3 × 3 matrices with the identity, `b` or `c`, so most of their
/// entries are zero: the products run over the nonzero ones (the same sums as the dense products).
impl Block {
    /// The block of `X ↦ left X right` (see [`kron`]).
    fn kron(right: &Matrix3<f64>, left: &Matrix3<f64>) -> Self {
        let identity = Matrix3::identity();
        if *right == identity && *left == identity {
            Block::Identity
        } else {
            Block::Matrix(kron(right, left))
        }
    }

    /// `selfᵀ m`, `None` for a zero block.
    fn tr_mul(&self, m: &Form) -> Option<Form> {
        match self {
            Block::Zero => None,
            Block::Identity => Some(*m),
            Block::Matrix(a) => {
                let mut out = Form::zeros();
                for i in 0..9 {
                    for k in (0..9).filter(|&k| a[(k, i)] != 0.0) {
                        let v = a[(k, i)];
                        for j in 0..9 {
                            out[(i, j)] += v * m[(k, j)];
                        }
                    }
                }
                Some(out)
            }
        }
    }

    /// `m self`, `None` for a zero block.
    fn mul_by(&self, m: &Form) -> Option<Form> {
        match self {
            Block::Zero => None,
            Block::Identity => Some(*m),
            Block::Matrix(b) => {
                let mut out = Form::zeros();
                for j in 0..9 {
                    for k in (0..9).filter(|&k| b[(k, j)] != 0.0) {
                        out.column_mut(j).axpy(b[(k, j)], &m.column(k), 1.0);
                    }
                }
                Some(out)
            }
        }
    }
}

/// A map from the strain vector to `vec` of a 3 × 3 argument: `vec A = e vec Ê + gamma vec Γ̂`.
#[derive(Clone, Copy)]
struct ArgumentMap {
    e: Block,
    gamma: Block,
}

impl ArgumentMap {
    /// `vec Ê`.
    const E: Self = Self {
        e: Block::Identity,
        gamma: Block::Zero,
    };

    /// `vec(Ê r) + gamma vec Γ̂`: its `Ê` block is the matrix of `Ê ↦ Ê r`.
    fn new(right: &Matrix3<f64>, gamma: Block) -> Self {
        Self {
            e: Block::kron(right, &Matrix3::identity()),
            gamma,
        }
    }

    /// `vec(left Γ̂ right)`.
    fn gamma(right: &Matrix3<f64>, left: &Matrix3<f64>) -> Self {
        Self {
            e: Block::Zero,
            gamma: Block::kron(right, left),
        }
    }

    /// The blocks, `Ê` first.
    fn blocks(&self) -> [&Block; 2] {
        [&self.e, &self.gamma]
    }
}

/// The isotropic forms of the terms: they depend on the material only.
struct Forms {
    membrane: Form,
    membrane_no_trace: Form,
    membrane_half_lambda: Form,
    curvature: Form,
}

impl Forms {
    fn of(m: &Moduli) -> Self {
        let [b1, b2, b3] = m.curvature_coefficients;
        let l2 = m.mu * m.length_scale * m.length_scale;
        Self {
            membrane: isotropic(m.mu, m.mu_c, m.plane_lambda),
            membrane_no_trace: isotropic(m.mu, m.mu_c, 0.0),
            membrane_half_lambda: isotropic(m.mu, m.mu_c, 0.5 * m.lambda),
            curvature: isotropic(l2 * b1, l2 * b2, l2 * b3),
        }
    }
}

/// One strain-quadratic term as `factor · W(L_A s, L_B s)`.
struct TermForm<'a> {
    factor: f64,
    form: &'a Form,
    a: ArgumentMap,
    b: ArgumentMap,
}

impl<'a> TermForm<'a> {
    /// The term's factor, form and arguments (`None` for a term that is not strain-quadratic).
    fn of(term: EnergyTerm, geom: &PointGeometry, m: &Moduli, forms: &'a Forms) -> Option<Self> {
        let h = m.thickness;
        let (h3, h5) = (h * h * h, h * h * h * h * h);
        let k = geom.gaussian;
        let (b, c) = (geom.b, geom.c);
        let i3 = Matrix3::identity();
        let (e, gamma) = (ArgumentMap::E, ArgumentMap::gamma);
        let (membrane, curv) = (&forms.membrane, &forms.curvature);
        let quadratic = |factor: f64, form: &'a Form, a: ArgumentMap| Self { factor, form, a, b: a };
        Some(match term {
            EnergyTerm::NonlinearVolume => return None,
            EnergyTerm::Membrane => quadratic(h, membrane, e),
            EnergyTerm::MembraneNoTrace => quadratic(h, &forms.membrane_no_trace, e),
            EnergyTerm::Bending => quadratic(h3 / 12.0, membrane, gamma(&i3, &c)),
            EnergyTerm::Curvature => quadratic(h, curv, gamma(&i3, &i3)),
            EnergyTerm::CurvedMembrane1 => quadratic(h - k * h3 / 12.0, membrane, e),
            // vec(E b + c Γ) = (bᵀ ⊗ I) vec E + (I ⊗ c) vec Γ.
            EnergyTerm::CurvedMembrane2 => quadratic(
                h3 / 12.0 - k * h5 / 80.0,
                membrane,
                ArgumentMap::new(&b, Block::kron(&i3, &c)),
            ),
            // W_mixt(E, c Γ (b − 2H I)).
            EnergyTerm::CurvedMembrane3 => Self {
                factor: h3 / 6.0,
                form: membrane,
                a: e,
                b: gamma(&(b - i3 * (2.0 * geom.mean)), &c),
            },
            // W_mp(E b² + c Γ b): λ/2 on the trace.
            EnergyTerm::CurvedMembrane4 => quadratic(
                h5 / 80.0,
                &forms.membrane_half_lambda,
                ArgumentMap::new(&(b * b), Block::kron(&b, &c)),
            ),
            EnergyTerm::CurvedBending1 => quadratic(h - k * h3 / 12.0, curv, gamma(&i3, &i3)),
            EnergyTerm::CurvedBending2 => quadratic(h3 / 12.0 - k * h5 / 80.0, curv, gamma(&b, &i3)),
            EnergyTerm::CurvedBending3 => quadratic(h5 / 80.0, curv, gamma(&(b * b), &i3)),
        })
    }

    /// Adds `weight · factor · (L_Aᵀ M L_B + L_Bᵀ M L_A)` to `d`. `L_Aᵀ M L_B` is formed block by block
    /// of the arguments as `(L_Aᵀ M) L_B`, each product over the nonzero entries of its factor: the
    /// same sums, in the same order, as the dense products.
    fn add_hessian(&self, weight: f64, d: &mut StrainMatrix) {
        // The blocks of `L_Aᵀ M L_B` by part (`Ê`, `Γ̂`), `None` where they vanish.
        let mut ab: [[Option<Form>; 2]; 2] = Default::default();
        for (row, a) in self.a.blocks().into_iter().enumerate() {
            let Some(am) = a.tr_mul(self.form) else { continue };
            for (col, b) in self.b.blocks().into_iter().enumerate() {
                ab[row][col] = b.mul_by(&am);
            }
        }
        let scale = weight * self.factor;
        for (row, col) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let sum = match (&ab[row][col], &ab[col][row]) {
                (Some(upper), Some(lower)) => upper + lower.transpose(),
                (Some(upper), None) => *upper,
                (None, Some(lower)) => lower.transpose(),
                (None, None) => continue,
            };
            let mut block = d.fixed_view_mut::<9, 9>(9 * row, 9 * col);
            block += sum * scale;
        }
    }
}

/// `vec(L X R) = (Rᵀ ⊗ L) vec X`: the matrix of `X ↦ L X R`.
fn kron(right: &Matrix3<f64>, left: &Matrix3<f64>) -> Form {
    let mut out = Form::zeros();
    for cb in 0..3 {
        for rb in 0..3 {
            let r = right[(cb, rb)];
            if r != 0.0 {
                out.fixed_view_mut::<3, 3>(3 * rb, 3 * cb).copy_from(&(left * r));
            }
        }
    }
    out
}

/// `vec(A)ᵀ M vec(B) = μ sym A : sym B + μ_c skew A : skew B + t tr A tr B`.
fn isotropic(mu: f64, mu_c: f64, t: f64) -> Form {
    Form::from_fn(|r, c| {
        let (ra, rb, ca, cb) = (r % 3, r / 3, c % 3, c / 3);
        // sym A : sym B = vec(A)ᵀ ½ (I + T) vec(B), skew likewise with ½ (I − T); T transposes.
        let identity = if r == c { 1.0 } else { 0.0 };
        let transpose = if ra == cb && rb == ca { 1.0 } else { 0.0 };
        let trace = if ra == rb && ca == cb { 1.0 } else { 0.0 };
        0.5 * mu * (identity + transpose) + 0.5 * mu_c * (identity - transpose) + t * trace
    })
}

/// One nonzero entry of a density Hessian.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// Row.
    pub row: u8,
    /// Column.
    pub col: u8,
    /// Value.
    pub value: f64,
}

/// A density Hessian `D` together with the nonzero entries of its block on the variable strains.
///
/// `D` is sparse: a flat plate's has 16 nonzero entries in the 12 × 12 block of the variable strains
/// (of 144), a curved shell's about half. The kernels' products `D s` and `D J` (12 × 12 by 12 × 15)
/// therefore run over the nonzero entries, column by column in increasing order, which adds exactly
/// the nonzero terms of the dense products in the same order: the same numbers at a fraction of the
/// work.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityMatrix {
    matrix: StrainMatrix,
    /// Nonzero entries of `D`, sorted by column and then row.
    entries: Vec<Entry>,
    /// Nonzero entries of the block of the variable strains, indexed by position in
    /// [`VARIABLE_STRAINS`] (0–11), sorted by column and then row.
    variable_entries: Vec<Entry>,
}

impl DensityMatrix {
    /// Prepares a density Hessian.
    pub fn new(matrix: StrainMatrix) -> Self {
        let nonzeros = |indices: &[usize]| {
            let mut out = Vec::new();
            for (c, &ic) in indices.iter().enumerate() {
                for (r, &ir) in indices.iter().enumerate() {
                    let value = matrix[(ir, ic)];
                    if value != 0.0 {
                        out.push(Entry {
                            row: r as u8,
                            col: c as u8,
                            value,
                        });
                    }
                }
            }
            out
        };
        let all: [usize; 18] = std::array::from_fn(|i| i);
        Self {
            entries: nonzeros(&all),
            variable_entries: nonzeros(&VARIABLE_STRAINS),
            matrix,
        }
    }

    /// `D s`, over the nonzero entries (the same sums as the dense product).
    #[inline]
    pub fn mul_vector(&self, s: &StrainVector) -> StrainVector {
        let mut out = StrainVector::zeros();
        for e in &self.entries {
            out[e.row as usize] += e.value * s[e.col as usize];
        }
        out
    }

    /// The dense matrix.
    pub fn matrix(&self) -> &StrainMatrix {
        &self.matrix
    }

    /// The nonzero entries of the block of the variable strains (indices are positions in
    /// [`VARIABLE_STRAINS`]), sorted by column and then row.
    pub fn variable_entries(&self) -> &[Entry] {
        &self.variable_entries
    }
}

/// The density Hessians of all points of a shell: one shared matrix where the rest state allows it
/// (every flat point of a material), one per point otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityTable {
    matrices: Vec<DensityMatrix>,
    /// Matrix index per point; empty when all points share `matrices[0]`.
    index: Vec<u32>,
}

impl DensityTable {
    /// One matrix for every point.
    pub fn uniform(d: StrainMatrix) -> Self {
        Self {
            matrices: vec![DensityMatrix::new(d)],
            index: Vec::new(),
        }
    }

    /// Distinct matrices and, per point, the index of its matrix.
    ///
    /// # Panics
    /// If an index is out of range.
    #[track_caller]
    pub fn indexed(matrices: Vec<StrainMatrix>, index: Vec<u32>) -> Self {
        assert!(
            index.iter().all(|&i| (i as usize) < matrices.len()),
            "density index out of range"
        );
        if matrices.len() == 1 {
            Self::uniform(matrices[0])
        } else {
            Self {
                matrices: matrices.into_iter().map(DensityMatrix::new).collect(),
                index,
            }
        }
    }

    /// The matrix of point `p`.
    #[inline]
    pub fn get(&self, p: usize) -> &DensityMatrix {
        if self.index.is_empty() {
            &self.matrices[0]
        } else {
            &self.matrices[self.index[p] as usize]
        }
    }

    /// Number of distinct matrices stored.
    pub fn n_matrices(&self) -> usize {
        self.matrices.len()
    }
}

/// The strain-quadratic energy split by the part of the strain it comes from \[J\]. Each part is
/// `½ sₚᵀ D sₚ` integrated, with `sₚ` the strain vector restricted to that part; on curved points `D`
/// couples the parts, and `total` minus the sum of the parts is that coupling.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyParts {
    /// The symmetric tangential block of `E` (in-plane stretch and shear).
    pub membrane: f64,
    /// The skew tangential block of `E` (drilling).
    pub drilling: f64,
    /// The normal row of `E` (transverse shear).
    pub shear: f64,
    /// `Γ` (bending and curvature terms).
    pub bending: f64,
    /// The whole strain-quadratic energy.
    pub total: f64,
}

impl EnergyParts {
    /// Adds a point's strains `s` with density Hessian `d` and integration weight `weight`.
    pub fn add(&mut self, s: &StrainVector, d: &StrainMatrix, weight: f64) {
        let quad = |v: &StrainVector| 0.5 * v.dot(&(d * v)) * weight;
        // Ê column-major: (a, γ) at 3γ + a; rows 0, 1 tangential, row 2 normal.
        let (sym, skw) = (0.5 * (s[3] + s[1]), 0.5 * (s[3] - s[1]));
        let mut membrane = StrainVector::zeros();
        membrane[0] = s[0];
        membrane[4] = s[4];
        membrane[1] = sym;
        membrane[3] = sym;
        let mut drilling = StrainVector::zeros();
        drilling[1] = -skw;
        drilling[3] = skw;
        let mut shear = StrainVector::zeros();
        for i in [2, 5, 8] {
            shear[i] = s[i];
        }
        let mut bending = *s;
        bending.fixed_rows_mut::<9>(0).fill(0.0);
        self.membrane += quad(&membrane);
        self.drilling += quad(&drilling);
        self.shear += quad(&shear);
        self.bending += quad(&bending);
        self.total += quad(s);
    }
}

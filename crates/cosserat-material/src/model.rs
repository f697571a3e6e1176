//! Model choices and the set of active energy terms.
//!
//! The energy of a point is a weighted sum of [`EnergyTerm`]s. Which terms are active is decided once,
//! from the model, the material and the rest state ([`TermSet::select`]): a flat rest state gets the
//! plate terms even under the shell model (the curved terms vanish there), a zero coefficient removes
//! its term, and the run summary lists what was active ([`TermSet::names`]).

use crate::error::MaterialError;
use crate::parameters::Moduli;

/// Which Cosserat energy a shell uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShellModel {
    /// The flat-reference plate model (model.md §3.3): membrane, bending and curvature terms.
    Plate,
    /// The curved-shell model with every term of supplement eqs. 2–3 up to O(h⁵) (model.md §3.5).
    Shell,
}

/// How the curved-shell terms are counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CurvedTerms {
    /// The supplement's energy: each term once, with the three curvature (bending) terms. Default.
    #[default]
    Supplement,
    /// Reproduces the paper's reference code (model.md §3.6): membrane terms 1–3 counted twice, term 4
    /// once, and no curvature terms. Only for comparisons with the paper's figures and timings.
    ReferenceCompatibility,
}

/// The in-plane volume response of the plate membrane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MembraneVolume {
    /// The quadratic trace term of `W_m(E)`. Default.
    #[default]
    Quadratic,
    /// The trace term replaced by `h ½ λμ/(λ+2μ) ((J−1)² + (1/J−1)²)` with the area ratio `J`
    /// (model.md §3.4); resists inversion under large compression. Plate model only.
    Nonlinear,
}

/// The axial vector used for the curvature tensor `Γ_α = axl(Rᵀ ∂_α R)` when `Rᵀ ∂_α R` is only
/// approximately skew (interpolated nodal rotations).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AxlVariant {
    /// `axl(skew M)`: the axial vector of the skew part. Default.
    #[default]
    SkewPart,
    /// `(−M₂₃, −M₃₁, −M₁₂)`, the negated upper triangle of the reference code.
    UpperTriangle,
}

/// The model options of a shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ModelOptions {
    /// Plate or curved shell.
    pub model: ShellModel,
    /// How curved terms are counted (shell model only).
    pub curved_terms: CurvedTerms,
    /// Quadratic or nonlinear membrane volume term (plate model only).
    pub membrane_volume: MembraneVolume,
    /// Axial-vector variant of the curvature tensor.
    pub axl: AxlVariant,
}

impl ModelOptions {
    /// Default options of a model: supplement terms, quadratic membrane, `axl(skew M)`.
    pub fn new(model: ShellModel) -> Self {
        Self {
            model,
            curved_terms: CurvedTerms::default(),
            membrane_volume: MembraneVolume::default(),
            axl: AxlVariant::default(),
        }
    }
}

/// One term of the energy density. `E` is the membrane strain, `Γ` the curvature tensor (minus the rest
/// curvature), `c` the alternating tensor, `b`, `H`, `K` the rest curvature of the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EnergyTerm {
    /// `h W_m(E)`.
    Membrane,
    /// `h (μ |sym E|² + μ_c |skew E|²)`: the membrane without its trace term (used with
    /// [`EnergyTerm::NonlinearVolume`]).
    MembraneNoTrace,
    /// `h ½ λμ/(λ+2μ) ((J−1)² + (1/J−1)²)` with the area ratio `J` (model.md §3.4).
    NonlinearVolume,
    /// `h³/12 W_m(cΓ)` (times `κ_b` in the plate model).
    Bending,
    /// `h W_curv(Γ)`.
    Curvature,
    /// `(h − K h³/12) W_m(E)`.
    CurvedMembrane1,
    /// `(h³/12 − K h⁵/80) W_m(E b + cΓ)`.
    CurvedMembrane2,
    /// `h³/6 W_mixt(E, cΓ b − 2H cΓ)`.
    CurvedMembrane3,
    /// `h⁵/80 W_mp(E b² + cΓ b)`.
    CurvedMembrane4,
    /// `(h − K h³/12) W_curv(Γ)`.
    CurvedBending1,
    /// `(h³/12 − K h⁵/80) W_curv(Γ b)`.
    CurvedBending2,
    /// `h⁵/80 W_curv(Γ b²)`.
    CurvedBending3,
}

impl EnergyTerm {
    /// The name used in run summaries.
    pub fn name(self) -> &'static str {
        match self {
            EnergyTerm::Membrane => "membrane",
            EnergyTerm::MembraneNoTrace => "membrane_no_trace",
            EnergyTerm::NonlinearVolume => "nonlinear_volume",
            EnergyTerm::Bending => "bending",
            EnergyTerm::Curvature => "curvature",
            EnergyTerm::CurvedMembrane1 => "curved_membrane_1",
            EnergyTerm::CurvedMembrane2 => "curved_membrane_2",
            EnergyTerm::CurvedMembrane3 => "curved_membrane_3",
            EnergyTerm::CurvedMembrane4 => "curved_membrane_4",
            EnergyTerm::CurvedBending1 => "curved_bending_1",
            EnergyTerm::CurvedBending2 => "curved_bending_2",
            EnergyTerm::CurvedBending3 => "curved_bending_3",
        }
    }

    /// Whether the term is a quadratic form of the strains `(E, Γ)`; all but the nonlinear volume term.
    pub fn is_strain_quadratic(self) -> bool {
        self != EnergyTerm::NonlinearVolume
    }
}

/// A term with the factor it is counted with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeightedTerm {
    /// The term.
    pub term: EnergyTerm,
    /// Its factor (1 except for the bending correction and the reference-compatibility mode).
    pub factor: f64,
}

/// The active terms of a point's energy density.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TermSet {
    terms: Vec<WeightedTerm>,
}

impl TermSet {
    /// The terms for a point with the given options and moduli; `curved` says whether the rest surface
    /// is curved there (`b ≠ 0`).
    ///
    /// # Errors
    /// [`MaterialError::Unsupported`] for the nonlinear volume term with the shell model.
    pub fn select(options: &ModelOptions, moduli: &Moduli, curved: bool) -> Result<Self, MaterialError> {
        use EnergyTerm::*;
        let curvature_on = moduli.length_scale > 0.0 && moduli.curvature_coefficients.iter().any(|&b| b > 0.0);
        let mut terms = Vec::new();
        let mut push = |term, factor: f64| {
            if factor != 0.0 {
                terms.push(WeightedTerm { term, factor })
            }
        };
        match (options.model, options.curved_terms) {
            (ShellModel::Plate, _) => {
                match options.membrane_volume {
                    MembraneVolume::Quadratic => push(Membrane, 1.0),
                    MembraneVolume::Nonlinear => {
                        push(MembraneNoTrace, 1.0);
                        push(NonlinearVolume, 1.0);
                    }
                }
                push(Bending, moduli.bending_correction);
                if curvature_on {
                    push(Curvature, 1.0);
                }
            }
            (ShellModel::Shell, _) if options.membrane_volume == MembraneVolume::Nonlinear => {
                return Err(MaterialError::Unsupported(
                    "the nonlinear volume term is defined for the plate model only",
                ));
            }
            (ShellModel::Shell, CurvedTerms::Supplement) => {
                if curved {
                    for t in [CurvedMembrane1, CurvedMembrane2, CurvedMembrane3, CurvedMembrane4] {
                        push(t, 1.0);
                    }
                    if curvature_on {
                        for t in [CurvedBending1, CurvedBending2, CurvedBending3] {
                            push(t, 1.0);
                        }
                    }
                } else {
                    // With b = 0 the curved terms reduce exactly to these (without κ_b).
                    push(Membrane, 1.0);
                    push(Bending, 1.0);
                    if curvature_on {
                        push(Curvature, 1.0);
                    }
                }
            }
            (ShellModel::Shell, CurvedTerms::ReferenceCompatibility) => {
                if curved {
                    for t in [CurvedMembrane1, CurvedMembrane2, CurvedMembrane3] {
                        push(t, 2.0);
                    }
                    push(CurvedMembrane4, 1.0);
                } else {
                    push(Membrane, 2.0);
                    push(Bending, 2.0);
                }
            }
        }
        Ok(Self { terms })
    }

    /// The weighted terms.
    pub fn terms(&self) -> &[WeightedTerm] {
        &self.terms
    }

    /// Whether a term is active.
    pub fn contains(&self, term: EnergyTerm) -> bool {
        self.terms.iter().any(|t| t.term == term)
    }

    /// Names for the run summary, with the factor where it is not 1 (e.g. `"curved_membrane_1 x2"`).
    pub fn names(&self) -> Vec<String> {
        self.terms
            .iter()
            .map(|t| {
                if t.factor == 1.0 {
                    t.term.name().to_string()
                } else {
                    format!("{} x{}", t.term.name(), t.factor)
                }
            })
            .collect()
    }
}

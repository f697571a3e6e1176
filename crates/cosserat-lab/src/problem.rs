//! The validation problems as data: scene, compared quantities, reference solution and refinement
//! ladders per element pair. Shared by `cargo xtask validate` and `cargo xtask study`.

use crate::postprocess::ProbeTable;
use crate::reference;
use anyhow::Result;
use std::f64::consts::PI;

/// A displacement/rotation element pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pair {
    /// Linear displacements and rotations.
    Tri3Tri3,
    /// Quadratic displacements, linear rotations (the paper's main discretisation).
    Tri6Tri3,
    /// Quadratic displacements and rotations.
    Tri6Tri6,
}

impl Pair {
    /// All pairs, cheapest first.
    pub const ALL: [Pair; 3] = [Pair::Tri3Tri3, Pair::Tri6Tri3, Pair::Tri6Tri6];

    /// `Tri6/Tri3` etc.
    pub fn label(self) -> &'static str {
        match self {
            Pair::Tri3Tri3 => "Tri3/Tri3",
            Pair::Tri6Tri3 => "Tri6/Tri3",
            Pair::Tri6Tri6 => "Tri6/Tri6",
        }
    }

    /// Scene overrides selecting the pair.
    pub fn overrides(self) -> Vec<String> {
        let (d, r) = match self {
            Pair::Tri3Tri3 => ("tri3", "tri3"),
            Pair::Tri6Tri3 => ("tri6", "tri3"),
            Pair::Tri6Tri6 => ("tri6", "tri6"),
        };
        vec![format!("mesh.element={d}"), format!("mesh.rotation_element={r}")]
    }

    /// The expected order of the displacement error under uniform refinement in the asymptotic range:
    /// `min(k_u, k_θ) + 1` for interpolation orders `k_u` (displacements) and `k_θ` (rotations).
    pub fn expected_order(self) -> f64 {
        match self {
            Pair::Tri3Tri3 | Pair::Tri6Tri3 => 2.0,
            Pair::Tri6Tri6 => 3.0,
        }
    }

    /// Colour index for plots.
    pub fn color(self) -> usize {
        match self {
            Pair::Tri3Tri3 => 2,
            Pair::Tri6Tri3 => 1,
            Pair::Tri6Tri6 => 3,
        }
    }
}

/// A strain interpolation of the shell element (`material.strain_interpolation`, docs/model-notes.md),
/// by its scene name.
pub use cosserat::scene::schema::StrainInterpolationName as Interpolation;

/// One mesh of a refinement ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Label, e.g. `20×2`.
    pub label: String,
    /// Scene overrides.
    pub overrides: Vec<String>,
    /// Element length along the structure \[m\].
    pub h: f64,
}

/// A second value shown beside the reference: its label and its value at load factor λ.
pub type SecondValue = (&'static str, fn(f64) -> Option<f64>);

/// A compared quantity: how it is read from the probes, and its reference.
#[derive(Debug, Clone, Copy)]
pub struct Component {
    /// Label, e.g. `−U` or `W`.
    pub label: &'static str,
    /// Reads the quantity from a probe row.
    pub read: fn(&ProbeTable, usize) -> Result<f64>,
    /// The reference value at load factor λ.
    pub reference: fn(f64) -> f64,
    /// A second value at λ shown beside the reference (e.g. Sze's FE result): its label and values.
    pub second: Option<SecondValue>,
}

/// A validation problem.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Name (the scene's name).
    pub name: &'static str,
    /// Title.
    pub title: &'static str,
    /// Scene file.
    pub scene: &'static str,
    /// What the reference is.
    pub reference_note: &'static str,
    /// Compared quantities.
    pub components: Vec<Component>,
    /// Meshes per pair, coarse to fine.
    pub ladder: fn(Pair) -> Vec<Mesh>,
    /// The mesh of the scene file (the "moderate mesh" of the validation).
    pub default_mesh: &'static str,
    /// Whether the problem has a curved rest state (plate and shell models differ).
    pub curved: bool,
    /// Whether the study measures errors against the components' second values instead of the
    /// reference (when the reference is a rounded table and the second value a closed form).
    pub study_against_second: bool,
    /// The smallest error the reference resolves, where it is a finite element result and not a
    /// closed form (its own discretisation error); the study reports no cheapest run for finer targets.
    pub resolution: Option<f64>,
}

fn col(p: &ProbeTable, row: usize, name: &str) -> Result<f64> {
    let c = p.column(name)?;
    p.rows
        .get(row)
        .map(|r| r[c])
        .ok_or_else(|| anyhow::anyhow!("no probe row {row}"))
}

fn strip_ladder(length: f64, ratio: usize, tri6: &[usize], tri3: &[usize]) -> impl Fn(Pair) -> Vec<Mesh> {
    let tri6 = tri6.to_vec();
    let tri3 = tri3.to_vec();
    move |pair| {
        let meshes: Vec<(usize, usize)> = match pair {
            Pair::Tri3Tri3 => tri3.iter().map(|&nx| (nx, 1)).collect(),
            _ => tri6.iter().map(|&nx| (nx, (nx / ratio).max(1))).collect(),
        };
        meshes
            .into_iter()
            .map(|(nx, ny)| Mesh {
                label: format!("{nx}×{ny}"),
                overrides: vec![format!("mesh.nx={nx}"), format!("mesh.ny={ny}")],
                h: length / nx as f64,
            })
            .collect()
    }
}

fn sze_shear_ladder(pair: Pair) -> Vec<Mesh> {
    strip_ladder(10.0, 10, &[10, 20, 40, 80], &[80, 160, 320, 640, 1280])(pair)
}

/// The thin strips start coarser: where the paper's pair locks, the default discretisation is within
/// 1 % on a few elements, and a ladder that starts at its answer cannot say which mesh is the cheapest.
fn thin_shear_ladder(pair: Pair) -> Vec<Mesh> {
    strip_ladder(10.0, 10, &[5, 10, 20, 40, 80], &[80, 160, 320, 640, 1280])(pair)
}

fn rollup_ladder(pair: Pair) -> Vec<Mesh> {
    strip_ladder(12.0, 12, &[12, 24, 48, 96], &[96, 192, 384, 768, 1536])(pair)
}

fn small_load_ladder(pair: Pair) -> Vec<Mesh> {
    strip_ladder(1.0, 10, &[10, 20, 40, 80], &[80, 160, 320, 640, 1280])(pair)
}

fn ring_ladder(pair: Pair) -> Vec<Mesh> {
    let ns: &[usize] = match pair {
        Pair::Tri3Tri3 => &[256, 512, 1024, 2048],
        _ => &[32, 64, 128, 256, 512],
    };
    ns.iter()
        .map(|&n| Mesh {
            label: format!("{n}×1"),
            overrides: vec![format!("mesh.n_around={n}")],
            h: 2.0 * PI / n as f64,
        })
        .collect()
}

/// The slit annular plate: `n_radial × n_angular` with ten times as many elements around as across,
/// as the reference's own meshes; the element length is the radial one.
fn slit_annular_ladder(pair: Pair) -> Vec<Mesh> {
    let ns: &[usize] = match pair {
        Pair::Tri3Tri3 => &[8, 16],
        _ => &[2, 4, 8, 16],
    };
    ns.iter()
        .map(|&n| Mesh {
            label: format!("{n}×{}", 10 * n),
            overrides: vec![format!("mesh.n_radial={n}"), format!("mesh.n_angular={}", 10 * n)],
            h: 4.0 / n as f64,
        })
        .collect()
}

fn table_value(table: &[(f64, f64, f64)], lambda: f64, second: bool) -> Option<f64> {
    table
        .iter()
        .find(|r| (r.0 - lambda).abs() < 1e-9)
        .map(|r| if second { r.2 } else { r.1 })
}

/// Bending and shear stiffness of the small-load cantilever's cross-section (scene values: E = 1e9,
/// ν = 0, h = 0.01, b = 0.1, L_c = 1e-5, μ_c = μ): `B = E b h³/12 + 2 b h μ L_c²` (model-notes.md) and
/// `S = b h (μ + μ_c)` (the transverse-shear coefficient of the membrane energy).
fn small_load_stiffness() -> (f64, f64) {
    let (e, h, b, lc): (f64, f64, f64, f64) = (1e9, 0.01, 0.1, 1e-5);
    let mu = e / 2.0;
    (e * b * h.powi(3) / 12.0 + 2.0 * b * h * mu * lc * lc, b * h * 2.0 * mu)
}

/// The inextensible elastica's tip shortening `−U` of the Sze 3.1 strip (L = 10, EI = 100, end force
/// 4 λ) at load factor λ.
fn elastica_shortening(lambda: f64) -> f64 {
    10.0 * reference::elastica_tip(4.0 * lambda).1
}

/// The elastica's tip deflection `W` of the Sze 3.1 strip at load factor λ.
fn elastica_deflection(lambda: f64) -> f64 {
    10.0 * reference::elastica_tip(4.0 * lambda).0
}

/// The tip displacements `−U` and `W` of the Sze 3.1 strip against the inextensible elastica.
fn elastica_components() -> Vec<Component> {
    vec![
        Component {
            label: "−U",
            read: |p, r| Ok(-col(p, r, "tip.ux")?),
            reference: elastica_shortening,
            second: None,
        },
        Component {
            label: "W",
            read: |p, r| col(p, r, "tip.uz"),
            reference: elastica_deflection,
            second: None,
        },
    ]
}

/// The Sze 3.1 strip made thin at constant bending stiffness (`scene`, `h/L` in the title).
fn thin_cantilever(name: &'static str, title: &'static str, scene: &'static str) -> Problem {
    Problem {
        name,
        title,
        scene,
        reference_note: "the inextensible elastica (computed here by elliptic integrals); the model's extension, shear and curvature energy change the tip by less than 2e-5 relative at this slenderness",
        components: elastica_components(),
        ladder: thin_shear_ladder,
        default_mesh: "10×1",
        curved: false,
        study_against_second: false,
        resolution: None,
    }
}

/// All validation problems.
pub fn registry() -> Vec<Problem> {
    // Long because the registry is a data table, each problem with its references and ladder, that
    // reads best as one list.
    vec![
        Problem {
            name: "sze_cantilever_end_shear",
            title: "Cantilever under end shear force (Sze 3.1)",
            scene: "scenes/validation/sze_cantilever_end_shear.toml",
            reference_note: "Sze, Liu & Lo (2004) table (their 16×1 S4R result, 3 decimals); the inextensible elastica (computed here by elliptic integrals) is shown beside it",
            components: vec![
                Component {
                    label: "−U",
                    read: |p, r| Ok(-col(p, r, "tip.ux")?),
                    reference: |l| table_value(&reference::SZE_END_SHEAR, l, false).unwrap_or(f64::NAN),
                    second: Some(("elastica", |l| Some(elastica_shortening(l)))),
                },
                Component {
                    label: "W",
                    read: |p, r| col(p, r, "tip.uz"),
                    reference: |l| table_value(&reference::SZE_END_SHEAR, l, true).unwrap_or(f64::NAN),
                    second: Some(("elastica", |l| Some(elastica_deflection(l)))),
                },
            ],
            ladder: sze_shear_ladder,
            default_mesh: "20×2",
            curved: false,
            study_against_second: true,
            resolution: None,
        },
        Problem {
            name: "end_moment_rollup",
            title: "Cantilever rolled up by an end moment (Sze 3.2)",
            scene: "scenes/validation/end_moment_rollup.toml",
            reference_note: "the exact arc −U/L = 1 − sin(2πλ)/(2πλ), W/L = (1 − cos(2πλ))/(2πλ); Sze's 16×1 FE values shown beside it",
            components: vec![
                Component {
                    label: "−U",
                    read: |p, r| Ok(-col(p, r, "tip.ux")?),
                    reference: |l| reference::rollup_tip(l, 12.0).0,
                    second: Some(("Sze 16×1 FE", |l| table_value(&reference::SZE_END_MOMENT_FE, l, false))),
                },
                Component {
                    label: "W",
                    read: |p, r| col(p, r, "tip.uz"),
                    reference: |l| reference::rollup_tip(l, 12.0).1,
                    second: Some(("Sze 16×1 FE", |l| table_value(&reference::SZE_END_MOMENT_FE, l, true))),
                },
            ],
            ladder: rollup_ladder,
            default_mesh: "48×4",
            curved: false,
            study_against_second: false,
            resolution: None,
        },
        Problem {
            name: "cantilever_small_load",
            title: "Cantilever under a small end load (Euler–Bernoulli)",
            scene: "scenes/validation/cantilever_small_load.toml",
            reference_note: "Euler–Bernoulli P L³/(3B) plus the Timoshenko shear term P L/S of this model (relative 2.5e-5)",
            components: vec![Component {
                label: "W",
                read: |p, r| col(p, r, "tip.uz"),
                reference: |l| {
                    let (b, s) = small_load_stiffness();
                    reference::cantilever_tip_deflection(2.5e-3 * l, 1.0, b, s)
                },
                second: None,
            }],
            ladder: small_load_ladder,
            default_mesh: "20×2",
            curved: false,
            study_against_second: false,
            resolution: None,
        },
        Problem {
            name: "ring_diametral_compression",
            title: "Thin ring squeezed across a diameter (curved rest state)",
            scene: "scenes/validation/ring_diametral_compression.toml",
            reference_note: "thin-ring theory (Roark, ring case 1), itself exact only to O((h/R)², δ/R) ≈ 1e-4 for this ring",
            components: vec![
                Component {
                    label: "δ_V",
                    read: |p, r| Ok(-col(p, r, "top.uy")?),
                    reference: |l| reference::ring_diametral(0.1 * l, 1.0, 100.0).0,
                    second: None,
                },
                Component {
                    label: "δ_H",
                    read: |p, r| Ok(col(p, r, "right.ux")? - col(p, r, "left.ux")?),
                    reference: |l| reference::ring_diametral(0.1 * l, 1.0, 100.0).1,
                    second: None,
                },
            ],
            ladder: ring_ladder,
            default_mesh: "128×1",
            curved: true,
            study_against_second: false,
            resolution: None,
        },
        Problem {
            name: "slit_annular_plate",
            title: "Slit annular plate lifted by a line force (Sze 3.3)",
            scene: "scenes/validation/slit_annular_plate.toml",
            reference_note: "Sze, Liu & Lo (2004) table (their 10×80 S4R result, 3 decimals)",
            components: vec![
                Component {
                    label: "W_A",
                    read: |p, r| col(p, r, "A.uz"),
                    reference: |l| table_value(&reference::SZE_SLIT_ANNULAR, l, false).unwrap_or(f64::NAN),
                    second: None,
                },
                Component {
                    label: "W_B",
                    read: |p, r| col(p, r, "B.uz"),
                    reference: |l| table_value(&reference::SZE_SLIT_ANNULAR, l, true).unwrap_or(f64::NAN),
                    second: None,
                },
            ],
            ladder: slit_annular_ladder,
            default_mesh: "4×40",
            curved: false,
            study_against_second: false,
            // The table lies 0.2 % above the limit that the refined meshes of every discretisation
            // approach (docs/validation.md).
            resolution: Some(2e-3),
        },
        thin_cantilever(
            "thin_cantilever_end_shear",
            "Thin cantilever under end shear force (Sze 3.1 at h/L = 1e-3)",
            "scenes/validation/thin_cantilever_end_shear.toml",
        ),
        thin_cantilever(
            "very_thin_cantilever_end_shear",
            "Very thin cantilever under end shear force (Sze 3.1 at h/L = 1e-4)",
            "scenes/validation/very_thin_cantilever_end_shear.toml",
        ),
    ]
}

/// Errors of one run against the reference: for each component, the largest `|u − u_ref|` over the
/// load levels divided by the largest `|u_ref|` of that component.
#[derive(Debug, Clone, PartialEq)]
pub struct Errors {
    /// Per component, in the order of [`Problem::components`].
    pub per_component: Vec<f64>,
}

impl Errors {
    /// The largest error over all components.
    pub fn max(&self) -> f64 {
        self.per_component.iter().copied().fold(0.0, f64::max)
    }
}

/// Per load level: `(λ, [(value, reference, error)] per component)`, errors normalised as in [`Errors`].
pub type LevelTable = Vec<(f64, Vec<(f64, f64, f64)>)>;

/// Compares a run's probes with the reference (or, with `against_second`, with the components' second
/// values where they have one) at every written load level `λ > 0`.
///
/// # Errors
/// Missing probe columns.
pub fn compare(problem: &Problem, probes: &ProbeTable, against_second: bool) -> Result<(Errors, LevelTable)> {
    let t = probes.column("t")?;
    let rows: Vec<usize> = (0..probes.rows.len()).filter(|&r| probes.rows[r][t] > 0.0).collect();
    let mut table: LevelTable = Vec::new();
    for &r in &rows {
        let lambda = probes.rows[r][t];
        let mut values = Vec::new();
        for c in &problem.components {
            let reference = match (against_second, c.second) {
                (true, Some((_, f))) => f(lambda).unwrap_or(f64::NAN),
                _ => (c.reference)(lambda),
            };
            values.push(((c.read)(probes, r)?, reference, 0.0));
        }
        table.push((lambda, values));
    }
    let mut per_component = Vec::new();
    for k in 0..problem.components.len() {
        let scale = table.iter().map(|(_, v)| v[k].1.abs()).fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for (_, v) in &mut table {
            let e = (v[k].0 - v[k].1).abs() / scale;
            v[k].2 = e;
            worst = if e.is_nan() { f64::NAN } else { worst.max(e) };
        }
        per_component.push(if table.is_empty() { f64::NAN } else { worst });
    }
    Ok((Errors { per_component }, table))
}

/// A discretisation: an element pair with a strain interpolation, on the pair's default quadrature rule
/// or another.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Discretisation {
    /// The element pair.
    pub pair: Pair,
    /// The strain interpolation.
    pub interpolation: Interpolation,
    /// `mesh.quadrature_degree` (`None`: the pair's default).
    pub quadrature_degree: Option<usize>,
}

impl Discretisation {
    /// The default discretisation of a scene with quadratic displacements: Tri6/Tri6 with Regge
    /// membrane strains and stabilised shear and drilling, on the 3-point rule.
    pub const DEFAULT: Self = Self::new(Pair::Tri6Tri6, Interpolation::ReggeStabilized);

    /// A pair with a strain interpolation.
    pub const fn new(pair: Pair, interpolation: Interpolation) -> Self {
        Self {
            pair,
            interpolation,
            quadrature_degree: None,
        }
    }

    /// A pair with the paper's strain interpolation.
    pub const fn paper(pair: Pair) -> Self {
        Self::new(pair, Interpolation::Paper)
    }

    /// The same on the six-point rule (degree 4; quadratic rotations with `regge_stabilized` take the
    /// 3-point rule unless the scene names another).
    pub const fn on_six_points(self) -> Self {
        Self {
            quadrature_degree: Some(4),
            ..self
        }
    }

    /// `Tri6/Tri3` with the paper's interpolation, `Tri6/Tri3 stabilized` with another,
    /// `Tri6/Tri6 regge_stabilized 6-point` on the six-point rule.
    pub fn label(self) -> String {
        let mut label = match self.interpolation {
            Interpolation::Paper => self.pair.label().to_string(),
            other => format!("{} {}", self.pair.label(), other.as_str()),
        };
        match self.quadrature_degree {
            None => {}
            Some(2) => label.push_str(" 3-point"),
            Some(4) => label.push_str(" 6-point"),
            Some(d) => label.push_str(&format!(" degree {d}")),
        }
        label
    }

    /// A directory name: `tri6_tri3_paper`, `tri6_tri6_regge_stabilized_q4` etc.
    pub fn directory(self) -> String {
        let mut name = format!(
            "{}_{}",
            self.pair.label().to_lowercase().replace('/', "_"),
            self.interpolation.as_str()
        );
        if let Some(d) = self.quadrature_degree {
            name.push_str(&format!("_q{d}"));
        }
        name
    }

    /// The scene overrides selecting it.
    pub fn overrides(self) -> Vec<String> {
        let mut ov = self.pair.overrides();
        ov.push(self.interpolation.scene_override());
        if let Some(d) = self.quadrature_degree {
            ov.push(format!("mesh.quadrature_degree={d}"));
        }
        ov
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> std::path::PathBuf {
        crate::workspace_root()
    }

    #[test]
    fn every_ladder_point_is_a_valid_scene() {
        for p in registry() {
            for pair in Pair::ALL {
                for mesh in (p.ladder)(pair) {
                    let mut ov = pair.overrides();
                    ov.extend(mesh.overrides.iter().cloned());
                    let scene = cosserat::scene::load_scene(&root().join(p.scene), &ov);
                    assert!(
                        scene.is_ok(),
                        "{} {} {}: {:?}",
                        p.name,
                        pair.label(),
                        mesh.label,
                        scene.err()
                    );
                }
            }
        }
    }

    #[test]
    fn quadratic_rotations_take_three_points_unless_a_discretisation_names_six() {
        let p = &registry()[0];
        let points = |d: Discretisation| {
            let spec = cosserat::scene::load_scene(&root().join(p.scene), &d.overrides()).unwrap();
            let shell = &spec.shells[0];
            assert_eq!(
                shell.rest.interpolation,
                cosserat::material::StrainInterpolation::ReggeStabilized
            );
            shell.quadrature_rule().n_points()
        };
        let default = Discretisation::DEFAULT;
        let six = default.on_six_points();
        assert_eq!(default.label(), "Tri6/Tri6 regge_stabilized");
        assert_eq!(six.label(), "Tri6/Tri6 regge_stabilized 6-point");
        assert_eq!(six.directory(), "tri6_tri6_regge_stabilized_q4");
        assert_eq!(points(default), 3);
        assert_eq!(points(six), 6);
    }

    #[test]
    fn the_default_mesh_is_on_the_tri6_tri3_ladder() {
        for p in registry() {
            assert!(
                (p.ladder)(Pair::Tri6Tri3).iter().any(|m| m.label == p.default_mesh),
                "{}",
                p.name
            );
        }
    }

    #[test]
    fn compare_measures_errors_relative_to_the_largest_reference_value() {
        let p = registry().into_iter().find(|p| p.name == "end_moment_rollup").unwrap();
        // Exact values at λ = 0.5 and 1, except −U at λ = 1, which is off by 0.12.
        let (u5, w5) = reference::rollup_tip(0.5, 12.0);
        let (u1, w1) = reference::rollup_tip(1.0, 12.0);
        let probes = ProbeTable {
            columns: vec!["t".into(), "tip.ux".into(), "tip.uz".into()],
            rows: vec![vec![0.0, 0.0, 0.0], vec![0.5, -u5, w5], vec![1.0, -u1 + 0.12, w1]],
        };
        let (e, table) = compare(&p, &probes, false).unwrap();
        assert_eq!(table.len(), 2);
        // −U: error 0.12 over the largest reference −U, 12.
        assert!((e.per_component[0] - 0.01).abs() < 1e-12, "{:?}", e);
        assert!(e.per_component[1] < 1e-12);
    }
}

//! The comparison models beside the Cosserat rows: the Kirchhoff–Love Bunny (`scenes/bunny_kl.toml`, h =
//! 10, 3.75 and 1.5 mm) and the volumetric Tet4 Lotus flower (`scenes/lotus_flower_tet4.toml`, Newton
//! with a sparse Cholesky factorisation; the paper used conjugate gradients), and the "Comparison of
//! models" section: for the same scene, the Hausdorff
//! distance between the final shapes relative to the bounding-box diagonal at rest, and cost ratios
//! (ms per step, Newton iterations per step, total time).
//!
//! The shapes compared are the last frames as triangle surfaces: the bunny's shells without the floor,
//! the lotus slab's mid-surface (column means of the slab nodes) against the shell layer with the same
//! bending strength b = 0.35 (the third connected piece of the three-layer Cosserat frame). The
//! Hausdorff distance is between surfaces (every frame point to the other surface's nearest triangle,
//! both ways), so different samplings of the same shape (Tri3 vertices against Tri6 nodes) give zero.

use super::check::Check;
use super::{Options, RunResult, RunSpec, quick_end, run};
use cosserat::io::ModelRecord;
use cosserat::io::VtuFrame;
use std::fmt::Write as _;

/// The Kirchhoff–Love bunny at the Cosserat bunny's settings: h = 10 mm at the scene's time step; with
/// `--large` also h = 3.75 and 1.5 mm at the paper's smaller time step; quick runs take the small bunny
/// for a few steps.
pub(super) fn bunny_kl_runs(o: &Options) -> Vec<RunSpec> {
    let (mesh, label) = if o.quick {
        ("bunny_lvl5_verts828.obj", " (lvl5 mesh)")
    } else {
        ("bunny_lvl3_verts3308.obj", "")
    };
    let path = o.mesh(mesh);
    let mut variants = vec![("h = 10 mm", 0.01, 0.01)];
    if o.large && !o.quick {
        variants.extend([("h = 3.75 mm", 0.00375, 0.001), ("h = 1.5 mm", 0.0015, 0.001)]);
    }
    variants
        .into_iter()
        .map(|(name, h, dt)| {
            let mut ov = vec![
                format!("mesh.path={}", path.display()),
                format!("material.thickness={h}"),
                format!("time.dt={dt}"),
            ];
            ov.extend(quick_end(o, 0.03));
            run(&format!("{name}{label}"), "tri3", "scenes/bunny_kl.toml", &ov)
        })
        .collect()
}

pub(super) fn bunny_kl_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    let mut lines = Vec::new();
    for res in r {
        let s = &res.summary;
        lines.push(format!(
            "- **{}** (Kirchhoff–Love, {}): {} steps ({:?}{}), {:.2} Newton iterations per step, {:.1} ms per step, {} step reductions.",
            res.spec.variant,
            match &s.model {
                ModelRecord::KirchhoffLove { law } => law.as_str(),
                _ => "?",
            },
            s.n_steps,
            s.status,
            s.reason.as_ref().map_or(String::new(), |r| format!(": {r}")),
            s.avg_newton_iterations,
            s.avg_step_ms,
            s.n_step_reductions
        ));
        if let Some(p) = &res.probes
            && let (Ok(z0), Ok(z1)) = (p.at("top.z", 0.0), p.last("top.z"))
        {
            lines.push(format!(
                "  - drop of the top (mean of the highest 5 mm at rest): {:.2} mm at t = {:.2} s.",
                1e3 * (z0 - z1),
                p.last("t").unwrap_or(f64::NAN)
            ));
        }
        if let Some(g) = s.contact.as_ref().and_then(|c| c.min_gap) {
            lines.push(format!("  - smallest contact gap reached: {:.4} mm.", 1e3 * g));
        }
        c.extend(std::mem::take(&mut lines));
        super::contact::expect_no_intersections(&mut c, res, "floor included");
    }
    c
}

/// The Tet4 lotus: n × n × 1 cells (default 32; quick 8; with `--large` also the paper's 100).
pub(super) fn lotus_tet4_runs(o: &Options) -> Vec<RunSpec> {
    let sizes: Vec<usize> = if o.quick {
        vec![8]
    } else if o.large {
        vec![32, 100]
    } else {
        vec![32]
    };
    sizes
        .into_iter()
        .map(|n| {
            let mut ov = vec![format!("mesh.nx={n}"), format!("mesh.ny={n}")];
            ov.extend(quick_end(o, 0.05));
            run(&format!("{n}x{n}x1"), "tet4", "scenes/lotus_flower_tet4.toml", &ov)
        })
        .collect()
}

pub(super) fn lotus_tet4_check(r: &[RunResult]) -> Check {
    let mut lines = vec![
        "| mesh | Tet4 | DOFs (disp. + rot.) | Newton it./step | CG it./Newton it. | ms/step | edge-midpoint z [m] | corner z [m] |".to_string(),
        "|---|---|---|---|---|---|---|---|".to_string(),
    ];
    for res in r {
        let s = &res.summary;
        let z = |name: &str| {
            res.probes
                .as_ref()
                .and_then(|p| p.last(&format!("{name}.z")).ok())
                .map_or("–".into(), |v| format!("{v:.4}"))
        };
        lines.push(format!(
            "| {} | {} | {} | {:.2} | {} | {:.1} | {} | {} |",
            res.spec.variant,
            match s.model {
                ModelRecord::MicropolarVolume { n_tetrahedra } => n_tetrahedra.to_string(),
                _ => "?".into(),
            },
            s.n_displacement_dofs + s.n_rotation_dofs,
            s.avg_newton_iterations,
            s.linear_solver
                .cg_iterations_per_newton
                .map_or("–".into(), |v| format!("{v:.0}")),
            s.avg_step_ms,
            z("b035_edge_mid"),
            z("b035_corner"),
        ));
    }
    let mut c = Check::new();
    c.extend(lines);
    c
}

/// A triangle surface: points and triangles.
type Surface = (Vec<[f64; 3]>, Vec<[usize; 3]>);

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The distance from `p` to the triangle `(a, b, c)` (closest point by Voronoi regions, Ericson 2005,
/// §5.1.5).
fn point_triangle_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let at = |s: f64, t: f64| {
        let q = [
            a[0] + s * ab[0] + t * ac[0],
            a[1] + s * ab[1] + t * ac[1],
            a[2] + s * ab[2] + t * ac[2],
        ];
        dot(sub(p, q), sub(p, q)).sqrt()
    };
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return at(0.0, 0.0);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return at(1.0, 0.0);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(d1 / (d1 - d3), 0.0);
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return at(0.0, 1.0);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(0.0, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    at(vb * denom, vc * denom)
}

/// The symmetric Hausdorff distance between two triangle surfaces, sampled at their points (brute
/// force with a bounding-box cull).
fn surface_hausdorff(x: &Surface, y: &Surface) -> f64 {
    let one_way = |from: &Surface, to: &Surface| {
        let boxes: Vec<([f64; 3], [f64; 3])> =
            to.1.iter()
                .map(|t| {
                    let mut lo = [f64::INFINITY; 3];
                    let mut hi = [f64::NEG_INFINITY; 3];
                    for &v in t {
                        for c in 0..3 {
                            lo[c] = lo[c].min(to.0[v][c]);
                            hi[c] = hi[c].max(to.0[v][c]);
                        }
                    }
                    (lo, hi)
                })
                .collect();
        from.0
            .iter()
            .map(|&p| {
                let mut best = f64::INFINITY;
                for (t, (lo, hi)) in to.1.iter().zip(&boxes) {
                    let gap: f64 = (0..3).map(|c| (lo[c] - p[c]).max(p[c] - hi[c]).max(0.0).powi(2)).sum();
                    if gap.sqrt() >= best {
                        continue;
                    }
                    best = best.min(point_triangle_distance(p, to.0[t[0]], to.0[t[1]], to.0[t[2]]));
                }
                best
            })
            .fold(0.0, f64::max)
    };
    one_way(x, y).max(one_way(y, x))
}

fn surface(frame: &VtuFrame) -> Surface {
    (frame.points.clone(), frame.triangles.clone())
}

/// The `k`-th connected piece (in order of first appearance) of a frame's triangles, reindexed.
fn piece(frame: &VtuFrame, k: usize) -> Surface {
    let n = frame.points.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for t in &frame.triangles {
        for e in 0..3 {
            let (a, b) = (find(&mut parent, t[e]), find(&mut parent, t[(e + 1) % 3]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut roots: Vec<usize> = Vec::new();
    let mut new_index = vec![usize::MAX; n];
    let mut points = Vec::new();
    for i in 0..n {
        let r = find(&mut parent, i);
        let index = roots.iter().position(|&x| x == r).unwrap_or_else(|| {
            roots.push(r);
            roots.len() - 1
        });
        if index == k {
            new_index[i] = points.len();
            points.push(frame.points[i]);
        }
    }
    let triangles = frame
        .triangles
        .iter()
        .filter(|t| new_index[t[0]] != usize::MAX)
        .map(|t| t.map(|v| new_index[v]))
        .collect();
    (points, triangles)
}

fn diagonal(res: &RunResult) -> f64 {
    let b = &res.summary.rest_bbox;
    (0..3).map(|c| (b.max[c] - b.min[c]).powi(2)).sum::<f64>().sqrt()
}

fn ratio(a: f64, b: f64) -> String {
    if b > 0.0 && a.is_finite() {
        format!("{:.2}", a / b)
    } else {
        "–".into()
    }
}

/// One comparison row: shape distance and cost ratios of `alt` against `reference`.
fn row(label: &str, reference: &RunResult, alt: &RunResult, a: &Surface, b: &Surface, per_layer: f64) -> String {
    let diag = diagonal(reference);
    let d = if a.1.is_empty() || b.1.is_empty() {
        f64::NAN
    } else {
        surface_hausdorff(a, b)
    };
    let (r, s) = (&reference.summary, &alt.summary);
    format!(
        "| {label} | {} vs {} | {} | {:.3e} | {} | {} | {} | {:.2} / {:.2} |",
        alt.spec.variant,
        reference.spec.variant,
        if d.is_finite() {
            format!("{:.2} mm", 1e3 * d)
        } else {
            "–".into()
        },
        d / diag,
        ratio(s.avg_step_ms, r.avg_step_ms * per_layer),
        ratio(s.avg_newton_iterations, r.avg_newton_iterations),
        ratio(s.wall_seconds, r.wall_seconds * per_layer),
        s.avg_step_ms,
        r.avg_step_ms * per_layer,
    )
}

/// The "Comparison of models" section from the results of all experiments (by experiment name).
pub(super) fn section(all: &[(&str, Vec<RunResult>)]) -> String {
    let find = |name: &str| all.iter().find(|(n, _)| *n == name).map(|(_, r)| r.as_slice());
    let mut md = String::new();
    let _ = writeln!(md, "\n## Comparison of models\n");
    let _ = writeln!(
        md,
        "Same scene, different models. Shape: symmetric Hausdorff distance between the final frames' surfaces, and relative to the diagonal of the rest bounding box. Costs: comparison model over Cosserat shell (ms per step, Newton iterations per step, total run time); the last column gives both ms per step (comparison / Cosserat).\n"
    );
    let _ = writeln!(
        md,
        "| scene | runs | Hausdorff | / diagonal | ms/step ratio | Newton it. ratio | total time ratio | ms/step |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    let mut any = false;
    if let (Some(cos), Some(kl)) = (find("bunny"), find("bunny_kl")) {
        for alt in kl {
            let h = alt.spec.variant.split(" (").next().unwrap_or("");
            let Some(reference) = cos.iter().find(|c| c.spec.variant.split(" (").next() == Some(h)) else {
                continue;
            };
            let (Some(fa), Some(fb)) = (&alt.frame, &reference.frame) else {
                continue;
            };
            let a = surface(&super::contact::without_obstacles(fa));
            let b = surface(&super::contact::without_obstacles(fb));
            let _ = writeln!(md, "{}", row("Bunny, KL vs Cosserat", reference, alt, &a, &b, 1.0));
            any = true;
        }
    }
    if let (Some(shell), Some(tet)) = (find("lotus_flower"), find("lotus_flower_tet4")) {
        // The finest shell run: the three layers in one system, so costs are divided by three.
        if let Some(reference) = shell.last() {
            for alt in tet {
                let (Some(fa), Some(fb)) = (&alt.frame, &reference.frame) else {
                    continue;
                };
                let b = piece(fb, 2);
                let _ = writeln!(
                    md,
                    "{}",
                    row(
                        "Lotus b = 0.35, Tet4 vs shell",
                        reference,
                        alt,
                        &surface(fa),
                        &b,
                        1.0 / 3.0
                    )
                );
                any = true;
            }
        }
    }
    if !any {
        let _ = writeln!(md, "| – | no pair of runs of the same scene finished | | | | | | |");
    }
    let _ = writeln!(
        md,
        "\nThe lotus shell costs are one third of the three-layer run (the layers do not interact). The Tet4 frames are the slab's mid-surface (column means); the Cosserat lotus frame's third piece is the b = 0.35 layer. Bunny shapes include self-contact and the held base; differences at the thin rows mostly measure where the crumpling goes.\n"
    );
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_triangle_distances_in_every_voronoi_region() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let d = |p: [f64; 3]| point_triangle_distance(p, a, b, c);
        assert!((d([0.2, 0.3, 0.5]) - 0.5).abs() < 1e-15); // face
        assert!((d([-1.0, -1.0, 0.0]) - 2f64.sqrt()).abs() < 1e-15); // vertex a
        assert!((d([2.0, -1.0, 0.0]) - 2f64.sqrt()).abs() < 1e-15); // vertex b
        assert!((d([0.0, 3.0, 4.0]) - 20f64.sqrt()).abs() < 1e-15); // vertex c
        assert!((d([0.5, -2.0, 0.0]) - 2.0).abs() < 1e-15); // edge ab
        assert!((d([-3.0, 0.5, 0.0]) - 3.0).abs() < 1e-15); // edge ac
        assert!((d([1.0, 1.0, 0.0]) - 0.5f64.sqrt()).abs() < 1e-15); // edge bc
    }

    #[test]
    fn surfaces_sampled_differently_are_at_zero_distance() {
        // A unit square as 2 triangles, and as 8 triangles over its 3 × 3 grid; then lifted by 0.25.
        let coarse: Surface = (
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let mut points = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                points.push([0.5 * i as f64, 0.5 * j as f64, 0.0]);
            }
        }
        let mut triangles = Vec::new();
        for j in 0..2 {
            for i in 0..2 {
                let v = 3 * j + i;
                triangles.extend([[v, v + 1, v + 4], [v, v + 4, v + 3]]);
            }
        }
        let fine: Surface = (points, triangles);
        assert!(surface_hausdorff(&coarse, &fine) < 1e-15);
        let lifted: Surface = (fine.0.iter().map(|p| [p[0], p[1], 0.25]).collect(), fine.1.clone());
        assert!((surface_hausdorff(&coarse, &lifted) - 0.25).abs() < 1e-15);
    }
}

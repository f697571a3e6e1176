//! The experiments with contact: Bunny, Dumpling and Papyrus scroll. Runs (meshes from
//! `assets/meshes/`) and checks read from the outputs: the
//! contact statistics of `summary.json`, an exact intersection test over every written frame, and what each
//! experiment should show (the bunny's drop, the dumpling's pole rotation and folds, the scroll's rolls).

use super::check::{Check, within};
use super::{Options, RunResult, RunSpec, quick_end, run};
use crate::postprocess::{fit_circle, hausdorff, rest_positions};
use cosserat::intersections::intersections_in_frames;
use cosserat::io::{RunStatus, VtuFrame, read_pvd, read_pvd_frame};
use std::f64::consts::PI;
use std::path::Path;

/// The points of a frame that belong to shells (the `obstacle` point array is 0 there), with their
/// indices.
fn shell_points(f: &VtuFrame) -> Vec<(usize, [f64; 3])> {
    let marker = f.point_array("obstacle");
    f.points
        .iter()
        .enumerate()
        .filter(|(i, _)| marker.is_none_or(|m| m.tuple(*i)[0] == 0.0))
        .map(|(i, p)| (i, *p))
        .collect()
}

/// The frame with its obstacles removed (for pictures of the shells).
pub(super) fn without_obstacles(f: &VtuFrame) -> VtuFrame {
    let Some(marker) = f.point_array("obstacle") else {
        return f.clone();
    };
    let keep: Vec<bool> = (0..f.points.len()).map(|i| marker.tuple(i)[0] == 0.0).collect();
    let mut index = vec![usize::MAX; f.points.len()];
    let mut out = VtuFrame::new(Vec::new(), Vec::new(), f.time);
    for (i, p) in f.points.iter().enumerate().filter(|(i, _)| keep[*i]) {
        index[i] = out.points.len();
        out.points.push(*p);
    }
    out.triangles = f
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&v| keep[v]))
        .map(|t| t.map(|v| index[v]))
        .collect();
    out.point_data = f
        .point_data
        .iter()
        .filter(|a| a.name != "obstacle")
        .map(|a| {
            let n = a.n_components;
            let values = (0..f.points.len())
                .filter(|&i| keep[i])
                .flat_map(|i| a.values[n * i..n * (i + 1)].iter().copied())
                .collect();
            cosserat::io::DataArray::new(a.name.clone(), n, values)
        })
        .collect();
    out
}

/// What every contact experiment reports per run: solver effort, contact statistics, the contact
/// share of the step; and expects no intersection in any written frame.
fn contact_report(c: &mut Check, res: &RunResult) {
    c.extend(contact_lines(res));
    expect_no_intersections(c, res, "obstacles included");
}

/// Expects no intersecting pair of triangles in any frame the run wrote (exact test over all
/// triangles of each frame; `what` says which surfaces the frames hold).
pub(super) fn expect_no_intersections(c: &mut Check, res: &RunResult, what: &str) {
    c.expect(
        format!(
            "{}: no two triangles intersect in any written frame (exact test over all triangles, {what})",
            res.spec.variant
        ),
        intersections_in_frames(&res.dir).ok().filter(|f| f.frames > 0).map(|f| {
            let text = match f.worst() {
                None => format!("{} frames, none with an intersecting pair", f.frames),
                Some(w) => format!(
                    "{} of {} frames with intersecting pairs, at most {} (t = {:.4} s)",
                    f.crossing.len(),
                    f.frames,
                    w.pairs,
                    w.time
                ),
            };
            (f.crossing.is_empty(), text)
        }),
    );
}

fn contact_lines(res: &RunResult) -> Vec<String> {
    let s = &res.summary;
    let mut lines = vec![format!(
        "- **{}**: {} steps ({:?}{}), {:.2} Newton iterations per step (at most {}), {} step reductions, {:.1} ms per step.",
        res.spec.variant,
        s.n_steps,
        s.status,
        s.reason.as_ref().map_or(String::new(), |r| format!(": {r}")),
        s.avg_newton_iterations,
        s.max_newton_iterations,
        s.n_step_reductions,
        s.avg_step_ms
    )];
    let Some(c) = &s.contact else {
        lines.push("  - no contact record (the run did not start).".into());
        return lines;
    };
    let pct = |v: f64| format!("{:.0} %", 100.0 * v);
    let gap = c.min_gap.map_or("– (no pair came within reach)".into(), |g| {
        format!("{:.4} mm", 1e3 * g)
    });
    lines.push(format!(
        "  - contact: {} triangles; active pairs {:.0} on average, {} at most; smallest gap reached {gap}; share of the step {} (energies and derivatives {}, CCD {}, broad phases {}).",
        c.n_triangles,
        c.mean_active_pairs,
        c.max_active_pairs,
        pct(c.share_of_step),
        pct(c.energy_share),
        pct(c.ccd_share),
        pct(c.broad_phase_share),
    ));
    if c.max_obstacle_lag > 0.0 {
        let (lag, last) = (c.max_obstacle_lag, c.final_obstacle_lag);
        lines.push(format!(
            "  - kinematic obstacles held back at most {:.1} mm behind their scripted paths ({:.1} mm at the end).",
            1e3 * lag,
            1e3 * last
        ));
    }
    lines
}

/// Bunny runs: the paper's mesh at h = 10 mm for the full 5 s; with `--large` also the thin rows
/// (h = 3.75 and 1.5 mm at the paper's time step), each for the paper's whole duration, so that their
/// rows compare with Table 1's totals. Quick runs take the small bunny for a few steps.
pub(super) fn bunny_runs(o: &Options) -> Vec<RunSpec> {
    let (mesh, label) = if o.quick {
        ("bunny_lvl5_verts828.obj", " (lvl5 mesh)")
    } else {
        ("bunny_lvl3_verts3308.obj", "")
    };
    let path = o.mesh(mesh);
    let mut variants: Vec<(&str, f64, f64, Option<f64>)> = vec![("h = 10 mm", 0.01, 0.01, None)];
    if o.large && !o.quick {
        // The paper's rows in full: its whole duration at its time step.
        variants.extend([
            ("h = 3.75 mm", 0.00375, 0.001, None),
            ("h = 1.5 mm", 0.0015, 0.001, None),
        ]);
    }
    variants
        .into_iter()
        .map(|(name, h, dt, end)| {
            let mut ov = vec![
                format!("mesh.path={}", path.display()),
                format!("material.thickness={h}"),
                format!("material.length_scale={}", 0.5 * h),
                format!("time.dt={dt}"),
            ];
            ov.extend(quick_end(o, 0.03));
            let label = match end {
                Some(end) => {
                    ov.push(format!("time.end={end}"));
                    format!("{name}{label} (first {end} s of 5 s)")
                }
                None => format!("{name}{label}"),
            };
            run(&label, "tri6", "scenes/bunny.toml", &ov)
        })
        .collect()
}

pub(super) fn bunny_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    for res in r {
        contact_report(&mut c, res);
        let height = res.summary.rest_bbox.max[2] - res.summary.rest_bbox.min[2];
        let drop = res
            .probes
            .as_ref()
            .and_then(|p| Some((p.at("top.z", 0.0).ok()? - p.last("top.z").ok()?, p.last("t").ok()?)));
        if let Some((drop, t)) = drop {
            c.say(format!(
                "  - drop of the top (mean of the highest 5 mm at rest): {:.2} mm at t = {t:.2} s.",
                1e3 * drop
            ));
        }
        if res.spec.variant.starts_with("h = 10 mm") {
            c.expect(
                "the thick bunny keeps its shape under its own weight: its top drops by less than a tenth of its height",
                drop.and_then(|(d, _)| within(d, 0.0, 0.1 * height, format!("{:.2} mm of {:.1} mm", 1e3 * d, 1e3 * height))),
            );
        }
    }
    c.say("\nThinner bunnies sag, buckle and crumple into self-contact (`--large`).");
    c
}

/// Dumpling runs: plate and shell model.
pub(super) fn dumpling_runs(o: &Options) -> Vec<RunSpec> {
    vec![
        run("plate model", "tri6", "scenes/dumpling_plate.toml", &quick_end(o, 0.03)),
        run("shell model", "tri6", "scenes/dumpling_shell.toml", &quick_end(o, 0.03)),
    ]
}

/// Up to `n` frames of a run spread evenly over its collection, with their times.
fn sample_frames(dir: &Path, n: usize) -> Vec<VtuFrame> {
    let pvd = dir.join("frames").join("run.pvd");
    let Ok(entries) = read_pvd(&pvd) else { return Vec::new() };
    let count = entries.len();
    if count == 0 {
        return Vec::new();
    }
    let stride = count.div_ceil(n.max(1)).max(1);
    (0..count)
        .step_by(stride)
        .chain(std::iter::once(count - 1))
        .filter_map(|k| read_pvd_frame(&pvd, k).ok())
        .collect()
}

/// The index of the shell point whose rest position is nearest to `target`.
fn nearest_rest_point(f: &VtuFrame, target: [f64; 3]) -> Option<usize> {
    let rest = rest_positions(f).ok()?;
    shell_points(f).into_iter().map(|(i, _)| i).min_by(|&a, &b| {
        let d = |i: usize| (0..3).map(|c| (rest[i][c] - target[c]).powi(2)).sum::<f64>();
        d(a).total_cmp(&d(b))
    })
}

/// The pole's turn about z over a run: `(t, measured angle, target angle)` from director 1 of the
/// pole's output point, unwrapped.
fn pole_turn(frames: &[VtuFrame]) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    let mut previous: Option<f64> = None;
    for f in frames {
        let (Some(i), Some(d1)) = (nearest_rest_point(f, [0.0, 0.0, 1.0]), f.point_array("director1")) else {
            continue;
        };
        let d = d1.tuple(i);
        let mut angle = d[1].atan2(d[0]);
        if let Some(p) = previous {
            angle += 2.0 * PI * ((p - angle) / (2.0 * PI)).round();
        }
        previous = Some(angle);
        out.push((f.time, angle, 0.5 * PI * f.time.min(4.0)));
    }
    out
}

/// Waves of the distance from the sphere's centre along the 45° latitude ring (rest polar angle 45°):
/// sign changes of `|x| − mean`, sorted by azimuth, halved. The folds of the twisted dome.
fn ring_waves(f: &VtuFrame) -> Option<usize> {
    let rest = rest_positions(f).ok()?;
    let z45 = 0.5_f64.sqrt();
    let mut ring: Vec<(f64, f64)> = shell_points(f)
        .into_iter()
        .filter(|(i, _)| (rest[*i][2] - z45).abs() < 1e-6)
        .map(|(i, p)| {
            (
                rest[i][1].atan2(rest[i][0]),
                (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt(),
            )
        })
        .collect();
    if ring.len() < 8 {
        return None;
    }
    ring.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mean = ring.iter().map(|p| p.1).sum::<f64>() / ring.len() as f64;
    let amplitude = ring.iter().map(|p| (p.1 - mean).abs()).fold(0.0, f64::max);
    let signs: Vec<bool> = ring
        .iter()
        .filter(|p| (p.1 - mean).abs() > 0.05 * amplitude)
        .map(|p| p.1 > mean)
        .collect();
    let changes = (0..signs.len()).filter(|&i| signs[i] != signs[(i + 1) % signs.len()]).count();
    Some(changes / 2)
}

pub(super) fn dumpling_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    let mut lines = Vec::new();
    for res in r {
        contact_report(&mut c, res);
        let frames = sample_frames(&res.dir, 13);
        let turn = pole_turn(&frames);
        let worst = turn.iter().map(|(_, a, b)| (a - b).abs()).reduce(f64::max);
        c.expect(
            format!(
                "{}: the pole follows its target turn (90°/s up to 360° at 4 s) within 1° (a position and rotation condition)",
                res.spec.variant
            ),
            worst.and_then(|w| within(w.to_degrees(), 0.0, 1.0, format!("largest deviation {:.2}°", w.to_degrees()))),
        );
        if let Some(worst) = worst {
            let (t, a, b) = turn[turn.len() - 1];
            c.say(format!(
                "  - pole rotation about z (director 1 of the pole, {} frames): at t = {t:.2} s {:.1}° against the target {:.1}°; largest deviation {:.2}°.",
                turn.len(),
                a.to_degrees(),
                b.to_degrees(),
                worst.to_degrees()
            ));
        }
        let folds = res.frame.as_ref().and_then(ring_waves);
        c.expect(
            format!(
                "{}: the twist folds the dome: at least two waves of the radius along the 45° latitude ring in the last frame",
                res.spec.variant
            ),
            folds.map(|w| (w >= 2, format!("{w} waves"))),
        );
    }
    if let [a, b] = r
        && let (Some(fa), Some(fb)) = (&a.frame, &b.frame)
        && a.summary.status == RunStatus::Ok
        && b.summary.status == RunStatus::Ok
    {
        let pa: Vec<[f64; 3]> = shell_points(fa).into_iter().map(|x| x.1).collect();
        let pb: Vec<[f64; 3]> = shell_points(fb).into_iter().map(|x| x.1).collect();
        lines.push(format!(
            "- Hausdorff distance between the plate and the shell model's last frames: {:.1} mm.",
            1e3 * hausdorff(&pa, &pb)
        ));
    }
    c.extend(lines);
    c
}

/// Papyrus scroll run (the scene's rounded boxes).
pub(super) fn scroll_runs(o: &Options) -> Vec<RunSpec> {
    let path = o.mesh("rounded_box.obj");
    let label = "-";
    let mut ov: Vec<String> = (1..=3)
        .map(|k| format!("contact.obstacle.{k}.mesh.path={}", path.display()))
        .collect();
    ov.extend(quick_end(o, 0.05));
    vec![run(label, "tri6", "scenes/papyrus_scroll.toml", &ov)]
}

/// One roll of the scroll (`side` = −1 left, +1 right) in a frame: the number of turns of the centre
/// line (rest y = 0) from the middle to the free end, and the radius of a circle fitted to its last
/// 5 cm (in the xz plane).
fn roll(f: &VtuFrame, side: f64) -> Option<(f64, f64)> {
    let rest = rest_positions(f).ok()?;
    let mut line: Vec<(f64, [f64; 3])> = shell_points(f)
        .into_iter()
        .filter(|(i, _)| rest[*i][1].abs() < 1e-9 && rest[*i][0] * side >= -1e-9)
        .map(|(i, p)| (rest[i][0].abs(), p))
        .collect();
    if line.len() < 4 {
        return None;
    }
    line.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut turning = 0.0;
    let mut previous: Option<f64> = None;
    for w in line.windows(2) {
        let (a, b) = (w[0].1, w[1].1);
        let angle = (b[2] - a[2]).atan2((b[0] - a[0]) * side);
        if let Some(p) = previous {
            let mut d = angle - p;
            d -= 2.0 * PI * (d / (2.0 * PI)).round();
            turning += d;
        }
        previous = Some(angle);
    }
    let end: Vec<[f64; 3]> = line.iter().filter(|(x, _)| *x >= 0.2 - 1e-9).map(|(_, p)| *p).collect();
    let (_, _, radius, _) = fit_circle(&end, 0, 2).ok()?;
    Some((turning.abs() / (2.0 * PI), radius))
}

/// Turns of the rest curvature `c_x(x) = min(2000π ((0.05 + |x|)/0.5)³, 100)` from the middle to an
/// end at full strength, `∫ c_x dx / 2π` (midpoint rule).
fn rest_turns() -> f64 {
    let n = 10_000;
    let h = 0.25 / n as f64;
    (0..n)
        .map(|k| {
            let x = (k as f64 + 0.5) * h;
            (2000.0 * PI * ((0.05 + x) / 0.5).powi(3)).min(100.0) * h
        })
        .sum::<f64>()
        / (2.0 * PI)
}

pub(super) fn scroll_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    for res in r {
        contact_report(&mut c, res);
        let turns = scroll_rolls(&mut c, res);
        let middle = scroll_middle_motion(&mut c, res);
        c.say("");
        let before = turns.iter().find(|(t, _, _)| *t <= 6.0 + 1e-9).copied();
        let last = turns.iter().rfind(|(t, _, _)| *t > 6.0 + 1e-9).copied();
        c.expect(
            format!(
                "both ends roll up before the boxes come: at least two turns per side (the rest curvature holds \
                 {:.2} turns; the layers' 1 mm contact distance keeps the roll from closing that tightly) with \
                 end radii within 50 % of the 10 mm cap",
                rest_turns()
            ),
            before.map(|(_, l, r)| {
                (
                    l.0.min(r.0) >= 2.0 && [l.1, r.1].iter().all(|radius| (radius - 0.01).abs() <= 0.005),
                    format!(
                        "{:.2} / {:.2} turns, radii {:.1} / {:.1} mm",
                        l.0,
                        r.0,
                        1e3 * l.1,
                        1e3 * r.1
                    ),
                )
            }),
        );
        c.expect(
            "the sheet does not slide while it rolls (friction μ = 1 on the floor): its middle moves less than 1 mm by t = 6 s",
            middle.and_then(|d| within(d, 0.0, 1e-3, format!("{:.2} mm", 1e3 * d))),
        );
        c.expect(
            "the boxes push the rolls open after 9 s: each roll has fewer turns in the last frame than at 6 s",
            before.zip(last).map(|((_, l0, r0), (_, l1, r1))| {
                (
                    l1.0 < l0.0 && r1.0 < r0.0,
                    format!("left {:.2} → {:.2}, right {:.2} → {:.2} turns", l0.0, l1.0, r0.0, r1.0),
                )
            }),
        );
        let lag = res.summary.contact.as_ref().map(|c| c.final_obstacle_lag);
        c.expect(
            "the boxes reach their scripted end positions: at the end none is held back by more than 5 mm \
             (a box is stopped only while the sheet it presses cannot give way)",
            lag.and_then(|l| within(l, 0.0, 5e-3, format!("{:.1} mm", 1e3 * l))),
        );
    }
    c
}

/// One roll of the scroll: its turns and its end radius \[m\].
type Roll = (f64, f64);

/// The two rolls of the scroll before the boxes come (the last frame at t ≤ 6 s) and in the last
/// frame, reported: per frame its time and the (turns, end radius) of the left and the right roll.
fn scroll_rolls(c: &mut Check, res: &RunResult) -> Vec<(f64, Roll, Roll)> {
    let pvd = res.dir.join("frames").join("run.pvd");
    let rolled = read_pvd(&pvd).ok().and_then(|entries| {
        let k = entries
            .iter()
            .enumerate()
            .filter(|(_, e)| e.time <= 6.0 + 1e-9)
            .max_by(|a, b| a.1.time.total_cmp(&b.1.time))?
            .0;
        read_pvd_frame(&pvd, k).ok()
    });
    let mut turns = Vec::new();
    for (name, frame) in [
        ("before the boxes (t ≤ 6 s)", rolled.as_ref()),
        ("last frame", res.frame.as_ref()),
    ] {
        let Some(f) = frame else { continue };
        let sides: Vec<(f64, f64)> = [-1.0, 1.0].iter().filter_map(|&side| roll(f, side)).collect();
        if let [left, right] = sides[..] {
            c.say(format!(
                "  - rolls {name}, t = {:.2} s: left {:.2} turns, end radius {:.1} mm; right {:.2} turns, end radius {:.1} mm.",
                f.time,
                left.0,
                1e3 * left.1,
                right.0,
                1e3 * right.1
            ));
            turns.push((f.time, left, right));
        }
    }
    turns
}

/// How far the middle of the sheet moved in x and y by t = 6 s, reported with where the roll ends
/// are at 9 s and at the end.
fn scroll_middle_motion(c: &mut Check, res: &RunResult) -> Option<f64> {
    res.probes.as_ref().map(|p| {
        let v = |name: &str, t: f64| p.at(name, t).unwrap_or(f64::NAN);
        c.say(format!(
            "  - middle of the sheet moved ({:.2}, {:.2}) mm in x, y by t = 6 s; roll ends at x = {:.1} / {:.1} mm at t = 9 s and {:.1} / {:.1} mm at the end.",
            1e3 * v("middle.x", 6.0),
            1e3 * v("middle.y", 6.0),
            1e3 * v("left_end.x", 9.0),
            1e3 * v("right_end.x", 9.0),
            1e3 * p.last("left_end.x").unwrap_or(f64::NAN),
            1e3 * p.last("right_end.x").unwrap_or(f64::NAN)
        ));
        v("middle.x", 6.0).hypot(v("middle.y", 6.0))
    })
}

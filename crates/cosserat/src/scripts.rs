//! Scripted boundary conditions, loads and rest fields: what a scene changes before every step.
//!
//! Built once from a [`SceneSpec`]: regions become global node lists, distributions become nodal
//! weights, and each step only evaluates the scene's time functions and writes targets, forces, rest
//! fields and the end-of-step positions of kinematic contact obstacles into the potential's parts.

use crate::contact_run::contact_parts;
use crate::error::SimulationError;
use cosserat_assembly::boundary::{AngularVelocityPenalty, PositionConstraint, PositionPenalty, RotationPenalty};
use cosserat_assembly::{IncrementalPotential, ShellLayout};
use cosserat_geometry::rotation::exp_map;
use cosserat_scene::spec::{
    BoundarySpec, FieldFunction, ForceDistribution, LoadKind, LoadSpec, MotionSpec, NodeSelection, PositionEnforcement,
    RestFieldSpec, SceneSpec, TimeFunction, Timing,
};
use cosserat_solver::ScriptError;
use nalgebra::{Matrix3, Vector3};

/// Where one boundary condition's terms sit in the potential.
#[derive(Debug)]
struct BoundaryScript {
    name: String,
    motion: MotionSpec,
    timing: Timing,
    active: (f64, f64),
    /// Creation-time positions of the position-constrained nodes.
    anchors: Vec<Vector3<f64>>,
    position_penalty: Option<(usize, f64)>,
    position_constraint: Option<(usize, [bool; 3])>,
    rotation: Option<(usize, f64)>,
    angular_velocity: Option<(usize, f64, [TimeFunction; 3])>,
}

/// A load with its nodal weights.
#[derive(Debug)]
struct LoadScript {
    name: String,
    torque: bool,
    vector: Vector3<f64>,
    nodes: Vec<(usize, f64)>,
    scale: TimeFunction,
    timing: Timing,
}

/// Rest fields of one shell.
#[derive(Debug)]
struct RestFieldScript {
    shell: usize,
    points: Vec<Vector3<f64>>,
    curvature: Vec<(usize, usize, FieldFunction)>,
    frame: Option<Matrix3<f64>>,
    growth: Option<FieldFunction>,
    timing: Timing,
    time_dependent: bool,
    applied: bool,
}

/// A contact obstacle: where it is, and its scripted motion if it moves.
#[derive(Debug)]
struct ObstacleScript {
    /// Rest positions (the motion maps these).
    rest: Vec<Vector3<f64>>,
    /// Triangles (for output frames).
    triangles: Vec<[usize; 3]>,
    motion: Option<MotionSpec>,
    /// The end-of-step positions last given to the contact term.
    current: Vec<Vector3<f64>>,
}

/// The contact obstacles of a scene and the position of the contact term in the potential.
#[derive(Debug)]
struct ObstacleScripts {
    /// Index of the contact term in `PotentialParts::extra`.
    term: usize,
    obstacles: Vec<ObstacleScript>,
    /// The largest distance of an obstacle vertex from its scripted target at the end of a step \[m\].
    max_lag: f64,
    /// The same at the end of the last step \[m\].
    last_lag: f64,
}

/// The position, rest position and triangles of a contact obstacle, for output frames.
#[derive(Debug, Clone, Copy)]
pub struct ObstacleView<'a> {
    /// Current positions \[m\].
    pub positions: &'a [Vector3<f64>],
    /// Rest positions \[m\].
    pub rest: &'a [Vector3<f64>],
    /// Triangles (local vertex triples).
    pub triangles: &'a [[usize; 3]],
}

/// All scripted quantities of a scene.
#[derive(Debug)]
pub struct Scripts {
    boundaries: Vec<BoundaryScript>,
    loads: Vec<LoadScript>,
    rest_fields: Vec<RestFieldScript>,
    obstacles: Option<ObstacleScripts>,
}

fn global_disp(layouts: &[ShellLayout], sel: &NodeSelection) -> Vec<usize> {
    sel.disp_nodes
        .iter()
        .map(|&i| layouts[sel.shell].disp_nodes.start + i)
        .collect()
}

fn global_rot(layouts: &[ShellLayout], sel: &NodeSelection) -> Vec<usize> {
    sel.rot_nodes.iter().map(|&k| layouts[sel.shell].rot_nodes.start + k).collect()
}

/// Nodal weights of a line load along the boundary edges of a shell whose nodes are all selected:
/// consistent weights of the edge's Lagrange interpolation, times the edge length.
fn line_weights(
    elements: &[Vec<usize>],
    rest: &dyn Fn(usize) -> Vector3<f64>,
    selected: &[usize],
) -> Vec<(usize, f64)> {
    use std::collections::HashMap;
    // Edges as (corner a, corner b, optional mid node), keyed by sorted corners.
    let mut count: HashMap<(usize, usize), (usize, Option<usize>)> = HashMap::new();
    for el in elements {
        let corners = [el[0], el[1], el[2]];
        for k in 0..3 {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let mid = (el.len() == 6).then(|| el[3 + k]);
            let key = (a.min(b), a.max(b));
            count.entry(key).and_modify(|e| e.0 += 1).or_insert((1, mid));
        }
    }
    let is_selected = |i: usize| selected.binary_search(&i).is_ok();
    let mut weights: HashMap<usize, f64> = HashMap::new();
    for ((a, b), (n, mid)) in count {
        if n != 1 || !is_selected(a) || !is_selected(b) || mid.is_some_and(|m| !is_selected(m)) {
            continue;
        }
        let len = match mid {
            // Length of the quadratic edge by 2-point Gauss on x(s), s ∈ [0, 1].
            Some(m) => {
                let (xa, xb, xm) = (rest(a), rest(b), rest(m));
                let d = |s: f64| (xa * (4.0 * s - 3.0) + xb * (4.0 * s - 1.0) + xm * (4.0 - 8.0 * s)).norm();
                let g = 0.5 / 3f64.sqrt();
                0.5 * (d(0.5 - g) + d(0.5 + g))
            }
            None => (rest(a) - rest(b)).norm(),
        };
        match mid {
            Some(m) => {
                *weights.entry(a).or_default() += len / 6.0;
                *weights.entry(b).or_default() += len / 6.0;
                *weights.entry(m).or_default() += 2.0 * len / 3.0;
            }
            None => {
                *weights.entry(a).or_default() += len / 2.0;
                *weights.entry(b).or_default() += len / 2.0;
            }
        }
    }
    let mut w: Vec<(usize, f64)> = weights.into_iter().collect();
    w.sort_by_key(|&(i, _)| i);
    w
}

impl Scripts {
    /// Compiles the scene's boundary conditions, loads and rest fields, and adds the boundary terms to
    /// the potential.
    ///
    /// # Errors
    /// A line load whose selection contains no boundary edge.
    pub fn build(
        spec: &SceneSpec,
        layouts: &[ShellLayout],
        potential: &mut IncrementalPotential,
    ) -> Result<Self, SimulationError> {
        let mut boundaries = Vec::new();
        for bc in &spec.boundaries {
            boundaries.push(Self::boundary(bc, layouts, potential));
        }
        let mut loads = Vec::new();
        for load in &spec.loads {
            loads.push(Self::load(load, layouts)?);
        }
        // One script per shell: entries of several rest-field tables on the same shell add up.
        let mut rest_fields: Vec<RestFieldScript> = Vec::new();
        for r in &spec.rest_fields {
            let new = Self::rest_field(r, layouts);
            match rest_fields.iter_mut().find(|s| s.shell == r.shell) {
                None => rest_fields.push(new),
                Some(existing) => {
                    if existing.frame != new.frame
                        || existing.timing != new.timing
                        || (existing.growth.is_some() && new.growth.is_some())
                    {
                        return Err(SimulationError::Setup(format!(
                            "shell {}: several rest fields with different frames, timings or growth; merge them into one",
                            r.shell
                        )));
                    }
                    existing.curvature.extend(new.curvature);
                    existing.growth = existing.growth.take().or(new.growth);
                    existing.time_dependent |= new.time_dependent;
                }
            }
        }
        let obstacles = spec.contact.as_ref().and_then(|c| {
            let term = (0..potential.parts.extra.len()).find(|&k| contact_parts(potential, k).is_some())?;
            Some(ObstacleScripts {
                term,
                obstacles: c
                    .obstacles
                    .iter()
                    .map(|o| ObstacleScript {
                        rest: o.positions.clone(),
                        triangles: o.triangles.clone(),
                        motion: o.motion.clone(),
                        current: o.positions_at(0.0),
                    })
                    .collect(),
                max_lag: 0.0,
                last_lag: 0.0,
            })
        });
        Ok(Self {
            boundaries,
            loads,
            rest_fields,
            obstacles,
        })
    }

    /// The contact obstacles where they are now (positions last given to the contact term), for
    /// output frames; empty without contact.
    pub fn obstacles(&self) -> Vec<ObstacleView<'_>> {
        self.obstacles.as_ref().map_or_else(Vec::new, |o| {
            o.obstacles
                .iter()
                .map(|s| ObstacleView {
                    positions: &s.current,
                    rest: &s.rest,
                    triangles: &s.triangles,
                })
                .collect()
        })
    }

    /// The largest distance between a kinematic obstacle's vertex and its scripted target at the end of
    /// a step so far \[m\]: positive when an obstacle was held back so as not to cross a shell at the
    /// start of a step (it then catches up over the following steps).
    pub fn max_obstacle_lag(&self) -> f64 {
        self.obstacles.as_ref().map_or(0.0, |o| o.max_lag)
    }

    /// The largest distance between a kinematic obstacle's vertex and its scripted target at the end of
    /// the last step \[m\].
    pub fn last_obstacle_lag(&self) -> f64 {
        self.obstacles.as_ref().map_or(0.0, |o| o.last_lag)
    }

    /// Moves the kinematic obstacles to their targets at `t_end`, as far as the shells at the start of
    /// the step allow: if the full motion would bring an obstacle closer to a shell than CCD's minimum
    /// gap, all kinematic obstacles go the safe fraction of the way.
    fn move_obstacles(&mut self, potential: &mut IncrementalPotential, t_end: f64) {
        let Some(scripts) = &mut self.obstacles else { return };
        if scripts.obstacles.iter().all(|o| o.motion.is_none()) {
            return;
        }
        let Some((term, state, _)) = contact_parts(potential, scripts.term) else {
            return;
        };
        let mut targets: Vec<Option<Vec<Vector3<f64>>>> = Vec::with_capacity(scripts.obstacles.len());
        for (k, o) in scripts.obstacles.iter().enumerate() {
            let target = o.motion.as_ref().map(|m| {
                let map = m.map_at(t_end);
                o.rest.iter().map(map).collect::<Vec<_>>()
            });
            if let Some(target) = &target
                && let Err(e) = term.set_obstacle_positions(k, target.clone())
            {
                log::warn!("obstacle {k}: its scripted position at t = {t_end} is unusable ({e}); it stays");
                targets.push(None);
                continue;
            }
            targets.push(target);
        }
        let alpha = term.obstacle_motion_fraction(state);
        scripts.last_lag = 0.0;
        for (k, (o, target)) in scripts.obstacles.iter_mut().zip(&targets).enumerate() {
            let Some(target) = target else { continue };
            let start = term.obstacle_positions(k).to_vec();
            let end: Vec<Vector3<f64>> = if alpha < 1.0 {
                start.iter().zip(target).map(|(a, b)| a + (b - a) * alpha).collect()
            } else {
                target.clone()
            };
            let lag = end.iter().zip(target).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
            scripts.max_lag = scripts.max_lag.max(lag);
            scripts.last_lag = scripts.last_lag.max(lag);
            if term.set_obstacle_positions(k, end.clone()).is_ok() {
                o.current = end;
            }
        }
    }

    fn boundary(bc: &BoundarySpec, layouts: &[ShellLayout], potential: &mut IncrementalPotential) -> BoundaryScript {
        let parts = &mut potential.parts;
        let disp = global_disp(layouts, &bc.selection);
        let rot = global_rot(layouts, &bc.selection);
        let anchors: Vec<Vector3<f64>> = disp.iter().map(|&i| parts.state.x[i]).collect();
        let mut script = BoundaryScript {
            name: bc.name.clone(),
            motion: bc.motion.clone(),
            timing: bc.timing,
            active: bc.active,
            anchors: anchors.clone(),
            position_penalty: None,
            position_constraint: None,
            rotation: None,
            angular_velocity: None,
        };
        match bc.position {
            Some((PositionEnforcement::Penalty(k), axes)) => {
                parts.position_penalties.push(PositionPenalty {
                    label: bc.name.clone(),
                    nodes: disp.clone(),
                    targets: anchors.clone(),
                    active: axes,
                    stiffness: k,
                });
                script.position_penalty = Some((parts.position_penalties.len() - 1, k));
            }
            Some((PositionEnforcement::Exact, axes)) => {
                parts.position_constraints.push(PositionConstraint {
                    label: bc.name.clone(),
                    nodes: disp.clone(),
                    targets: anchors,
                    active: axes,
                });
                script.position_constraint = Some((parts.position_constraints.len() - 1, axes));
            }
            None => {}
        }
        if let Some((k, columns)) = bc.rotation {
            parts.rotation_penalties.push(RotationPenalty {
                label: bc.name.clone(),
                nodes: rot.clone(),
                targets: vec![Matrix3::identity(); rot.len()],
                columns,
                stiffness: k,
            });
            script.rotation = Some((parts.rotation_penalties.len() - 1, k));
        }
        if let Some((k, active, target)) = &bc.angular_velocity {
            parts.omega_penalties.push(AngularVelocityPenalty {
                label: bc.name.clone(),
                nodes: rot,
                target: Vector3::zeros(),
                active: *active,
                stiffness: *k,
            });
            script.angular_velocity = Some((parts.omega_penalties.len() - 1, *k, target.clone()));
        }
        script
    }

    fn load(load: &LoadSpec, layouts: &[ShellLayout]) -> Result<LoadScript, SimulationError> {
        let (torque, vector, distribution) = match &load.kind {
            LoadKind::Force { vector, distribution } => (false, *vector, *distribution),
            LoadKind::Torque { vector, distribution } => (true, *vector, *distribution),
        };
        let layout = &layouts[load.selection.shell];
        let (local, start) = if torque {
            (&load.selection.rot_nodes, layout.rot_nodes.start)
        } else {
            (&load.selection.disp_nodes, layout.disp_nodes.start)
        };
        let nodes: Vec<(usize, f64)> = match distribution {
            ForceDistribution::Equal => local.iter().map(|&i| (start + i, 1.0 / local.len() as f64)).collect(),
            ForceDistribution::PerNode => local.iter().map(|&i| (start + i, 1.0)).collect(),
            ForceDistribution::PerLength | ForceDistribution::TotalOverLength => {
                let (elements, positions): (Vec<Vec<usize>>, &[Vector3<f64>]) = if torque {
                    let e = layout
                        .rot_elements
                        .iter()
                        .map(|e| e.iter().map(|&k| k - start).collect())
                        .collect();
                    (e, &layout.rest_rot_positions)
                } else {
                    let e = layout
                        .disp_elements
                        .iter()
                        .map(|e| e.iter().map(|&i| i - start).collect())
                        .collect();
                    (e, &layout.rest_disp_positions)
                };
                let mut w = line_weights(&elements, &|i| positions[i], local);
                if w.is_empty() {
                    return Err(SimulationError::Setup(format!(
                        "load `{}`: a line load needs boundary edges whose nodes are all selected; none found",
                        load.name
                    )));
                }
                if distribution == ForceDistribution::TotalOverLength {
                    let total: f64 = w.iter().map(|x| x.1).sum();
                    w.iter_mut().for_each(|x| x.1 /= total);
                }
                w.into_iter().map(|(i, wi)| (start + i, wi)).collect()
            }
        };
        Ok(LoadScript {
            name: load.name.clone(),
            torque,
            vector,
            nodes,
            scale: load.scale.clone(),
            timing: load.timing,
        })
    }

    fn rest_field(r: &RestFieldSpec, layouts: &[ShellLayout]) -> RestFieldScript {
        let time_dependent = r.curvature.iter().any(|c| c.2.is_time_dependent())
            || r.growth.as_ref().is_some_and(|g| g.is_time_dependent());
        RestFieldScript {
            shell: r.shell,
            points: layouts[r.shell].rest_point_positions.clone(),
            curvature: r.curvature.clone(),
            frame: r.curvature_frame,
            growth: r.growth.clone(),
            timing: r.timing,
            time_dependent,
            applied: false,
        }
    }

    /// Sets targets, loads, rest fields and kinematic obstacles for the step from `t` to `t + dt`.
    ///
    /// # Errors
    /// [`ScriptError`] naming the item and the expression when a scripted value is not finite at the
    /// time (or rest position) it is needed; the potential may then hold some of the new values, and the
    /// step must not be solved.
    pub fn apply(&mut self, potential: &mut IncrementalPotential, t: f64, dt: f64) -> Result<(), ScriptError> {
        self.move_obstacles(potential, t + dt);
        let at = |timing: Timing| match timing {
            Timing::StartOfStep => t,
            Timing::EndOfStep => t + dt,
        };
        let parts = &mut potential.parts;
        for bc in &self.boundaries {
            let tau = at(bc.timing);
            let on = bc.active.0 <= tau && tau < bc.active.1;
            let value = |what: &str, f: &TimeFunction| {
                finite(f.eval(tau), tau, || format!("boundary `{}`: {what}", bc.name), f)
            };
            let (rotation, center) = match &bc.motion.rotation {
                Some((axis, center, angle)) => (exp_map(&(axis * value("rotation angle", angle)?)), *center),
                None => (Matrix3::identity(), Vector3::zeros()),
            };
            let translation = match &bc.motion.translation {
                Some(d) => Vector3::new(
                    value("translation x", &d[0])?,
                    value("translation y", &d[1])?,
                    value("translation z", &d[2])?,
                ),
                None => Vector3::zeros(),
            };
            let target = |x: &Vector3<f64>| rotation * (x - center) + center + translation;
            if let Some((idx, k)) = bc.position_penalty {
                let p = &mut parts.position_penalties[idx];
                p.stiffness = if on { k } else { 0.0 };
                p.targets.iter_mut().zip(&bc.anchors).for_each(|(t, x)| *t = target(x));
            }
            if let Some((idx, axes)) = bc.position_constraint {
                let c = &mut parts.position_constraints[idx];
                c.active = if on { axes } else { [false; 3] };
                c.targets.iter_mut().zip(&bc.anchors).for_each(|(t, x)| *t = target(x));
            }
            if let Some((idx, k)) = bc.rotation {
                let r = &mut parts.rotation_penalties[idx];
                r.stiffness = if on { k } else { 0.0 };
                r.targets.fill(rotation);
            }
            if let Some((idx, k, target)) = &bc.angular_velocity {
                let w = &mut parts.omega_penalties[*idx];
                w.stiffness = if on { *k } else { 0.0 };
                w.target = Vector3::new(
                    value("angular velocity x", &target[0])?,
                    value("angular velocity y", &target[1])?,
                    value("angular velocity z", &target[2])?,
                );
            }
        }
        if !self.loads.is_empty() {
            parts.loads.forces.fill(Vector3::zeros());
            parts.loads.torques.fill(Vector3::zeros());
            for load in &self.loads {
                let tau = at(load.timing);
                let s = finite(
                    load.scale.eval(tau),
                    tau,
                    || format!("load `{}`: scale", load.name),
                    &load.scale,
                )?;
                let out = if load.torque {
                    &mut parts.loads.torques
                } else {
                    &mut parts.loads.forces
                };
                for &(i, w) in &load.nodes {
                    out[i] += load.vector * (w * s);
                }
            }
        }
        for rf in &mut self.rest_fields {
            if rf.applied && !rf.time_dependent {
                continue;
            }
            let values = rf.values(at(rf.timing))?;
            parts.shells[rf.shell].set_rest_fields_dyn(&mut |p| values[p]);
            rf.applied = true;
        }
        Ok(())
    }
}

impl RestFieldScript {
    /// The growth factor and the rest curvature at every point at time `tau`.
    ///
    /// # Errors
    /// [`ScriptError`] naming the entry, its expression and the point where a value is not finite.
    fn values(&self, tau: f64) -> Result<Vec<RestFieldValues>, ScriptError> {
        let check = |v: f64, what: &dyn Fn() -> String, f: &FieldFunction, x: &Vector3<f64>| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(ScriptError(format!(
                    "shell {}: {} `{}` is {v} at t = {tau}, X = ({}, {}, {})",
                    self.shell,
                    what(),
                    f.description(),
                    x.x,
                    x.y,
                    x.z
                )))
            }
        };
        self.points
            .iter()
            .map(|x| {
                let g = match &self.growth {
                    Some(f) => Some((2.0 * check(f.eval(x, tau), &|| "rest-metric growth".into(), f, x)?).exp()),
                    None => None,
                };
                let c = if self.curvature.is_empty() {
                    None
                } else {
                    let mut m = Matrix3::zeros();
                    for (i, j, f) in &self.curvature {
                        m[(*i, *j)] += check(f.eval(x, tau), &|| format!("rest curvature ({i}, {j})"), f, x)?;
                    }
                    Some(self.frame.map_or(m, |q| q.transpose() * m * q))
                };
                Ok((g, c))
            })
            .collect()
    }
}

/// The growth factor `exp(2 s)` and the rest curvature of one point, as the shell term takes them.
type RestFieldValues = (Option<f64>, Option<Matrix3<f64>>);

/// `value` if it is finite; otherwise the error naming the item and the expression.
fn finite(value: f64, tau: f64, item: impl FnOnce() -> String, f: &TimeFunction) -> Result<f64, ScriptError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ScriptError(format!(
            "{} `{}` is {value} at t = {tau}",
            item(),
            f.description()
        )))
    }
}

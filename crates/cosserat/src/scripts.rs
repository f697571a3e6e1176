//! Scripted boundary conditions and loads: what a scene changes before every step.
//!
//! Built once from a [`SceneSpec`] and the model's [`ShellPlacement`]s: regions become system node
//! lists, distributions become nodal weights, and each step only evaluates the scene's time functions
//! and writes targets and forces into the potential's parts. (Rest fields belong to the model, moving
//! obstacles to contact.)
//!
//! A program driving a run (a controller between steps) replaces a boundary's scripted motion with a
//! [`RigidMotion`] of its own ([`Scripts::set_motion`]) or a load's scale with a number
//! ([`Scripts::set_load_scale`]); the items are named as in the scene.

use crate::error::SimulationError;
use crate::placement::NodeMap;
use crate::placement::ShellPlacement;
use cosserat_assembly::boundary::{AngularVelocityPenalty, PositionConstraint, PositionPenalty, RotationPenalty};
use cosserat_assembly::pressure::{FollowerPressure, normal_weights, profiled_area_weights};
use cosserat_assembly::{IncrementalPotential, TermHandle};
use cosserat_geometry::Num;
use cosserat_geometry::rotation::exp_map;
use cosserat_scene::spec::{
    BoundarySpec, FieldFunction, ForceDistribution, LoadKind, LoadSpec, MotionSpec, PositionEnforcement, SceneSpec,
    TimeFunction, Timing,
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
    /// The motion set by the program, in place of `motion`.
    motion_override: Option<RigidMotion>,
}

/// A rigid motion of a boundary's nodes from their positions when the scene was built: the target of
/// a node at `X` is `rotation · (X − center) + center + translation`, and the target of its rotation
/// is `rotation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    /// The rotation (orthonormal, determinant 1).
    pub rotation: Matrix3<f64>,
    /// The point the rotation turns about \[m\].
    pub center: Vector3<f64>,
    /// The translation after the rotation \[m\].
    pub translation: Vector3<f64>,
}

impl RigidMotion {
    /// A rotation by `angle` \[rad\] about `axis` (normalised here) through `center`.
    ///
    /// # Errors
    /// [`ScriptTargetError::InvalidValue`] for a zero or non-finite axis, or a non-finite angle or
    /// centre.
    pub fn about_axis(axis: Vector3<f64>, angle: f64, center: Vector3<f64>) -> Result<Self, ScriptTargetError> {
        let norm = axis.norm();
        if !(norm > 0.0 && norm.is_finite() && angle.is_finite() && center.iter().all(|c| c.is_finite())) {
            return Err(ScriptTargetError::InvalidValue(format!(
                "a rotation needs a finite non-zero axis, a finite angle and centre (got axis {:?}, angle {angle}, \
                 centre {:?})",
                axis.as_slice(),
                center.as_slice()
            )));
        }
        Ok(Self {
            rotation: exp_map(&(axis * (angle / norm))),
            center,
            translation: Vector3::zeros(),
        })
    }

    /// Checks that the entries are finite and the rotation is one (orthonormal, determinant 1).
    ///
    /// # Errors
    /// [`ScriptTargetError::InvalidValue`] saying what is wrong.
    pub fn check(&self) -> Result<(), ScriptTargetError> {
        let r = &self.rotation;
        let finite = r.iter().chain(&self.center).chain(&self.translation).all(|v| v.is_finite());
        // Round-off of a rotation built in double precision stays far below this.
        let orthonormal = (r.transpose() * r - Matrix3::identity()).norm() < 1e-9 && r.determinant() > 0.0;
        if finite && orthonormal {
            Ok(())
        } else {
            Err(ScriptTargetError::InvalidValue(format!(
                "a motion needs finite values and a rotation matrix (orthonormal, determinant 1); got \
                 rotation {:?}, centre {:?}, translation {:?}",
                r.as_slice(),
                self.center.as_slice(),
                self.translation.as_slice()
            )))
        }
    }

    fn target(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * (x - self.center) + self.center + self.translation
    }
}

/// A script target that cannot be set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScriptTargetError {
    /// No boundary condition has this name.
    #[error("no boundary named `{name}` (the scene has: {known})")]
    UnknownBoundary {
        /// The name asked for.
        name: String,
        /// The scene's boundary names, comma-separated.
        known: String,
    },
    /// No load has this name.
    #[error("no load named `{name}` (the scene has: {known})")]
    UnknownLoad {
        /// The name asked for.
        name: String,
        /// The scene's load names, comma-separated.
        known: String,
    },
    /// A value is not finite or not a rigid motion.
    #[error("{0}")]
    InvalidValue(String),
}

/// A load with its nodal forces (or torques) at scale 1, or its follower-pressure term.
#[derive(Debug)]
struct LoadScript {
    name: String,
    torque: bool,
    nodes: Vec<(usize, Vector3<f64>)>,
    follower: Option<(FollowerHandle, f64)>,
    scale: TimeFunction,
    timing: Timing,
    /// The scale set by the program, in place of `scale`.
    scale_override: Option<f64>,
}

/// The follower-pressure term of a load, by element type.
#[derive(Debug, Clone, Copy)]
enum FollowerHandle {
    Tri3(TermHandle<FollowerPressure<3>>),
    Tri6(TermHandle<FollowerPressure<6>>),
}

impl FollowerHandle {
    /// Inserts a follower pressure on `elements` (system nodes, all of one type).
    fn insert(potential: &mut IncrementalPotential, label: &str, elements: &[Vec<usize>]) -> Self {
        fn fixed<const N: usize>(elements: &[Vec<usize>]) -> Vec<[usize; N]> {
            elements.iter().map(|e| std::array::from_fn(|a| e[a])).collect()
        }
        if elements.first().is_some_and(|e| e.len() == 6) {
            Self::Tri6(potential.insert(FollowerPressure::new(label, fixed::<6>(elements))))
        } else {
            Self::Tri3(potential.insert(FollowerPressure::new(label, fixed::<3>(elements))))
        }
    }

    fn set(self, potential: &mut IncrementalPotential, pressure: f64) {
        match self {
            Self::Tri3(h) => potential.term_mut(h).pressure = pressure,
            Self::Tri6(h) => potential.term_mut(h).pressure = pressure,
        }
    }
}

/// The warning for a follower pressure whose surface has boundary edges with nodes that no exact
/// position condition holds on all axes: the load is not conservative there (docs/scenes.md).
fn free_edge_warning(name: &str, potential: &IncrementalPotential, handle: FollowerHandle) -> Option<String> {
    let elements: Vec<Vec<usize>> = match handle {
        FollowerHandle::Tri3(h) => potential.term(h).elements.iter().map(|e| e.to_vec()).collect(),
        FollowerHandle::Tri6(h) => potential.term(h).elements.iter().map(|e| e.to_vec()).collect(),
    };
    let mut count: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
    for el in &elements {
        for k in 0..3 {
            let (a, b) = (el[k], el[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let held = |i: usize| {
        potential
            .parts
            .position_constraints
            .iter()
            .any(|c| c.active == [true; 3] && c.nodes.contains(&i))
    };
    let mut free: Vec<usize> = count
        .iter()
        .filter(|(_, n)| **n == 1)
        .flat_map(|((a, b), _)| [*a, *b])
        .filter(|&i| !held(i))
        .collect();
    free.sort_unstable();
    free.dedup();
    (!free.is_empty()).then(|| {
        format!(
            "load `{name}`: the follower pressure's surface has free edges ({} boundary nodes not held exactly); \
             a follower load is not conservative there and Newton may not converge: use `follower = false` or \
             hold the rim (docs/scenes.md)",
            free.len()
        )
    })
}

/// The weights of the selected nodes `local` in a load of this distribution: equal shares, one per
/// node, or by the boundary length or element area each carries (`elements` and rest `positions`
/// by local index; the totals are normalised by the caller). A profile multiplies the intensity: at
/// the quadrature points of an area load, at the nodes otherwise.
fn distribution_weights(
    distribution: ForceDistribution,
    profile: Option<&FieldFunction>,
    local: &[usize],
    elements: &[Vec<usize>],
    positions: &[Vector3<f64>],
) -> Vec<(usize, f64)> {
    let f = |x: &Vector3<f64>| profile.map_or(1.0, |p| p.eval(x, 0.0));
    let nodal = match distribution {
        ForceDistribution::Equal => local.iter().map(|&i| (i, 1.0 / local.len() as f64)).collect(),
        ForceDistribution::PerNode => local.iter().map(|&i| (i, 1.0)).collect(),
        ForceDistribution::PerLength | ForceDistribution::TotalOverLength => {
            line_weights(elements, &|i| positions[i], local)
        }
        ForceDistribution::PerArea | ForceDistribution::TotalOverArea => {
            return profiled_area_weights(&covered_elements(elements, local), &|i| positions[i], &f);
        }
    };
    match profile {
        None => nodal,
        Some(_) => nodal.into_iter().map(|(i, w)| (i, w * f(&positions[i]))).collect(),
    }
}

/// The elements whose nodes are all selected.
fn covered_elements(elements: &[Vec<usize>], selected: &[usize]) -> Vec<Vec<usize>> {
    let has = |i: &usize| selected.binary_search(i).is_ok();
    elements.iter().filter(|e| e.iter().all(has)).cloned().collect()
}

/// The scripted boundary conditions and loads of a scene.
#[derive(Debug)]
pub struct Scripts {
    boundaries: Vec<BoundaryScript>,
    loads: Vec<LoadScript>,
    warnings: Vec<String>,
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
    /// Compiles the scene's boundary conditions and loads, and adds the boundary terms to the
    /// potential.
    ///
    /// # Errors
    /// A line load whose selection contains no boundary edge.
    pub fn build(
        spec: &SceneSpec,
        placements: &[ShellPlacement],
        potential: &mut IncrementalPotential,
    ) -> Result<Self, SimulationError> {
        let boundaries = spec
            .boundaries
            .iter()
            .map(|bc| Self::boundary(bc, &placements[bc.selection.shell], potential))
            .collect();
        let loads: Vec<LoadScript> = spec
            .loads
            .iter()
            .map(|load| Self::load(load, &placements[load.selection.shell], potential))
            .collect::<Result<_, _>>()?;
        let warnings = loads
            .iter()
            .filter(|l| l.follower.is_some())
            .filter_map(|l| free_edge_warning(&l.name, potential, l.follower.map(|f| f.0)?))
            .collect();
        Ok(Self {
            boundaries,
            loads,
            warnings,
        })
    }

    /// Warnings about the scene's loads (a follower pressure on free edges).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    fn boundary(bc: &BoundarySpec, placement: &ShellPlacement, potential: &mut IncrementalPotential) -> BoundaryScript {
        let parts = &mut potential.parts;
        let disp = placement.disp.nodes(&bc.selection.disp_nodes);
        let rot = placement.rot.nodes(&bc.selection.rot_nodes);
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
            motion_override: None,
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

    fn load(
        load: &LoadSpec,
        placement: &ShellPlacement,
        potential: &mut IncrementalPotential,
    ) -> Result<LoadScript, SimulationError> {
        let mut script = LoadScript {
            name: load.name.clone(),
            torque: false,
            nodes: Vec::new(),
            follower: None,
            scale: load.scale.clone(),
            timing: load.timing,
            scale_override: None,
        };
        let (vector, distribution) = match &load.kind {
            LoadKind::Force { vector, distribution } => (*vector, *distribution),
            LoadKind::Torque { vector, distribution } => {
                script.torque = true;
                (*vector, *distribution)
            }
            LoadKind::Pressure { value, follower } => {
                Self::pressure(&mut script, load, (*value, *follower), placement, potential)?;
                return Ok(script);
            }
        };
        let (local, map, elements, positions) = if script.torque {
            (
                &load.selection.rot_nodes,
                &placement.rot,
                &placement.rot_elements,
                &placement.rest_rot,
            )
        } else {
            (
                &load.selection.disp_nodes,
                &placement.disp,
                &placement.disp_elements,
                &placement.rest_disp,
            )
        };
        let mut weights = distribution_weights(distribution, load.profile.as_ref(), local, elements, positions);
        if weights.is_empty() {
            return Err(SimulationError::Setup(format!(
                "load `{}`: the region covers no boundary edge or element to spread the load over",
                load.name
            )));
        }
        if matches!(
            distribution,
            ForceDistribution::TotalOverLength | ForceDistribution::TotalOverArea
        ) {
            let total: f64 = weights.iter().map(|x| x.1).sum();
            weights.iter_mut().for_each(|x| x.1 /= total);
        }
        script.nodes = map.weights(&weights).into_iter().map(|(i, w)| (i, vector * w)).collect();
        Ok(script)
    }

    /// A pressure `(value, follower)` on the elements the selection covers: a follower term in the
    /// potential, or fixed nodal forces along the rest normals.
    fn pressure(
        script: &mut LoadScript,
        load: &LoadSpec,
        (value, follower): (f64, bool),
        placement: &ShellPlacement,
        potential: &mut IncrementalPotential,
    ) -> Result<(), SimulationError> {
        let NodeMap::Offset(start) = placement.disp else {
            return Err(SimulationError::Setup(format!(
                "load `{}`: a pressure needs a shell model (one node per mid-surface node)",
                load.name
            )));
        };
        let elements = covered_elements(&placement.disp_elements, &load.selection.disp_nodes);
        if follower {
            let system: Vec<Vec<usize>> = elements.iter().map(|e| e.iter().map(|&i| start + i).collect()).collect();
            script.follower = Some((FollowerHandle::insert(potential, &load.name, &system), value));
        } else {
            let rest = &placement.rest_disp;
            script.nodes = normal_weights(&elements, &|i| rest[i])
                .into_iter()
                .map(|(i, n)| (start + i, n * value))
                .collect();
        }
        Ok(())
    }

    /// The names of the scene's boundary conditions, in scene order.
    pub fn boundary_names(&self) -> impl Iterator<Item = &str> {
        self.boundaries.iter().map(|b| b.name.as_str())
    }

    /// The names of the scene's loads, in scene order.
    pub fn load_names(&self) -> impl Iterator<Item = &str> {
        self.loads.iter().map(|l| l.name.as_str())
    }

    /// Prescribes `motion` for the boundary `name` from the next step on, in place of the scene's
    /// motion (`None`: back to the scene's). The boundary's stiffnesses, axes, timing and activity
    /// window stay as the scene sets them.
    ///
    /// # Errors
    /// [`ScriptTargetError::UnknownBoundary`]; [`ScriptTargetError::InvalidValue`] for a motion with
    /// non-finite entries or a rotation that is not orthonormal with determinant 1.
    pub fn set_motion(&mut self, name: &str, motion: Option<RigidMotion>) -> Result<(), ScriptTargetError> {
        if let Some(m) = &motion {
            m.check()?;
        }
        let known = || self.boundary_names().collect::<Vec<_>>().join(", ");
        match self.boundaries.iter().position(|b| b.name == name) {
            Some(idx) => {
                self.boundaries[idx].motion_override = motion;
                Ok(())
            }
            None => Err(ScriptTargetError::UnknownBoundary {
                name: name.into(),
                known: known(),
            }),
        }
    }

    /// Sets the scale of the load `name` from the next step on, in place of the scene's scale function
    /// (`None`: back to the scene's).
    ///
    /// # Errors
    /// [`ScriptTargetError::UnknownLoad`]; [`ScriptTargetError::InvalidValue`] for a scale that is not
    /// finite.
    pub fn set_load_scale(&mut self, name: &str, scale: Option<f64>) -> Result<(), ScriptTargetError> {
        if let Some(s) = scale.filter(|s| !s.is_finite()) {
            return Err(ScriptTargetError::InvalidValue(format!(
                "load `{name}`: the scale must be finite (got {s})"
            )));
        }
        let known = || self.load_names().collect::<Vec<_>>().join(", ");
        match self.loads.iter().position(|l| l.name == name) {
            Some(idx) => {
                self.loads[idx].scale_override = scale;
                Ok(())
            }
            None => Err(ScriptTargetError::UnknownLoad {
                name: name.into(),
                known: known(),
            }),
        }
    }

    /// Sets targets and loads for the step from `t` to `t + dt`.
    ///
    /// # Errors
    /// [`ScriptError`] naming the item and the expression when a scripted value is not finite at the
    /// time it is needed; the potential may then hold some of the new values, and the step must not be
    /// solved.
    pub fn apply(&mut self, potential: &mut IncrementalPotential, t: f64, dt: f64) -> Result<(), ScriptError> {
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
            let motion = match bc.motion_override {
                Some(motion) => motion,
                None => scripted_motion(&bc.motion, &value)?,
            };
            let rotation = motion.rotation;
            let target = |x: &Vector3<f64>| motion.target(x);
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
            let parts = &mut potential.parts;
            parts.loads.forces.fill(Vector3::zeros());
            parts.loads.torques.fill(Vector3::zeros());
            for load in &self.loads {
                let tau = at(load.timing);
                let s = match load.scale_override {
                    Some(s) => s,
                    None => finite(
                        load.scale.eval(tau),
                        tau,
                        || format!("load `{}`: scale", load.name),
                        &load.scale,
                    )?,
                };
                if let Some((handle, pressure)) = load.follower {
                    handle.set(potential, pressure * s);
                    continue;
                }
                let parts = &mut potential.parts;
                let out = if load.torque {
                    &mut parts.loads.torques
                } else {
                    &mut parts.loads.forces
                };
                for &(i, f) in &load.nodes {
                    out[i] += f * s;
                }
            }
        }
        Ok(())
    }
}

/// The motion a boundary's time functions prescribe, with `value` evaluating them.
fn scripted_motion(
    motion: &MotionSpec,
    value: &dyn Fn(&str, &TimeFunction) -> Result<f64, ScriptError>,
) -> Result<RigidMotion, ScriptError> {
    let (rotation, center) = match &motion.rotation {
        Some((axis, center, angle)) => (exp_map(&(axis * value("rotation angle", angle)?)), *center),
        None => (Matrix3::identity(), Vector3::zeros()),
    };
    let translation = match &motion.translation {
        Some(d) => Vector3::new(
            value("translation x", &d[0])?,
            value("translation y", &d[1])?,
            value("translation z", &d[2])?,
        ),
        None => Vector3::zeros(),
    };
    Ok(RigidMotion {
        rotation,
        center,
        translation,
    })
}

/// `value` if it is finite; otherwise the error naming the item and the expression.
fn finite(value: f64, tau: f64, item: impl FnOnce() -> String, f: &TimeFunction) -> Result<f64, ScriptError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ScriptError(format!(
            "{} `{}` is {value} at t = {}",
            item(),
            f.description(),
            Num(tau)
        )))
    }
}

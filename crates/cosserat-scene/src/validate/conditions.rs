//! Checks of what acts on the shells: boundary conditions, loads, rest fields and probes, with their
//! regions resolved into node selections.

use super::Ctx;
use super::shell::ValidShell;
use crate::error::{Num, RegionError, SceneError};
use crate::region::{Region, Selected};
use crate::schema::{
    AngularVelocitySection, AxisName, BoundarySection, DistributionName, ExprValue, LoadSection, MotionSection,
    PositionSection, ProbeSection, QuantityName, ReductionName, RegionSection, RestFieldSection, RotationSection,
    ShellRef, TimingName,
};
use crate::spec::{
    BoundarySpec, FieldFunction, ForceDistribution, LoadKind, LoadSpec, MotionSpec, NodeSelection, PositionEnforcement,
    ProbeQuantity, ProbeReduction, ProbeSpec, RestFieldSpec, TimeFunction, Timing,
};
use nalgebra::Vector3;

/// Which nodes the user of a region needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Needs {
    Displacement,
    Rotation,
}

impl Ctx<'_> {
    /// The index of the shell an item acts on.
    pub(super) fn shell_index(
        &self,
        field: &str,
        shell: Option<&ShellRef>,
        shells: &[ValidShell],
    ) -> Result<usize, SceneError> {
        let names = || shells.iter().map(|s| s.spec.name.as_str()).collect::<Vec<_>>().join(", ");
        match shell {
            None if shells.len() == 1 => Ok(0),
            None => Err(self.invalid(
                &format!("{field}.shell"),
                format!("the scene has {} shells; name one of: {}", shells.len(), names()),
            )),
            Some(ShellRef::Index(i)) if *i < shells.len() => Ok(*i),
            Some(ShellRef::Index(i)) => Err(self.invalid(
                &format!("{field}.shell"),
                format!(
                    "shell index {i} does not exist: the scene has {} shell(s) ({})",
                    shells.len(),
                    names()
                ),
            )),
            Some(ShellRef::Name(name)) => shells.iter().position(|s| &s.spec.name == name).ok_or_else(|| {
                self.invalid(
                    &format!("{field}.shell"),
                    format!("no shell is named `{name}` (shells: {})", names()),
                )
            }),
        }
    }

    fn region(&self, field: &str, r: &RegionSection) -> Result<Region, SceneError> {
        let kinds = [
            ("box", r.aabb.is_some()),
            ("predicate", r.predicate.is_some()),
            ("nodes", r.nodes.is_some()),
            ("boundary_loop", r.boundary_loop.is_some()),
            ("group", r.group.is_some()),
            ("nearest", r.nearest.is_some()),
            ("all", r.all.is_some()),
        ];
        let given: Vec<&str> = kinds.iter().filter(|(_, g)| *g).map(|(k, _)| *k).collect();
        if given.len() != 1 {
            return Err(self.invalid(
                field,
                format!(
                    "give exactly one of `box`, `predicate`, `nodes`, `boundary_loop`, `group`, `nearest`, `all` (got {})",
                    if given.is_empty() {
                        "none".to_string()
                    } else {
                        given.join(", ")
                    }
                ),
            ));
        }
        if let Some(b) = &r.aabb {
            let center = self.vector(&format!("{field}.box.center"), b.center)?;
            let size = self.vector(&format!("{field}.box.size"), b.size)?;
            if size.iter().any(|s| *s < 0.0) {
                return Err(self.invalid(
                    &format!("{field}.box.size"),
                    format!("must be non-negative (got {:?})", b.size),
                ));
            }
            return Ok(Region::Box { center, size });
        }
        if let Some(text) = &r.predicate {
            let f = format!("{field}.predicate");
            return Ok(Region::Predicate(
                self.exprs.predicate(text).map_err(|e| self.expr_error(&f, e))?,
            ));
        }
        if let Some(list) = &r.nodes {
            if list.is_empty() {
                return Err(self.invalid(&format!("{field}.nodes"), "the vertex list is empty"));
            }
            return Ok(Region::Vertices(list.clone()));
        }
        if let Some(k) = r.boundary_loop {
            return Ok(Region::BoundaryLoop(k));
        }
        if let Some(name) = &r.group {
            return Ok(Region::Group(name.clone()));
        }
        if let Some(p) = r.nearest {
            return Ok(Region::Nearest(self.vector(&format!("{field}.nearest"), p)?));
        }
        match r.all {
            Some(true) => Ok(Region::All),
            _ => Err(self.invalid(&format!("{field}.all"), "only `all = true` is meaningful")),
        }
    }

    fn region_error(&self, field: &str, source: RegionError) -> SceneError {
        SceneError::Region {
            location: self.location(field),
            field: field.to_string(),
            source: Box::new(source),
        }
    }

    /// Resolves a region on a shell and checks that it selects the kinds of nodes needed.
    fn select(
        &self,
        field: &str,
        region: &Region,
        shell: &ValidShell,
        needs: &[Needs],
    ) -> Result<Selected, SceneError> {
        let selected = region.select(&shell.nodes).map_err(|e| self.region_error(field, e))?;
        for need in needs {
            let (empty, kind) = match need {
                Needs::Displacement => (selected.disp_nodes.is_empty(), "displacement"),
                Needs::Rotation => (selected.rot_nodes.is_empty(), "rotation"),
            };
            if empty {
                return Err(self.region_error(
                    field,
                    RegionError::Empty {
                        region: region.describe(),
                        kind,
                        shell: shell.spec.name.clone(),
                    },
                ));
            }
        }
        Ok(selected)
    }

    fn timing(timing: Option<TimingName>, default: Timing) -> Timing {
        match timing {
            None => default,
            Some(TimingName::StartOfStep) => Timing::StartOfStep,
            Some(TimingName::EndOfStep) => Timing::EndOfStep,
        }
    }

    fn axes(&self, field: &str, axes: Option<&[AxisName]>) -> Result<[bool; 3], SceneError> {
        match axes {
            None => Ok([true; 3]),
            Some([]) => Err(self.invalid(field, "the list is empty")),
            Some(list) => {
                let mut active = [false; 3];
                for a in list {
                    active[a.index()] = true;
                }
                Ok(active)
            }
        }
    }

    pub(super) fn unique_name(&self, field: &str, name: &str, previous: &[String]) -> Result<(), SceneError> {
        if name.trim().is_empty() {
            return Err(self.invalid(field, "must not be empty"));
        }
        if previous.iter().any(|p| p == name) {
            return Err(self.invalid(field, format!("the name `{name}` is used twice")));
        }
        Ok(())
    }

    fn time_functions(&self, field: &str, values: &[ExprValue; 3]) -> Result<[TimeFunction; 3], SceneError> {
        Ok([
            self.time_function(&format!("{field}.0"), &values[0])?,
            self.time_function(&format!("{field}.1"), &values[1])?,
            self.time_function(&format!("{field}.2"), &values[2])?,
        ])
    }

    /// A scripted rigid motion `X ↦ R(t) (X − c) + c + d(t)`.
    pub(super) fn motion(&self, mf: &str, m: &MotionSection) -> Result<MotionSpec, SceneError> {
        let rotation = match &m.rotate {
            None => None,
            Some(r) => {
                let axis = self.axis(&format!("{mf}.rotate.axis"), &r.axis)?.into_inner();
                let center = match r.center {
                    Some(c) => self.vector(&format!("{mf}.rotate.center"), c)?,
                    None => Vector3::zeros(),
                };
                let angle = self.time_function(&format!("{mf}.rotate.angle"), &r.angle)?;
                Some((axis, center, angle))
            }
        };
        let translation = match &m.translate {
            None => None,
            Some(t) => Some(self.time_functions(&format!("{mf}.translate"), t)?),
        };
        Ok(MotionSpec { rotation, translation })
    }

    /// `position = { stiffness | exact, axes }`.
    fn position_condition(
        &self,
        pf: &str,
        p: &PositionSection,
    ) -> Result<(PositionEnforcement, [bool; 3]), SceneError> {
        let enforcement = match (p.stiffness, p.exact) {
            (Some(_), Some(true)) => {
                return Err(self.invalid(&format!("{pf}.exact"), "give `stiffness` or `exact = true`, not both"));
            }
            (Some(k), _) => PositionEnforcement::Penalty(self.non_negative(&format!("{pf}.stiffness"), k)?),
            (None, Some(true)) => PositionEnforcement::Exact,
            (None, _) => return Err(self.invalid(pf, "give `stiffness = k` (a penalty) or `exact = true`")),
        };
        Ok((enforcement, self.axes(&format!("{pf}.axes"), p.axes.as_deref())?))
    }

    /// `rotation = { stiffness, directors }`: the penalty and the held directors (1-based in the file).
    fn rotation_condition(&self, rf: &str, r: &RotationSection) -> Result<(f64, [bool; 3]), SceneError> {
        let stiffness = self.non_negative(&format!("{rf}.stiffness"), r.stiffness)?;
        let directors = match &r.directors {
            None => [true; 3],
            Some(list) if list.is_empty() => return Err(self.invalid(&format!("{rf}.directors"), "the list is empty")),
            Some(list) => {
                let mut active = [false; 3];
                for &d in list {
                    if !(1..=3).contains(&d) {
                        return Err(self.invalid(
                            &format!("{rf}.directors"),
                            format!("directors are numbered 1 to 3 (got {d})"),
                        ));
                    }
                    active[d - 1] = true;
                }
                active
            }
        };
        Ok((stiffness, directors))
    }

    /// `angular_velocity = { stiffness, axes, target }`.
    fn angular_velocity_condition(
        &self,
        af: &str,
        a: &AngularVelocitySection,
    ) -> Result<(f64, [bool; 3], [TimeFunction; 3]), SceneError> {
        let stiffness = self.non_negative(&format!("{af}.stiffness"), a.stiffness)?;
        let axes = self.axes(&format!("{af}.axes"), a.axes.as_deref())?;
        let target = match &a.target {
            Some(t) => self.time_functions(&format!("{af}.target"), t)?,
            None => [
                TimeFunction::constant(0.0),
                TimeFunction::constant(0.0),
                TimeFunction::constant(0.0),
            ],
        };
        Ok((stiffness, axes, target))
    }

    pub(super) fn boundaries(
        &self,
        list: &[BoundarySection],
        shells: &[ValidShell],
    ) -> Result<Vec<BoundarySpec>, SceneError> {
        let mut out = Vec::with_capacity(list.len());
        let mut names = Vec::new();
        for (k, b) in list.iter().enumerate() {
            let f = format!("boundary.{k}");
            let name = b.name.clone().unwrap_or_else(|| format!("boundary{k}"));
            self.unique_name(&format!("{f}.name"), &name, &names)?;
            let shell = self.shell_index(&f, b.shell.as_ref(), shells)?;
            let position = match &b.position {
                None => None,
                Some(p) => Some(self.position_condition(&format!("{f}.position"), p)?),
            };
            let rotation = match &b.rotation {
                None => None,
                Some(r) => Some(self.rotation_condition(&format!("{f}.rotation"), r)?),
            };
            let angular_velocity = match &b.angular_velocity {
                None => None,
                Some(a) => Some(self.angular_velocity_condition(&format!("{f}.angular_velocity"), a)?),
            };
            if position.is_none() && rotation.is_none() && angular_velocity.is_none() {
                return Err(self.invalid(&f, "needs `position`, `rotation` or `angular_velocity`"));
            }
            let motion = match &b.motion {
                None => MotionSpec::fixed(),
                Some(m) => self.motion(&format!("{f}.motion"), m)?,
            };
            let active = match b.active {
                None => (f64::NEG_INFINITY, f64::INFINITY),
                Some([t0, t1]) => {
                    if t0.is_nan() || t1.is_nan() || t0 >= t1 {
                        return Err(self.invalid(&format!("{f}.active"), format!("needs t0 < t1 (got [{t0}, {t1}])")));
                    }
                    (t0, t1)
                }
            };
            let mut needs = Vec::new();
            if position.is_some() {
                needs.push(Needs::Displacement);
            }
            if rotation.is_some() || angular_velocity.is_some() {
                needs.push(Needs::Rotation);
            }
            let rf = format!("{f}.region");
            let region = self.region(&rf, &b.region)?;
            let selected = self.select(&rf, &region, &shells[shell], &needs)?;
            out.push(BoundarySpec {
                name: name.clone(),
                selection: NodeSelection {
                    shell,
                    disp_nodes: selected.disp_nodes,
                    rot_nodes: selected.rot_nodes,
                },
                position,
                rotation,
                angular_velocity,
                motion,
                timing: Self::timing(b.timing, Timing::EndOfStep),
                active,
            });
            names.push(name);
        }
        Ok(out)
    }

    pub(super) fn loads(&self, list: &[LoadSection], shells: &[ValidShell]) -> Result<Vec<LoadSpec>, SceneError> {
        let mut out = Vec::with_capacity(list.len());
        let mut names = Vec::new();
        for (k, l) in list.iter().enumerate() {
            let f = format!("load.{k}");
            let name = l.name.clone().unwrap_or_else(|| format!("load{k}"));
            self.unique_name(&format!("{f}.name"), &name, &names)?;
            let shell = self.shell_index(&f, l.shell.as_ref(), shells)?;
            let distribution = match l.distribution.unwrap_or(DistributionName::Equal) {
                DistributionName::Equal => ForceDistribution::Equal,
                DistributionName::PerNode => ForceDistribution::PerNode,
                DistributionName::PerLength => ForceDistribution::PerLength,
                DistributionName::TotalOverLength => ForceDistribution::TotalOverLength,
                DistributionName::PerArea => ForceDistribution::PerArea,
                DistributionName::TotalOverArea => ForceDistribution::TotalOverArea,
            };
            let (kind, needs, is_torque) = self.load_kind(&f, l, distribution)?;
            let profile = self.load_profile(&f, l, &kind, &shells[shell])?;
            let scale = match &l.scale {
                Some(s) => self.time_function(&format!("{f}.scale"), s)?,
                None => TimeFunction::constant(1.0),
            };
            let rf = format!("{f}.region");
            let region = self.region(&rf, &l.region)?;
            let selected = self.select(&rf, &region, &shells[shell], &[needs])?;
            let nodes = if is_torque {
                &selected.rot_nodes
            } else {
                &selected.disp_nodes
            };
            let on_area = distribution.is_area() || matches!(kind, LoadKind::Pressure { .. });
            if distribution.is_line() && shells[shell].nodes.count_boundary_edges(nodes, is_torque) == 0 {
                return Err(self.invalid(
                    &format!("{f}.distribution"),
                    "a line load needs a region that contains at least one boundary edge (both end nodes)",
                ));
            }
            if on_area && shells[shell].nodes.count_covered_elements(nodes, is_torque) == 0 {
                return Err(self.invalid(
                    &rf,
                    "a load over an area needs a region that contains at least one element (all its nodes)",
                ));
            }
            out.push(LoadSpec {
                name: name.clone(),
                selection: NodeSelection {
                    shell,
                    disp_nodes: selected.disp_nodes,
                    rot_nodes: selected.rot_nodes,
                },
                kind,
                profile,
                scale,
                timing: Self::timing(l.timing, Timing::StartOfStep),
            });
            names.push(name);
        }
        Ok(out)
    }

    /// The profile of a load: a time-independent function of the rest position, finite on the
    /// shell, for a force or a torque.
    fn load_profile(
        &self,
        f: &str,
        l: &LoadSection,
        kind: &LoadKind,
        shell: &ValidShell,
    ) -> Result<Option<FieldFunction>, SceneError> {
        let Some(value) = &l.profile else {
            return Ok(None);
        };
        let field = format!("{f}.profile");
        if matches!(kind, LoadKind::Pressure { .. }) {
            return Err(self.invalid(
                &field,
                "a pressure is uniform; give a `force` per area with a profile instead",
            ));
        }
        let profile = self.field_function(&field, value, &shell.sample_points)?;
        if profile.is_time_dependent() {
            return Err(self.invalid(
                &field,
                "is a function of the rest position `x, y, z` only; put the time dependence in `scale`",
            ));
        }
        Ok(Some(profile))
    }

    /// The kind of a load: a force, a torque or a pressure (exactly one), with what it needs and
    /// whether it acts on rotation nodes.
    fn load_kind(
        &self,
        f: &str,
        l: &LoadSection,
        distribution: ForceDistribution,
    ) -> Result<(LoadKind, Needs, bool), SceneError> {
        if l.follower.is_some() && l.pressure.is_none() {
            return Err(self.invalid(&format!("{f}.follower"), "only a `pressure` can follow the surface"));
        }
        match (l.force, l.torque, l.pressure) {
            (Some(v), None, None) => Ok((
                LoadKind::Force {
                    vector: self.load_vector(&format!("{f}.force"), v)?,
                    distribution,
                },
                Needs::Displacement,
                false,
            )),
            (None, Some(v), None) => Ok((
                LoadKind::Torque {
                    vector: self.load_vector(&format!("{f}.torque"), v)?,
                    distribution,
                },
                Needs::Rotation,
                true,
            )),
            (None, None, Some(p)) => {
                self.load_magnitude(&format!("{f}.pressure"), p)?;
                if l.distribution.is_some() {
                    return Err(self.invalid(
                        &format!("{f}.distribution"),
                        "a pressure is always spread over the selected elements; remove `distribution`",
                    ));
                }
                Ok((
                    LoadKind::Pressure {
                        value: p,
                        follower: l.follower.unwrap_or(true),
                    },
                    Needs::Displacement,
                    false,
                ))
            }
            (None, None, None) => Err(self.invalid(f, "needs a `force`, a `torque` or a `pressure`")),
            _ => Err(self.invalid(f, "give one of `force`, `torque` and `pressure`, not several")),
        }
    }

    /// Checks a growth field at the points and times where [`Ctx::field_function`] checked it for
    /// finite values: the rest metric `e^{2s} a₀` enters the energy squared and inverted, so `e^{±4s}`
    /// must be finite and non-zero, i.e. `|s|` below `ln(f64::MAX)/4`. A larger growth passed as a
    /// finite number and stopped the run in its first step with a non-finite energy.
    fn growth_in_range(&self, field: &str, growth: &FieldFunction, points: &[Vector3<f64>]) -> Result<(), SceneError> {
        let max = f64::MAX.ln() / 4.0;
        for t in self.field_times(growth) {
            for p in points {
                let s = growth.eval(p, t);
                if s.abs() > max {
                    return Err(self.invalid(
                        field,
                        format!(
                            "`{}` is {} at t = {}, (x, y, z) = ({}, {}, {}): the rest metric e^(2s)·a₀ enters the \
                             energy squared and inverted, so |s| must stay below ln(f64::MAX)/4 = {:.1}",
                            growth.description(),
                            Num(s),
                            Num(t),
                            Num(p.x),
                            Num(p.y),
                            Num(p.z),
                            max
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    pub(super) fn rest_fields(
        &self,
        list: &[RestFieldSection],
        shells: &[ValidShell],
    ) -> Result<Vec<RestFieldSpec>, SceneError> {
        let mut out = Vec::with_capacity(list.len());
        for (k, r) in list.iter().enumerate() {
            let f = format!("rest_field.{k}");
            let shell = self.shell_index(&f, r.shell.as_ref(), shells)?;
            let points = &shells[shell].sample_points;
            let entries = r.curvature.as_deref().unwrap_or(&[]);
            let mut curvature = Vec::with_capacity(entries.len());
            for (j, e) in entries.iter().enumerate() {
                let ef = format!("{f}.curvature.{j}");
                for (key, v) in [("row", e.row), ("col", e.col)] {
                    if !(1..=3).contains(&v) {
                        return Err(self.invalid(
                            &format!("{ef}.{key}"),
                            format!("rows and columns are numbered 1 to 3, as in the paper's Γ_ij (got {v})"),
                        ));
                    }
                }
                let (row, col) = (e.row - 1, e.col - 1);
                if curvature.iter().any(|(r0, c0, _)| (*r0, *c0) == (row, col)) {
                    return Err(self.invalid(&ef, format!("entry Γ_{}{} is given twice", e.row, e.col)));
                }
                let value = self.field_function(&format!("{ef}.value"), &e.value, points)?;
                curvature.push((row, col, value));
            }
            let curvature_frame = match &r.frame {
                None => None,
                Some(_) if curvature.is_empty() => {
                    return Err(self.invalid(&format!("{f}.frame"), "a frame rotation needs `curvature` entries"));
                }
                Some(steps) => Some(self.rotation(&format!("{f}.frame"), steps)?),
            };
            let growth = match &r.growth {
                None => None,
                Some(g) => {
                    let field = format!("{f}.growth");
                    let growth = self.field_function(&field, g, points)?;
                    self.growth_in_range(&field, &growth, points)?;
                    Some(growth)
                }
            };
            if curvature.is_empty() && growth.is_none() {
                return Err(self.invalid(&f, "needs `curvature` entries or a `growth` field"));
            }
            out.push(RestFieldSpec {
                shell,
                curvature,
                curvature_frame,
                growth,
                timing: Self::timing(r.timing, Timing::StartOfStep),
            });
        }
        self.rest_fields_combine(&out)?;
        Ok(out)
    }

    /// The rest-field tables of one shell act as one: their curvature entries add up, so they share one
    /// frame (none is the identity) where both have entries, and one timing, and one of them at most
    /// grows the shell.
    fn rest_fields_combine(&self, fields: &[RestFieldSpec]) -> Result<(), SceneError> {
        for (k, r) in fields.iter().enumerate() {
            for (j, earlier) in fields[..k].iter().enumerate().filter(|(_, e)| e.shell == r.shell) {
                let clash = if r.growth.is_some() && earlier.growth.is_some() {
                    Some(("growth", "a shell has one growth field; write both as one expression"))
                } else if r.timing != earlier.timing {
                    Some(("timing", "the tables of one shell are evaluated at one timing"))
                } else if !r.curvature.is_empty()
                    && !earlier.curvature.is_empty()
                    && r.curvature_frame != earlier.curvature_frame
                {
                    Some(("frame", "the curvature entries of one shell share one frame"))
                } else {
                    None
                };
                if let Some((key, reason)) = clash {
                    return Err(self.invalid(
                        &format!("rest_field.{k}.{key}"),
                        format!("`rest_field.{j}` acts on the same shell: {reason}"),
                    ));
                }
            }
        }
        Ok(())
    }

    pub(super) fn probes(&self, list: &[ProbeSection], shells: &[ValidShell]) -> Result<Vec<ProbeSpec>, SceneError> {
        let mut out = Vec::with_capacity(list.len());
        let mut names = Vec::new();
        for (k, p) in list.iter().enumerate() {
            let f = format!("probe.{k}");
            self.unique_name(&format!("{f}.name"), &p.name, &names)?;
            if !p.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
                return Err(self.invalid(
                    &format!("{f}.name"),
                    "probe names become CSV column prefixes: use letters, digits, `_` and `-` only",
                ));
            }
            let shell = self.shell_index(&f, p.shell.as_ref(), shells)?;
            let quantity = match p.quantity.unwrap_or(QuantityName::Displacement) {
                QuantityName::Displacement => ProbeQuantity::Displacement,
                QuantityName::Position => ProbeQuantity::Position,
                QuantityName::Velocity => ProbeQuantity::Velocity,
                QuantityName::Director => ProbeQuantity::Director,
            };
            let needs = if quantity == ProbeQuantity::Director {
                Needs::Rotation
            } else {
                Needs::Displacement
            };
            let (field, region, reduction) = match (&p.point, &p.region) {
                (Some(point), None) => {
                    let pf = format!("{f}.point");
                    let region = Region::Nearest(self.vector(&pf, *point)?);
                    if p.reduction == Some(ReductionName::Mean) {
                        return Err(self.invalid(
                            &format!("{f}.reduction"),
                            "a `point` probes one node; use a `region` to average",
                        ));
                    }
                    (pf, region, ProbeReduction::Nearest)
                }
                (None, Some(r)) => {
                    let rf = format!("{f}.region");
                    let region = self.region(&rf, r)?;
                    if p.reduction == Some(ReductionName::Nearest) {
                        return Err(self.invalid(
                            &format!("{f}.reduction"),
                            "`nearest` needs a `point`; a region is reduced by its mean",
                        ));
                    }
                    (rf, region, ProbeReduction::Mean)
                }
                (Some(_), Some(_)) => {
                    return Err(self.invalid(&format!("{f}.region"), "give `point` or `region`, not both"));
                }
                (None, None) => return Err(self.invalid(&f, "needs a `point` or a `region`")),
            };
            let selected = self.select(&field, &region, &shells[shell], &[needs])?;
            out.push(ProbeSpec {
                name: p.name.clone(),
                selection: NodeSelection {
                    shell,
                    disp_nodes: selected.disp_nodes,
                    rot_nodes: selected.rot_nodes,
                },
                quantity,
                reduction,
            });
            names.push(p.name.clone());
        }
        Ok(out)
    }
}

//! Checks that tie the scene's conditions to the shells' models: the Kirchhoff–Love model has no
//! rotations (no rotation or angular-velocity conditions, torques, director probes) and takes its rest
//! curvature from the rest mesh (no rest fields); the micropolar volume model has no line loads, no
//! growth and no contact; and a scene with either of them has exactly one shell.

use super::Ctx;
use super::shell::ValidShell;
use crate::error::SceneError;
use crate::spec::{BoundarySpec, ContactSpec, LoadKind, LoadSpec, ModelKind, ProbeQuantity, ProbeSpec, RestFieldSpec};

/// The conditions of a scene, to be checked against the models of its shells.
pub(super) struct Conditions<'a> {
    pub boundaries: &'a [BoundarySpec],
    pub loads: &'a [LoadSpec],
    pub rest_fields: &'a [RestFieldSpec],
    pub probes: &'a [ProbeSpec],
    pub contact: Option<&'a ContactSpec>,
}

impl Ctx<'_> {
    pub(super) fn check_models(&self, shells: &[ValidShell], c: &Conditions<'_>) -> Result<(), SceneError> {
        let kind = |shell: usize| shells[shell].spec.model;
        let single = shells.len() == 1;
        for (k, s) in shells.iter().enumerate() {
            if s.spec.model != ModelKind::Cosserat && !single {
                return Err(self.invalid(
                    &format!("shell.{k}.material.model"),
                    "the Kirchhoff–Love and micropolar volume models run a scene of exactly one shell",
                ));
            }
        }
        self.check_boundary_models(c.boundaries, &kind)?;
        self.check_load_models(c.loads, &kind)?;
        self.check_rest_field_models(c.rest_fields, &kind)?;
        for (k, p) in c.probes.iter().enumerate() {
            if p.quantity == ProbeQuantity::Director && matches!(kind(p.selection.shell), ModelKind::KirchhoffLove(_)) {
                return Err(self.invalid(
                    &format!("probe.{k}.quantity"),
                    "the Kirchhoff–Love model has no directors (no rotation unknowns)",
                ));
            }
        }
        if let Some(contact) = c.contact
            && contact
                .surfaces
                .iter()
                .any(|s| matches!(kind(s.shell), ModelKind::MicropolarVolume { .. }))
        {
            return Err(self.invalid("contact", "contact is not available for the micropolar volume model"));
        }
        Ok(())
    }

    /// The Kirchhoff–Love model's boundaries prescribe no rotations or angular velocities.
    fn check_boundary_models(
        &self,
        boundaries: &[BoundarySpec],
        kind: &dyn Fn(usize) -> ModelKind,
    ) -> Result<(), SceneError> {
        for (k, b) in boundaries.iter().enumerate() {
            if matches!(kind(b.selection.shell), ModelKind::KirchhoffLove(_)) {
                let rejected = [
                    ("rotation", b.rotation.is_some()),
                    ("angular_velocity", b.angular_velocity.is_some()),
                ];
                if let Some((key, _)) = rejected.iter().find(|(_, given)| *given) {
                    return Err(self.invalid(
                    &format!("boundary.{k}.{key}"),
                    "the Kirchhoff–Love model has no rotation unknowns: clamp an edge by fixing the positions of two rows of vertices",
                ));
                }
            }
        }
        Ok(())
    }

    /// The Kirchhoff–Love model carries no torques; the micropolar volume model no line, area or
    /// pressure loads.
    fn check_load_models(&self, loads: &[LoadSpec], kind: &dyn Fn(usize) -> ModelKind) -> Result<(), SceneError> {
        for (k, l) in loads.iter().enumerate() {
            let model = kind(l.selection.shell);
            match (&l.kind, model) {
                (LoadKind::Torque { .. }, ModelKind::KirchhoffLove(_)) => {
                    return Err(self.invalid(
                        &format!("load.{k}.torque"),
                        "the Kirchhoff–Love model has no rotation unknowns to carry a torque",
                    ));
                }
                (
                    LoadKind::Force { distribution, .. } | LoadKind::Torque { distribution, .. },
                    ModelKind::MicropolarVolume { .. },
                ) if distribution.is_line() || distribution.is_area() => {
                    return Err(self.invalid(
                    &format!("load.{k}.distribution"),
                    "line and area loads are not available for the micropolar volume model: use `equal` or `per_node`",
                ));
                }
                (LoadKind::Pressure { .. }, ModelKind::MicropolarVolume { .. }) => {
                    return Err(self.invalid(
                        &format!("load.{k}.pressure"),
                        "pressure is not available for the micropolar volume model (it loads a mid-surface)",
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The Kirchhoff–Love model takes no rest fields; the micropolar volume model no growth.
    fn check_rest_field_models(
        &self,
        rest_fields: &[RestFieldSpec],
        kind: &dyn Fn(usize) -> ModelKind,
    ) -> Result<(), SceneError> {
        for (k, r) in rest_fields.iter().enumerate() {
            match kind(r.shell) {
                ModelKind::KirchhoffLove(_) => {
                    // Name the key that prescribes the field (a rest field has at least one), not the table.
                    let (key, what) = match r.growth {
                        Some(_) => ("growth", "rest-metric growth"),
                        None => ("curvature", "rest curvature"),
                    };
                    return Err(self.invalid(
                        &format!("rest_field.{k}.{key}"),
                        format!(
                            "the Kirchhoff–Love model takes its rest state from the rest mesh; a prescribed {what} is \
                             not available"
                        ),
                    ));
                }
                ModelKind::MicropolarVolume { .. } if r.growth.is_some() => {
                    return Err(self.invalid(
                        &format!("rest_field.{k}.growth"),
                        "the micropolar volume model has no rest-metric growth (only rest curvature)",
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }
}

//! Checks of the `\[contact\]` section: barrier parameters, the shells that take part and their
//! thicknesses, obstacles (boxes or meshes, static or scripted) and friction coefficients between
//! named bodies.

use super::Ctx;
use super::shell::ValidShell;
use crate::error::{Num, SceneError};
use crate::schema::{ContactSection, ObstacleSection};
use crate::spec::{ContactBody, ContactSpec, ContactSurfaceSpec, FrictionSpec, ObstacleSpec, SurfaceMesh};

impl Ctx<'_> {
    pub(super) fn contact(
        &self,
        section: Option<&ContactSection>,
        shells: &[ValidShell],
    ) -> Result<Option<ContactSpec>, SceneError> {
        let Some(c) = section else { return Ok(None) };
        let stiffness = self.positive("contact.stiffness", c.stiffness)?;
        let barrier_width = self.positive("contact.barrier_width", c.barrier_width)?;
        let default_thickness = match c.thickness {
            Some(h) => Some(self.non_negative("contact.thickness", h)?),
            None => None,
        };
        let stick_velocity = self.positive("contact.stick_velocity", c.stick_velocity.unwrap_or(0.1))?;
        let min_gap_fraction = c.min_gap_fraction.unwrap_or(0.1);
        if !(min_gap_fraction > 0.0 && min_gap_fraction < 1.0) {
            return Err(self.invalid(
                "contact.min_gap_fraction",
                format!("must lie in (0, 1) (got {})", Num(min_gap_fraction)),
            ));
        }
        let surfaces = self.contact_surfaces(c, shells, default_thickness)?;
        let obstacles = self.obstacles(c, shells, default_thickness)?;
        let friction = self.friction(c, shells, &surfaces, &obstacles)?;
        Ok(Some(ContactSpec {
            stiffness,
            barrier_width,
            stick_velocity,
            project_pd: c.project_pd.unwrap_or(true),
            min_gap_fraction,
            surfaces,
            obstacles,
            friction,
        }))
    }

    /// A contact thickness given at `field`, or the section's default.
    fn contact_thickness(&self, field: &str, own: Option<f64>, default: Option<f64>) -> Result<f64, SceneError> {
        match (own, default) {
            (Some(h), _) => self.non_negative(field, h),
            (None, Some(h)) => Ok(h),
            (None, None) => Err(self.invalid(
                field,
                "no contact thickness: give `thickness` here or a default `contact.thickness`",
            )),
        }
    }

    /// The shells that take part in contact: every shell, or those of `[[contact.surface]]`.
    fn contact_surfaces(
        &self,
        c: &ContactSection,
        shells: &[ValidShell],
        default_thickness: Option<f64>,
    ) -> Result<Vec<ContactSurfaceSpec>, SceneError> {
        let Some(list) = &c.surface else {
            return (0..shells.len())
                .map(|shell| {
                    Ok(ContactSurfaceSpec {
                        shell,
                        thickness: self.contact_thickness("contact.thickness", None, default_thickness)?,
                    })
                })
                .collect();
        };
        let mut out: Vec<ContactSurfaceSpec> = Vec::with_capacity(list.len());
        for (k, s) in list.iter().enumerate() {
            let f = format!("contact.surface.{k}");
            let shell = self.shell_index(&f, s.shell.as_ref(), shells)?;
            if out.iter().any(|o| o.shell == shell) {
                return Err(self.invalid(
                    &format!("{f}.shell"),
                    format!("shell `{}` is listed twice", shells[shell].spec.name),
                ));
            }
            out.push(ContactSurfaceSpec {
                shell,
                thickness: self.contact_thickness(&format!("{f}.thickness"), s.thickness, default_thickness)?,
            });
        }
        Ok(out)
    }

    /// The obstacles, with names distinct from the shells' and from each other.
    fn obstacles(
        &self,
        c: &ContactSection,
        shells: &[ValidShell],
        default_thickness: Option<f64>,
    ) -> Result<Vec<ObstacleSpec>, SceneError> {
        let mut obstacles: Vec<ObstacleSpec> = Vec::new();
        let shell_names: Vec<String> = shells.iter().map(|s| s.spec.name.clone()).collect();
        let mut names = shell_names.clone();
        for (k, o) in c.obstacle.as_deref().unwrap_or(&[]).iter().enumerate() {
            let f = format!("contact.obstacle.{k}");
            if shell_names.contains(&o.name) {
                return Err(self.invalid(
                    &format!("{f}.name"),
                    format!("`{}` is already the name of a shell", o.name),
                ));
            }
            self.unique_name(&format!("{f}.name"), &o.name, &names)?;
            let (positions, triangles) = self.obstacle_geometry(&f, o)?;
            let motion = match &o.motion {
                None => None,
                Some(m) => Some(self.motion(&format!("{f}.motion"), m)?),
            };
            obstacles.push(ObstacleSpec {
                name: o.name.clone(),
                positions,
                triangles,
                thickness: self.contact_thickness(&format!("{f}.thickness"), o.thickness, default_thickness)?,
                motion,
            });
            names.push(o.name.clone());
        }
        Ok(obstacles)
    }

    /// Friction coefficients between named bodies (shells that take part in contact, obstacles).
    fn friction(
        &self,
        c: &ContactSection,
        shells: &[ValidShell],
        surfaces: &[ContactSurfaceSpec],
        obstacles: &[ObstacleSpec],
    ) -> Result<Vec<FrictionSpec>, SceneError> {
        let names: Vec<&str> = shells
            .iter()
            .map(|s| s.spec.name.as_str())
            .chain(obstacles.iter().map(|o| o.name.as_str()))
            .collect();
        let mut friction: Vec<FrictionSpec> = Vec::new();
        for (k, fr) in c.friction.as_deref().unwrap_or(&[]).iter().enumerate() {
            let f = format!("contact.friction.{k}");
            let mut bodies = [ContactBody::Shell(0); 2];
            for (j, name) in fr.between.iter().enumerate() {
                let field = format!("{f}.between.{j}");
                bodies[j] = if let Some(s) = shells.iter().position(|s| &s.spec.name == name) {
                    if !surfaces.iter().any(|x| x.shell == s) {
                        return Err(self.invalid(
                            &field,
                            format!("shell `{name}` does not take part in contact (see `contact.surface`)"),
                        ));
                    }
                    ContactBody::Shell(s)
                } else if let Some(o) = obstacles.iter().position(|o| &o.name == name) {
                    ContactBody::Obstacle(o)
                } else {
                    return Err(self.invalid(
                        &field,
                        format!("no shell or obstacle is named `{name}` (names: {})", names.join(", ")),
                    ));
                };
            }
            let coefficient = self.non_negative(&format!("{f}.mu"), fr.mu)?;
            let same = |a: &FrictionSpec| a.bodies == bodies || (a.bodies[0] == bodies[1] && a.bodies[1] == bodies[0]);
            if friction.iter().any(same) {
                return Err(self.invalid(
                    &format!("{f}.between"),
                    format!(
                        "friction between `{}` and `{}` is set twice",
                        fr.between[0], fr.between[1]
                    ),
                ));
            }
            friction.push(FrictionSpec { bodies, coefficient });
        }
        Ok(friction)
    }

    fn obstacle_geometry(&self, f: &str, o: &ObstacleSection) -> Result<SurfaceMesh, SceneError> {
        match (&o.aabb, &o.mesh) {
            (Some(b), None) => {
                let center = self.vector(&format!("{f}.box.center"), b.center)?;
                let size = self.vector(&format!("{f}.box.size"), b.size)?;
                if !size.iter().all(|&s| s > 0.0) {
                    return Err(self.invalid(
                        &format!("{f}.box.size"),
                        format!("every edge length must be positive (got {:?})", b.size),
                    ));
                }
                Ok(ObstacleSpec::box_mesh(center, size))
            }
            (None, Some(mesh)) => self.obstacle_mesh(&format!("{f}.mesh"), mesh),
            (Some(_), Some(_)) => Err(self.invalid(&format!("{f}.mesh"), "give `box` or `mesh`, not both")),
            (None, None) => Err(self.invalid(f, "needs a `box = { center, size }` or a `mesh = { … }`")),
        }
    }
}

//! From TOML text to a checked [`SceneSpec`]: parsing, overrides, schema, and every semantic check,
//! with errors that name the file, the line, the field and the reason.
//!
//! Entry points: [`SceneSpec::from_file`] and [`SceneSpec::from_str`]. The steps:
//! 1. parse the text into a spanned TOML document (syntax errors carry their line);
//! 2. apply `--set key=value` overrides to the document ([`crate::overrides`]);
//! 3. deserialise the [`crate::schema`] types from it (unknown keys, missing keys, wrong types, and
//!    sections written as the other kind of table, [`table_kind`]);
//! 4. check values and build the spec: time and solver ([`time`]), shells with their meshes and
//!    materials ([`shell`]), and boundary conditions, loads, rest fields and probes, whose regions are
//!    resolved against the rest nodes ([`conditions`]), and contact with its obstacles ([`contact`]);
//! 5. check the conditions against the shells' models ([`model`]: no rotations for Kirchhoff–Love).
//!
//! Locations come from field paths looked up in the document ([`source`]) rather than from
//! `toml::Spanned` fields in the schema: a path works the same for values from the file and values
//! from overrides, and through the custom number-or-string deserialisers where a span would be lost.

mod conditions;
mod contact;
mod model;
mod shell;
mod source;
mod table_kind;
mod time;

use crate::error::{ExprError, Location, Num, SceneError};
use crate::expr::ExprContext;
use crate::mesh_source::ElementBudget;
use crate::overrides::{self, Override};
use crate::schema::{AxisValue, ExprValue, RotationStep, SceneFile};
use crate::spec::{FieldFunction, SceneSpec, TimeFunction};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use serde::Deserialize;
use source::Source;
use std::path::Path;
use toml::de::DeTable;

/// The largest magnitude of a load or gravity component. The solver squares loads (in energies and
/// residual norms), and squares overflow from √f64::MAX ≈ 1.3e154; the bound leaves a margin for the
/// masses, areas and time steps that multiply them. Beyond it a run stopped in its first step with a
/// non-finite energy that named no field.
const MAX_LOAD: f64 = 1e150;

impl SceneSpec {
    /// Reads, parses and checks a scene file. Relative mesh paths are resolved against the file's
    /// directory, those set by `overrides` against the working directory; `overrides` are `key=value`
    /// strings as given to `--set`.
    ///
    /// # Errors
    /// [`SceneError::ReadScene`] if the file cannot be read; otherwise as [`SceneSpec::from_str`],
    /// with the file's path in every location.
    pub fn from_file(path: impl AsRef<Path>, overrides: &[String]) -> Result<SceneSpec, SceneError> {
        Self::from_file_within(path, overrides, &ElementBudget::default())
    }

    /// [`SceneSpec::from_file`] with a limit on the size of every mesh, checked before it is built
    /// (a caller that knows the memory at hand passes what fits into it).
    ///
    /// # Errors
    /// As [`SceneSpec::from_file`].
    pub fn from_file_within(
        path: impl AsRef<Path>,
        overrides: &[String],
        budget: &ElementBudget,
    ) -> Result<SceneSpec, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::ReadScene {
            path: path.to_path_buf(),
            source,
        })?;
        let base_dir = path.parent().unwrap_or_else(|| Path::new("."));
        let mut spec = Self::parse(&text, &path.display().to_string(), base_dir, overrides, budget)?;
        spec.source = Some(path.to_path_buf());
        Ok(spec)
    }

    /// Parses and checks scene text. `source_name` names the text in messages, `base_dir` resolves
    /// relative mesh paths.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] for invalid TOML, [`SceneError::Override`] for a malformed override,
    /// [`SceneError::Schema`] for unknown, missing or mistyped keys, and [`SceneError::Invalid`],
    /// [`SceneError::Expression`], [`SceneError::Obj`], [`SceneError::Mesh`] or
    /// [`SceneError::Region`] for values that fail their checks.
    ///
    /// # Example
    /// ```
    /// use cosserat_scene::spec::SceneSpec;
    /// use std::path::Path;
    ///
    /// let text = r#"
    ///     name = "strip"
    ///     [time]
    ///     dt = 0.01
    ///     end = 1.0
    ///     [mesh]
    ///     generator = "rectangle"
    ///     lx = 0.1
    ///     ly = 0.01
    ///     nx = 10
    ///     ny = 1
    ///     [material]
    ///     model = "plate"
    ///     thickness = 1e-3
    ///     youngs_modulus = 1e6
    ///     poisson_ratio = 0.3
    ///     density = 1000.0
    ///     length_scale = 1e-6
    ///     [[boundary]]
    ///     region = { predicate = "x <= -0.05 + 1e-9" }
    ///     position = { stiffness = 1e6 }
    /// "#;
    /// let spec = SceneSpec::from_str(text, "strip.toml", Path::new("."), &[])?;
    /// // Tri6 by default: the clamped end column has 2·ny + 1 = 3 displacement nodes.
    /// assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 3);
    ///
    /// let err = SceneSpec::from_str(text, "strip.toml", Path::new("."), &["time.dt=-1".into()]).unwrap_err();
    /// assert_eq!(err.to_string(), "override `time.dt=-1`: time.dt: must be positive (got -1)");
    /// # Ok::<(), cosserat_scene::error::SceneError>(())
    /// ```
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(
        text: &str,
        source_name: &str,
        base_dir: &Path,
        overrides: &[String],
    ) -> Result<SceneSpec, SceneError> {
        Self::parse(text, source_name, base_dir, overrides, &ElementBudget::default())
    }

    fn parse(
        text: &str,
        source_name: &str,
        base_dir: &Path,
        overrides: &[String],
        budget: &ElementBudget,
    ) -> Result<SceneSpec, SceneError> {
        let overrides: Vec<Override> = overrides.iter().map(|o| Override::parse(o)).collect::<Result<_, _>>()?;
        let document = DeTable::parse(text).map_err(|e| {
            let line = e.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            SceneError::Syntax {
                location: Location::File {
                    file: source_name.to_string(),
                    line,
                },
                message: e.message().to_string(),
            }
        })?;
        let root_span = document.span();
        let mut document = document.into_inner();
        for (k, ov) in overrides.iter().enumerate() {
            overrides::apply(&mut document, ov, Source::override_span(text.len(), k))?;
        }
        let source = Source::new(source_name, text, root_span.clone(), document.clone(), &overrides);
        let deserializer = toml::de::Deserializer::from(toml::Spanned::new(root_span, document));
        let file = SceneFile::deserialize(deserializer).map_err(|e| schema_error(&source, source_name, &e))?;
        let mut ctx = Ctx {
            source,
            base_dir,
            budget,
            exprs: ExprContext::new(),
            sample_times: Vec::new(),
        };
        ctx.scene(file)
    }
}

/// A document that does not fit the schema, at the span serde names; where a section is written as the
/// other kind of table, the error names the section and says so instead.
fn schema_error(source: &Source<'_>, source_name: &str, e: &toml::de::Error) -> SceneError {
    let Some(span) = e.span() else {
        return SceneError::Schema {
            location: Location::File {
                file: source_name.to_string(),
                line: None,
            },
            field: String::new(),
            message: e.message().to_string(),
        };
    };
    let field = source.path_of_span(&span);
    let (document, root_span) = source.document();
    match table_kind::wrong_kind_of_table(document, root_span, &field, e.message()) {
        Some((section, hint)) => SceneError::Schema {
            location: source.location(&section),
            field: section,
            message: hint,
        },
        None => SceneError::Schema {
            location: source.location_of_offset(span.start),
            field,
            message: e.message().to_string(),
        },
    }
}

/// State shared by the checks of one scene.
pub(crate) struct Ctx<'a> {
    source: Source<'a>,
    base_dir: &'a Path,
    /// The largest mesh to build.
    budget: &'a ElementBudget,
    exprs: ExprContext,
    /// Times at which scripted functions are checked for finite values.
    sample_times: Vec<f64>,
}

impl Ctx<'_> {
    fn scene(&mut self, file: SceneFile) -> Result<SceneSpec, SceneError> {
        let safe = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.');
        if file.name.is_empty() || file.name.len() > 100 || file.name.starts_with('.') || !file.name.chars().all(safe) {
            return Err(self.invalid(
                "name",
                format!(
                    "`{}` is not a usable name: the name becomes the output folder `out/<name>`, so use 1 to 100 \
                     letters, digits, `_`, `-` and `.`, not starting with `.`",
                    file.name
                ),
            ));
        }
        if let Some(functions) = &file.functions {
            for (name, f) in functions {
                let field = format!("functions.{name}");
                self.exprs
                    .define(name, &f.args, &f.body)
                    .map_err(|e| self.expr_error(&field, e))?;
            }
            self.exprs.check_functions().map_err(|e| match &e {
                ExprError::Definition { name, .. } => self.expr_error(&format!("functions.{name}"), e.clone()),
                _ => self.expr_error("functions", e.clone()),
            })?;
        }
        let time = self.time(&file.time)?;
        let solver = self.solver(file.solver.as_ref(), &time)?;
        let gravity = match file.gravity {
            Some(g) => self.load_vector("gravity", g)?,
            None => Vector3::zeros(),
        };
        let shells = self.shells(&file)?;
        let boundaries = self.boundaries(file.boundary.as_deref().unwrap_or(&[]), &shells)?;
        let loads = self.loads(file.load.as_deref().unwrap_or(&[]), &shells)?;
        let rest_fields = self.rest_fields(file.rest_field.as_deref().unwrap_or(&[]), &shells)?;
        let probes = self.probes(file.probe.as_deref().unwrap_or(&[]), &shells)?;
        let output = self.output(file.output.as_ref(), &time)?;
        let contact = self.contact(file.contact.as_ref(), &shells)?;
        self.check_models(
            &shells,
            &model::Conditions {
                boundaries: &boundaries,
                loads: &loads,
                rest_fields: &rest_fields,
                probes: &probes,
                contact: contact.as_ref(),
            },
        )?;
        let warnings = shells.iter().flat_map(|s| s.warnings.iter().cloned()).collect();
        Ok(SceneSpec {
            name: file.name,
            source: None,
            warnings,
            shells: shells.into_iter().map(|s| s.spec).collect(),
            time,
            solver,
            gravity,
            boundaries,
            loads,
            rest_fields,
            probes,
            output,
            contact,
        })
    }

    fn location(&self, field: &str) -> Location {
        self.source.location(field)
    }

    /// A file path given at `field`: relative paths in the scene file are relative to the file's
    /// folder; those given by a `--set` override are relative to the working directory, like every
    /// other path typed on the command line.
    fn resolve_path(&self, field: &str, path: &str) -> std::path::PathBuf {
        let path = Path::new(path);
        if path.is_absolute() || matches!(self.location(field), Location::Override { .. }) {
            path.to_path_buf()
        } else {
            self.base_dir.join(path)
        }
    }

    fn invalid(&self, field: &str, reason: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            location: self.location(field),
            field: field.to_string(),
            reason: reason.into(),
        }
    }

    fn expr_error(&self, field: &str, source: ExprError) -> SceneError {
        SceneError::Expression {
            location: self.location(field),
            field: field.to_string(),
            source: Box::new(source),
        }
    }

    fn positive(&self, field: &str, value: f64) -> Result<f64, SceneError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(field, format!("must be positive (got {})", Num(value))))
        }
    }

    fn non_negative(&self, field: &str, value: f64) -> Result<f64, SceneError> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(field, format!("must be finite and non-negative (got {})", Num(value))))
        }
    }

    fn vector(&self, field: &str, v: [f64; 3]) -> Result<Vector3<f64>, SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vector3::from(v))
        } else {
            Err(self.invalid(field, format!("must be finite (got {v:?})")))
        }
    }

    /// A force, torque or gravity: finite, with no component beyond [`MAX_LOAD`].
    fn load_vector(&self, field: &str, v: [f64; 3]) -> Result<Vector3<f64>, SceneError> {
        let v = self.vector(field, v)?;
        for &c in v.iter() {
            self.load_magnitude(field, c)?;
        }
        Ok(v)
    }

    /// A load value (a pressure, or a component of a load vector): finite and within [`MAX_LOAD`].
    fn load_magnitude(&self, field: &str, value: f64) -> Result<f64, SceneError> {
        if !value.is_finite() {
            return Err(self.invalid(field, format!("must be finite (got {})", Num(value))));
        }
        if value.abs() > MAX_LOAD {
            return Err(self.invalid(
                field,
                format!(
                    "{} exceeds {} in magnitude, the largest load the solver takes: it squares loads, and \
                     their squares overflow from about 1.3e154",
                    Num(value),
                    Num(MAX_LOAD)
                ),
            ));
        }
        Ok(value)
    }

    /// A unit axis.
    fn axis(&self, field: &str, axis: &AxisValue) -> Result<Unit<Vector3<f64>>, SceneError> {
        let v = match axis {
            AxisValue::Named(a) => {
                let mut v = Vector3::zeros();
                v[a.index()] = 1.0;
                v
            }
            AxisValue::Vector(v) => self.vector(field, *v)?,
        };
        Unit::try_new(v, 1e-12).ok_or_else(|| self.invalid(field, "the axis must be a non-zero vector"))
    }

    /// The product of rotation steps, the first applied first.
    fn rotation(&self, field: &str, steps: &[RotationStep]) -> Result<Matrix3<f64>, SceneError> {
        let mut r = Matrix3::identity();
        for (k, step) in steps.iter().enumerate() {
            let axis = self.axis(&format!("{field}.{k}.axis"), &step.axis)?;
            if !step.degrees.is_finite() {
                return Err(self.invalid(
                    &format!("{field}.{k}.degrees"),
                    format!("must be finite (got {})", Num(step.degrees)),
                ));
            }
            r = Rotation3::from_axis_angle(&axis, step.degrees.to_radians()).into_inner() * r;
        }
        Ok(r)
    }

    /// A function of time, checked for finite values at the sample times.
    fn time_function(&self, field: &str, value: &ExprValue) -> Result<TimeFunction, SceneError> {
        let f = match value {
            ExprValue::Number(v) => {
                if !v.is_finite() {
                    return Err(self.invalid(field, format!("must be finite (got {})", Num(*v))));
                }
                return Ok(TimeFunction::constant(*v));
            }
            ExprValue::Text(text) => self.exprs.time_function(text).map_err(|e| self.expr_error(field, e))?,
        };
        for &t in &self.sample_times {
            let v = f.eval(t);
            if !v.is_finite() {
                return Err(self.expr_error(
                    field,
                    ExprError::NonFinite {
                        expression: f.description().to_string(),
                        value: v,
                        at: format!("t = {}", Num(t)),
                    },
                ));
            }
        }
        Ok(f)
    }

    /// A field of rest position and time, checked for finite values at the given points and a subset
    /// of the sample times.
    fn field_function(
        &self,
        field: &str,
        value: &ExprValue,
        points: &[Vector3<f64>],
    ) -> Result<FieldFunction, SceneError> {
        let f = match value {
            ExprValue::Number(v) => {
                if !v.is_finite() {
                    return Err(self.invalid(field, format!("must be finite (got {})", Num(*v))));
                }
                let v = *v;
                return Ok(FieldFunction::new(Num(v).to_string(), false, move |_, _| v));
            }
            ExprValue::Text(text) => self.exprs.field_function(text).map_err(|e| self.expr_error(field, e))?,
        };
        for t in self.field_times(&f) {
            for p in points {
                let v = f.eval(p, t);
                if !v.is_finite() {
                    return Err(self.expr_error(
                        field,
                        ExprError::NonFinite {
                            expression: f.description().to_string(),
                            value: v,
                            at: format!("t = {}, (x, y, z) = ({}, {}, {})", Num(t), Num(p.x), Num(p.y), Num(p.z)),
                        },
                    ));
                }
            }
        }
        Ok(f)
    }

    /// The times at which a field is checked: a subset of the sample times if it depends on time,
    /// else 0.
    fn field_times(&self, f: &FieldFunction) -> Vec<f64> {
        if !f.is_time_dependent() {
            return vec![0.0];
        }
        let stride = self.sample_times.len().div_ceil(32).max(1);
        self.sample_times
            .iter()
            .step_by(stride)
            .chain(self.sample_times.last())
            .copied()
            .collect()
    }
}

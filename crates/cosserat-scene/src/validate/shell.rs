//! Checks of the shells: the single `\[mesh\]` + `\[material\]` form or the `[\[shell\]]` list, each mesh
//! section (generator parameters, OBJ path, shaping steps) and each material.

use super::Ctx;
use crate::error::{MeshSourceError, Num, SceneError};
use crate::mesh_source::{
    Generator, MeshRecipe, MeshSource, RigidMotion, Scaling, SphereProjection, Transform, build_mesh_within,
};
use crate::region::ShellNodes;
use crate::schema::{
    AxlName, CurvatureSourceName, CurvedTermsName, ElementName, ExprValue, GeneratorName, InitialSection, LawName,
    MaterialSection, MembraneVolumeName, MeshSection, ModelName, NormalWeightingName, RestVolumeName, SceneFile,
    StrainInterpolationName, TransformSection,
};
use crate::spec::{HyperelasticLaw, KlRestVolume, KlSettings, ModelKind, ShellSpec, SurfaceMesh};
use cosserat_assembly::{ElementPair, ShellMesh};
use cosserat_fem::mesh::procedural::AnnulusSettings;
use cosserat_fem::mesh::{CurvatureSource, NormalWeighting};
use cosserat_fem::{ElementKind, MeshError, QuadratureRule};
use cosserat_material::rest::RestOptions;
use cosserat_material::{
    AxlVariant, CurvedTerms, MaterialError, MaterialParameters, MembraneVolume, ModelOptions, ShellModel,
    StrainInterpolation,
};
use cosserat_volume::grid::PlanarGrid;
use nalgebra::{Matrix3, Vector3};

/// The most uniform refinements a scene may ask for (each multiplies the elements by 4).
const MAX_REFINE: usize = 8;

/// A checked shell with what later checks need.
pub(crate) struct ValidShell {
    /// The spec.
    pub spec: ShellSpec,
    /// The nodes as regions see them.
    pub nodes: ShellNodes,
    /// Points at which rest fields are checked: displacement nodes and element centroids.
    pub sample_points: Vec<Vector3<f64>>,
    /// What the mesh input does that is allowed but probably not meant.
    pub warnings: Vec<String>,
}

impl Ctx<'_> {
    pub(super) fn shells(&self, file: &SceneFile) -> Result<Vec<ValidShell>, SceneError> {
        let sections: Vec<(String, String, &MeshSection, &MaterialSection)> =
            match (&file.mesh, &file.material, &file.shell) {
                (Some(mesh), Some(material), None) => vec![("shell".into(), String::new(), mesh, material)],
                (None, None, Some(list)) if !list.is_empty() => list
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        let name = s.name.clone().unwrap_or_else(|| format!("shell{k}"));
                        (name, format!("shell.{k}."), &s.mesh, &s.material)
                    })
                    .collect(),
                (None, None, Some(_)) => return Err(self.invalid("shell", "the list of shells is empty")),
                (None, None, None) => {
                    return Err(self.invalid(
                        "",
                        "the scene has no shell: add `[mesh]` and `[material]`, or `[[shell]]` tables",
                    ));
                }
                (_, _, Some(_)) => {
                    let field = if file.mesh.is_some() { "mesh" } else { "material" };
                    return Err(self.invalid(
                        field,
                        "a scene has either one shell (`[mesh]` + `[material]`) or `[[shell]]` tables, not both",
                    ));
                }
                (Some(_), None, None) => return Err(self.invalid("mesh", "`[mesh]` needs a `[material]` table")),
                (None, Some(_), None) => return Err(self.invalid("material", "`[material]` needs a `[mesh]` table")),
            };
        let mut shells = Vec::with_capacity(sections.len());
        for (k, (name, prefix, mesh, material)) in sections.iter().enumerate() {
            if name.trim().is_empty() {
                return Err(self.invalid(&format!("shell.{k}.name"), "must not be empty"));
            }
            if sections[..k].iter().any(|(other, ..)| other == name) {
                return Err(self.invalid(&format!("shell.{k}.name"), format!("the name `{name}` is used twice")));
            }
            shells.push(self.shell(name, prefix, mesh, material)?);
        }
        Ok(shells)
    }

    fn shell(
        &self,
        name: &str,
        prefix: &str,
        mesh: &MeshSection,
        material: &MaterialSection,
    ) -> Result<ValidShell, SceneError> {
        let m = format!("{prefix}mesh");
        let model_kind = self.model_kind(&format!("{prefix}material"), material)?;
        let pair = self.element_pair(&m, mesh, model_kind)?;
        let recipe = self.recipe(&m, mesh, pair)?;
        let mut built = build_mesh_within(&recipe, self.budget).map_err(|e| self.mesh_source_error(&m, e))?;
        if let Some(d) = &mesh.displace {
            self.displace(&m, d, &mut built.mesh)?;
            built.initial_positions = recipe.initial.map(|motion| {
                let rest = match (&built.mesh.tri6, pair.displacement()) {
                    (Some(t6), ElementKind::Tri6) => &t6.nodes,
                    _ => &built.mesh.corners.nodes,
                };
                rest.iter().map(|x| motion.apply(x)).collect()
            });
        }
        let quadrature = self.quadrature(&m, mesh, pair)?;
        let (params, rest, damping, angular_inertia_density) =
            self.material(&format!("{prefix}material"), material, pair)?;
        if let ModelKind::MicropolarVolume { .. } = model_kind
            && let Err(reason) = PlanarGrid::detect(&built.mesh.corners.nodes)
        {
            return Err(self.invalid(
                &m,
                format!("the micropolar volume model extrudes a flat rectangular grid (e.g. `generator = \"rectangle\"`): {reason}"),
            ));
        }
        let nodes = ShellNodes::new(name, &built.mesh, pair)
            .map_err(|source| SceneError::Region {
                location: self.location(&m),
                field: m.clone(),
                source: Box::new(source),
            })?
            .with_groups(std::mem::take(&mut built.groups));
        let mut sample_points = nodes.disp_positions().to_vec();
        let corners = &built.mesh.corners;
        sample_points.extend((0..corners.n_elements()).map(|e| {
            let x = corners.element_nodes(e);
            (x[0] + x[1] + x[2]) / 3.0
        }));
        Ok(ValidShell {
            spec: ShellSpec {
                name: name.to_string(),
                model: model_kind,
                mesh: built.mesh,
                pair,
                material: params,
                rest,
                quadrature,
                damping,
                angular_inertia_density,
                initial_positions: built.initial_positions,
            },
            nodes,
            sample_points,
            warnings: built.warnings,
        })
    }

    /// The element pair of a mesh section for the model: Tri3 only for the comparison models, which
    /// take no rotation element or quadrature.
    fn element_pair(&self, m: &str, mesh: &MeshSection, model_kind: ModelKind) -> Result<ElementPair, SceneError> {
        let default_element = if model_kind == ModelKind::Cosserat {
            ElementName::Tri6
        } else {
            ElementName::Tri3
        };
        if model_kind != ModelKind::Cosserat {
            let model = model_label(model_kind);
            if mesh.element == Some(ElementName::Tri6) {
                return Err(self.invalid(
                    &format!("{m}.element"),
                    format!("the {model} model is built on the Tri3 mesh (`element = \"tri3\"`, the default for it); Tri6 elements are not available"),
                ));
            }
            if mesh.rotation_element.is_some() {
                return Err(self.invalid(
                    &format!("{m}.rotation_element"),
                    format!("does not apply to the {model} model"),
                ));
            }
            if mesh.quadrature_degree.is_some() {
                return Err(self.invalid(
                    &format!("{m}.quadrature_degree"),
                    format!("does not apply to the {model} model (its quadrature is fixed)"),
                ));
            }
        }
        let displacement = mesh.element.unwrap_or(default_element);
        // Quadratic displacements default to quadratic rotations (with Regge membrane strains and
        // stabilised shear and drilling, `rest_options`): locking-free on thin and curved shells.
        // `rotation_element = "tri3"` alone selects the paper's discretisation.
        Ok(match (displacement, mesh.rotation_element.unwrap_or(displacement)) {
            (ElementName::Tri3, ElementName::Tri3) => ElementPair::Tri3Tri3,
            (ElementName::Tri6, ElementName::Tri3) => ElementPair::Tri6Tri3,
            (ElementName::Tri6, ElementName::Tri6) => ElementPair::Tri6Tri6,
            (ElementName::Tri3, ElementName::Tri6) => {
                return Err(self.invalid(
                    &format!("{m}.rotation_element"),
                    "quadratic rotations need quadratic displacements (`element = \"tri6\"`)",
                ));
            }
        })
    }

    /// The quadrature rule a mesh section asks for (`None`: the pair's default with the shell's strain
    /// interpolation, `cosserat_assembly::ElementPair::default_quadrature`).
    fn quadrature(&self, m: &str, mesh: &MeshSection, pair: ElementPair) -> Result<Option<QuadratureRule>, SceneError> {
        Ok(match mesh.quadrature_degree {
            None => None,
            Some(d) if d < pair.min_quadrature_degree() => {
                return Err(self.invalid(
                    &format!("{m}.quadrature_degree"),
                    format!(
                        "a rule of degree {d} leaves zero-energy modes in {:?} elements (they deform without \
                         resistance); use at least degree {} or leave the key out for the default",
                        pair.displacement(),
                        pair.min_quadrature_degree()
                    ),
                ));
            }
            Some(d) => Some(QuadratureRule::for_degree(d).ok_or_else(|| {
                self.invalid(
                    &format!("{m}.quadrature_degree"),
                    format!("no quadrature rule of degree {d} is available"),
                )
            })?),
        })
    }

    /// Moves every node (corners and Tri6 nodes alike, so the two stay consistent) by the displacement
    /// field `d(x, y, z)` and checks the result.
    fn displace(&self, m: &str, d: &[ExprValue; 3], mesh: &mut ShellMesh) -> Result<(), SceneError> {
        let f = format!("{m}.displace");
        let mut points = mesh.corners.nodes.clone();
        if let Some(t6) = &mesh.tri6 {
            points.extend_from_slice(&t6.nodes);
        }
        let mut fields = Vec::with_capacity(3);
        for (k, value) in d.iter().enumerate() {
            let field = self.field_function(&format!("{f}.{k}"), value, &points)?;
            if field.is_time_dependent() {
                return Err(self.invalid(
                    &format!("{f}.{k}"),
                    "a rest-shape displacement depends on the position only, not on `t`",
                ));
            }
            fields.push(field);
        }
        let shift = |x: &mut Vector3<f64>| {
            let at = *x;
            *x += Vector3::new(
                fields[0].eval(&at, 0.0),
                fields[1].eval(&at, 0.0),
                fields[2].eval(&at, 0.0),
            );
        };
        mesh.corners.nodes.iter_mut().for_each(shift);
        if let Some(t6) = &mut mesh.tri6 {
            t6.nodes.iter_mut().for_each(shift);
        }
        let invalid = |source: MeshError| SceneError::Mesh {
            location: self.location(&f),
            field: f.clone(),
            source: Box::new(source),
        };
        mesh.corners.validate().map_err(invalid)?;
        if let Some(t6) = &mesh.tri6 {
            t6.validate().map_err(invalid)?;
        }
        Ok(())
    }

    /// The flat triangle mesh of a contact obstacle given as a mesh section (generator or OBJ, with
    /// the shaping steps; no elements, quadrature or initial pose).
    pub(super) fn obstacle_mesh(&self, m: &str, mesh: &MeshSection) -> Result<SurfaceMesh, SceneError> {
        let unused = [
            ("element", mesh.element.is_some()),
            ("rotation_element", mesh.rotation_element.is_some()),
            ("quadrature_degree", mesh.quadrature_degree.is_some()),
            ("initial", mesh.initial.is_some()),
        ];
        if let Some((key, _)) = unused.iter().find(|(_, given)| *given) {
            return Err(self.invalid(
                &format!("{m}.{key}"),
                "does not apply to an obstacle (a flat triangle mesh that is not simulated)",
            ));
        }
        let recipe = self.recipe(m, mesh, ElementPair::Tri3Tri3)?;
        let mut built = build_mesh_within(&recipe, self.budget).map_err(|e| self.mesh_source_error(m, e))?;
        if let Some(d) = &mesh.displace {
            self.displace(m, d, &mut built.mesh)?;
        }
        let corners = built.mesh.corners;
        Ok((corners.nodes, corners.elements))
    }

    fn mesh_source_error(&self, m: &str, error: MeshSourceError) -> SceneError {
        match error {
            MeshSourceError::Generator(source) => {
                let field = match &source {
                    MeshError::InvalidParameter { parameter, .. } => {
                        let key = match *parameter {
                            "outer_radius" => "radius",
                            "polar_angle" => "polar_hole_degrees",
                            p => p,
                        };
                        format!("{m}.{key}")
                    }
                    _ => format!("{m}.generator"),
                };
                SceneError::Mesh {
                    location: self.location(&field),
                    field,
                    source: Box::new(source),
                }
            }
            MeshSourceError::Obj(source) => {
                let field = format!("{m}.path");
                SceneError::Obj {
                    location: self.location(&field),
                    field,
                    source: Box::new(source),
                }
            }
            MeshSourceError::File(source) => {
                let field = format!("{m}.path");
                SceneError::MeshFile {
                    location: self.location(&field),
                    field,
                    source: Box::new(source),
                }
            }
            MeshSourceError::Invalid { step, reason } => {
                let field = format!("{m}.{step}");
                self.invalid(&field, reason)
            }
            MeshSourceError::Result(source) => SceneError::Mesh {
                location: self.location(m),
                field: m.to_string(),
                source: Box::new(source),
            },
        }
    }

    fn recipe(&self, m: &str, mesh: &MeshSection, pair: ElementPair) -> Result<MeshRecipe, SceneError> {
        let source = self.mesh_source(m, mesh)?;
        let refine = mesh.refine.unwrap_or(0);
        if refine > MAX_REFINE {
            return Err(self.invalid(
                &format!("{m}.refine"),
                format!("must be at most {MAX_REFINE} (got {refine})"),
            ));
        }
        let project_to_sphere = match &mesh.project_to_sphere {
            None => None,
            Some(s) => Some(SphereProjection {
                center: match s.center {
                    Some(c) => self.vector(&format!("{m}.project_to_sphere.center"), c)?,
                    None => Vector3::zeros(),
                },
                radius: self.positive(&format!("{m}.project_to_sphere.radius"), s.radius)?,
            }),
        };
        let flatten_cap = match &mesh.flatten_cap {
            None => None,
            Some(f) => Some(self.positive(&format!("{m}.flatten_cap.radius"), f.radius)?),
        };
        let transform = match &mesh.transform {
            None => None,
            Some(t) => Some(self.transform(&format!("{m}.transform"), t)?),
        };
        let initial = match &mesh.initial {
            None => None,
            Some(i) => Some(self.initial_motion(&format!("{m}.initial"), i)?),
        };
        let weld = match (mesh.weld, &mesh.path) {
            (None, _) => None,
            (Some(_), None) => return Err(self.invalid(&format!("{m}.weld"), "only used with an OBJ `path`")),
            (Some(d), Some(_)) => Some(self.positive(&format!("{m}.weld"), d)?),
        };
        Ok(MeshRecipe {
            source,
            pair,
            refine,
            weld,
            project_to_sphere,
            flatten_cap,
            transform,
            initial,
        })
    }

    /// Where the mesh comes from: a generator with its parameters or a mesh file, exactly one.
    fn mesh_source(&self, m: &str, mesh: &MeshSection) -> Result<MeshSource, SceneError> {
        let given = given_parameters(mesh);
        match (mesh.generator, &mesh.path) {
            (Some(_), Some(_)) => Err(self.invalid(&format!("{m}.path"), "give `generator` or `path`, not both")),
            (None, None) => Err(self.invalid(m, "needs a `generator` or a `path` to an OBJ file")),
            (None, Some(path)) => {
                if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
                    return Err(self.invalid(&format!("{m}.{key}"), "a generator parameter, not used with `path`"));
                }
                MeshSource::file(self.resolve_path(&format!("{m}.path"), path))
                    .map_err(|e| self.mesh_source_error(m, e))
            }
            (Some(generator), None) => Ok(MeshSource::Generator(self.generator(m, generator, mesh, &given)?)),
        }
    }

    /// The `transform` step at field path `f`: rotation, centring, one scaling, translation.
    fn transform(&self, f: &str, t: &TransformSection) -> Result<Transform, SceneError> {
        let scaling = match (t.height, t.scale) {
            (Some(_), Some(_)) => {
                return Err(self.invalid(&format!("{f}.scale"), "give `height` or `scale`, not both"));
            }
            (Some(h), None) => Some(Scaling::Height(self.positive(&format!("{f}.height"), h)?)),
            (None, Some(s)) => Some(Scaling::Factor(self.positive(&format!("{f}.scale"), s)?)),
            (None, None) => None,
        };
        Ok(Transform {
            rotation: match &t.rotate {
                Some(steps) => self.rotation(&format!("{f}.rotate"), steps)?,
                None => Matrix3::identity(),
            },
            center: t.center.unwrap_or(false),
            scaling,
            translation: match t.translate {
                Some(d) => self.vector(&format!("{f}.translate"), d)?,
                None => Vector3::zeros(),
            },
        })
    }

    /// The `initial` rigid motion at field path `f`: a rotation about a point, then a translation.
    fn initial_motion(&self, f: &str, i: &InitialSection) -> Result<RigidMotion, SceneError> {
        Ok(RigidMotion {
            rotation: match &i.rotate {
                Some(steps) => self.rotation(&format!("{f}.rotate"), steps)?,
                None => Matrix3::identity(),
            },
            about: match i.about {
                Some(p) => self.vector(&format!("{f}.about"), p)?,
                None => Vector3::zeros(),
            },
            translation: match i.translate {
                Some(d) => self.vector(&format!("{f}.translate"), d)?,
                None => Vector3::zeros(),
            },
        })
    }

    /// Every parameter the generator needs is given, and none that it does not take.
    fn check_generator_parameters(
        &self,
        m: &str,
        generator: GeneratorName,
        given: &[(&'static str, bool)],
    ) -> Result<(), SceneError> {
        let (required, optional): (&[&str], &[&str]) = match generator {
            GeneratorName::Rectangle => (&["lx", "ly", "nx", "ny"], &[]),
            GeneratorName::Disk => (&["radius", "n_radial", "n_angular"], &[]),
            GeneratorName::Annulus => (&["inner_radius", "radius", "n_radial", "n_angular"], &["slit"]),
            GeneratorName::Cylinder => (&["radius", "length", "n_around", "n_along"], &[]),
            GeneratorName::Icosphere => (&["radius", "level"], &[]),
            GeneratorName::IcosphereCap => (&["radius", "frequency", "min_z"], &[]),
            GeneratorName::UvSphere => (&["radius", "n_lon", "n_lat"], &[]),
            GeneratorName::Hemisphere => (&["radius", "n_lon", "n_lat"], &["polar_hole_degrees"]),
            GeneratorName::Mobius => (&["radius", "width", "n_along", "n_across"], &[]),
        };
        let name = generator.as_str();
        let all: Vec<&str> = required.iter().chain(optional).copied().collect();
        for (key, is_given) in given {
            if *is_given && !all.contains(key) {
                return Err(self.invalid(
                    &format!("{m}.{key}"),
                    format!(
                        "not a parameter of the `{name}` generator (its parameters: {})",
                        all.join(", ")
                    ),
                ));
            }
        }
        for key in required {
            if !given.iter().any(|(k, g)| k == key && *g) {
                return Err(self.invalid(
                    &format!("{m}.{key}"),
                    format!(
                        "required by the `{name}` generator (its parameters: {})",
                        all.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn generator(
        &self,
        m: &str,
        generator: GeneratorName,
        mesh: &MeshSection,
        given: &[(&'static str, bool)],
    ) -> Result<Generator, SceneError> {
        self.check_generator_parameters(m, generator, given)?;
        // Presence of every required parameter was checked above.
        let f = |v: Option<f64>| v.unwrap_or(f64::NAN);
        let n = |v: Option<usize>| v.unwrap_or(0);
        Ok(match generator {
            GeneratorName::Rectangle => Generator::Rectangle {
                lx: f(mesh.lx),
                ly: f(mesh.ly),
                nx: n(mesh.nx),
                ny: n(mesh.ny),
            },
            GeneratorName::Disk => Generator::Disk {
                radius: f(mesh.radius),
                n_radial: n(mesh.n_radial),
                n_angular: n(mesh.n_angular),
            },
            GeneratorName::Annulus => Generator::Annulus(AnnulusSettings {
                inner_radius: f(mesh.inner_radius),
                outer_radius: f(mesh.radius),
                n_radial: n(mesh.n_radial),
                n_angular: n(mesh.n_angular),
                slit: mesh.slit.unwrap_or(false),
            }),
            GeneratorName::Cylinder => Generator::Cylinder {
                radius: f(mesh.radius),
                length: f(mesh.length),
                n_around: n(mesh.n_around),
                n_along: n(mesh.n_along),
            },
            GeneratorName::Icosphere => Generator::Icosphere {
                radius: f(mesh.radius),
                level: n(mesh.level),
            },
            GeneratorName::IcosphereCap => Generator::IcosphereCap {
                radius: f(mesh.radius),
                frequency: n(mesh.frequency),
                min_z: f(mesh.min_z),
            },
            GeneratorName::UvSphere => Generator::UvSphere {
                radius: f(mesh.radius),
                n_lon: n(mesh.n_lon),
                n_lat: n(mesh.n_lat),
            },
            GeneratorName::Hemisphere => Generator::Hemisphere {
                radius: f(mesh.radius),
                n_lon: n(mesh.n_lon),
                n_lat: n(mesh.n_lat),
                polar_hole: match mesh.polar_hole_degrees {
                    Some(d) if (0.0..90.0).contains(&d) => Some(d.to_radians()),
                    Some(d) => {
                        return Err(self.invalid(
                            &format!("{m}.polar_hole_degrees"),
                            format!(
                                "must lie in [0, 90): the polar angle of the hole's rim in degrees (got {})",
                                Num(d)
                            ),
                        ));
                    }
                    None => None,
                },
            },
            GeneratorName::Mobius => Generator::Mobius {
                radius: f(mesh.radius),
                width: f(mesh.width),
                n_along: n(mesh.n_along),
                n_across: n(mesh.n_across),
            },
        })
    }

    /// Material parameters, rest options, damping and angular inertia density.
    fn material(
        &self,
        p: &str,
        m: &MaterialSection,
        pair: ElementPair,
    ) -> Result<(MaterialParameters, RestOptions, f64, f64), SceneError> {
        let params = self.material_parameters(p, m)?;
        let damping = self.non_negative(&format!("{p}.damping"), m.damping.unwrap_or(0.0))?;
        let angular_inertia_density = self.non_negative(
            &format!("{p}.angular_inertia_density"),
            m.angular_inertia_density.unwrap_or(0.0),
        )?;
        let rest = self.rest_options(p, m, pair)?;
        Ok((params, rest, damping, angular_inertia_density))
    }

    /// The elastic parameters with the section's overrides, validated (errors name the key).
    fn material_parameters(&self, p: &str, m: &MaterialSection) -> Result<MaterialParameters, SceneError> {
        let length_scale = match (m.model, m.length_scale) {
            (ModelName::KirchhoffLove, _) => 0.0,
            (_, Some(l)) => l,
            (_, None) => return Err(self.invalid(&format!("{p}.length_scale"), "required by the Cosserat models")),
        };
        let mut params =
            MaterialParameters::new(m.thickness, m.youngs_modulus, m.poisson_ratio, m.density, length_scale);
        if let Some(v) = m.mu_c_factor {
            params.mu_c_factor = v;
        }
        if let Some(v) = m.curvature_coefficients {
            params.curvature_coefficients = v;
        }
        if let Some(v) = m.bending_correction {
            params.bending_correction = v;
        }
        params.validate().map_err(|e| match e {
            MaterialError::InvalidParameter { name, value, reason } => {
                let (key, detail) = match name.split_once('[') {
                    Some((key, index)) => (key, format!(" (entry {})", index.trim_end_matches(']'))),
                    None => (name, String::new()),
                };
                self.invalid(&format!("{p}.{key}"), format!("{reason}{detail} (got {})", Num(value)))
            }
            other => self.invalid(p, other.to_string()),
        })?;
        self.stiffness_scales(p, &params)?;
        Ok(params)
    }

    /// Checks that the stiffnesses and the mass the energy is made of are finite and, where the
    /// model needs them, not zero. Each parameter may be in range while a product overflows or
    /// underflows (`h = 1e100` gives `h³ = 1e300`, times `E` infinite; `h = 1e-200` gives `h³ = 0`):
    /// the run would then stop in its first step with a non-finite energy or a singular matrix and
    /// no word of which value is at fault.
    fn stiffness_scales(&self, p: &str, params: &MaterialParameters) -> Result<(), SceneError> {
        let (e, h, rho) = (params.youngs_modulus, params.thickness, params.density);
        let scales = [
            ("thickness", "the membrane stiffness E·h", e * h, true),
            (
                "thickness",
                "the plate bending stiffness E·h³/(12(1 − ν²))",
                params.plate_bending_stiffness(),
                true,
            ),
            (
                "length_scale",
                "the curvature stiffness h·μ·L_c²·(b₁ + b₂)",
                params.curvature_stiffness(),
                false,
            ),
            ("density", "the mass per area ρ·h", rho * h, true),
        ];
        for (key, what, value, needs_positive) in scales {
            let problem = if !value.is_finite() {
                "overflows"
            } else if needs_positive && value == 0.0 {
                "underflows to zero"
            } else {
                continue;
            };
            return Err(self.invalid(
                &format!("{p}.{key}"),
                format!(
                    "{what} {problem} in double precision (E = {} Pa, h = {} m, L_c = {} m, ρ = {} kg/m³); \
                     choose units in which these values are nearer to 1",
                    Num(e),
                    Num(h),
                    Num(params.length_scale),
                    Num(rho)
                ),
            ));
        }
        Ok(())
    }

    /// The model's options (plate or shell, curved terms, volume term, axl) and the rest-state
    /// options (strain interpolation, curvature source, normal weighting). The strain interpolation
    /// defaults to Regge membrane strains with stabilised shear and drilling on quadratic rotations, for
    /// which its constants are set, and to the paper's on the other pairs.
    fn rest_options(&self, p: &str, m: &MaterialSection, pair: ElementPair) -> Result<RestOptions, SceneError> {
        let model = ModelOptions {
            model: match m.model {
                ModelName::Plate | ModelName::KirchhoffLove | ModelName::MicropolarVolume => ShellModel::Plate,
                ModelName::Shell => ShellModel::Shell,
            },
            curved_terms: match m.curved_terms {
                None | Some(CurvedTermsName::Supplement) => CurvedTerms::Supplement,
                Some(CurvedTermsName::ReferenceCompatibility) => CurvedTerms::ReferenceCompatibility,
            },
            membrane_volume: match m.membrane_volume {
                None | Some(MembraneVolumeName::Quadratic) => MembraneVolume::Quadratic,
                Some(MembraneVolumeName::Nonlinear) => MembraneVolume::Nonlinear,
            },
            axl: match m.axl {
                None | Some(AxlName::SkewPart) => AxlVariant::SkewPart,
                Some(AxlName::UpperTriangle) => AxlVariant::UpperTriangle,
            },
        };
        if model.model == ShellModel::Shell && model.membrane_volume == MembraneVolume::Nonlinear {
            return Err(self.invalid(
                &format!("{p}.membrane_volume"),
                "the nonlinear volume term is defined for the plate model only",
            ));
        }
        let mut rest = RestOptions::new(model);
        rest.interpolation = match m.strain_interpolation {
            None if pair == ElementPair::Tri6Tri6 => StrainInterpolation::ReggeStabilized,
            None | Some(StrainInterpolationName::Paper) => StrainInterpolation::Paper,
            Some(StrainInterpolationName::Stabilized) => StrainInterpolation::Stabilized,
            Some(StrainInterpolationName::Assumed) => StrainInterpolation::Assumed,
            Some(StrainInterpolationName::Regge) => StrainInterpolation::Regge,
            Some(StrainInterpolationName::ReggeStabilized) => StrainInterpolation::ReggeStabilized,
        };
        if let Some(source) = m.curvature_source {
            rest.curvature.source = match source {
                CurvatureSourceName::Auto => CurvatureSource::Auto,
                CurvatureSourceName::Exact => CurvatureSource::ExactElement,
                CurvatureSourceName::Averaged => CurvatureSource::AveragedNodalNormals,
            };
        }
        if let Some(weighting) = m.normal_weighting {
            rest.curvature.weighting = match weighting {
                NormalWeightingName::Max => NormalWeighting::Max,
                NormalWeightingName::Angle => NormalWeighting::Angle,
                NormalWeightingName::Area => NormalWeighting::Area,
                NormalWeightingName::Uniform => NormalWeighting::Uniform,
            };
        }
        Ok(rest)
    }
}

/// The scene-file name of a non-Cosserat model, for messages.
fn model_label(kind: ModelKind) -> &'static str {
    match kind {
        ModelKind::KirchhoffLove(_) => "Kirchhoff–Love (`kirchhoff_love`)",
        ModelKind::MicropolarVolume { .. } => "micropolar volume (`micropolar_volume`)",
        _ => "Cosserat shell",
    }
}

impl Ctx<'_> {
    /// The model of a material section, with the keys that belong to other models rejected.
    fn model_kind(&self, p: &str, m: &MaterialSection) -> Result<ModelKind, SceneError> {
        let kind = match m.model {
            ModelName::Plate | ModelName::Shell => ModelKind::Cosserat,
            ModelName::KirchhoffLove => ModelKind::KirchhoffLove(KlSettings {
                law: match m.law {
                    Some(LawName::Stvk) => HyperelasticLaw::StVenantKirchhoff,
                    Some(LawName::NeoHookean) => HyperelasticLaw::NeoHookean,
                    None => {
                        return Err(self.invalid(
                            &format!("{p}.law"),
                            "required by the Kirchhoff–Love model: \"stvk\" or \"neo_hookean\"",
                        ));
                    }
                },
                rest_volume: match m.rest_volume {
                    None | Some(RestVolumeName::Exact) => KlRestVolume::Exact,
                    Some(RestVolumeName::MidSurface) => KlRestVolume::MidSurface,
                },
            }),
            ModelName::MicropolarVolume => {
                let layers = m.layers.unwrap_or(1);
                if layers == 0 {
                    return Err(self.invalid(&format!("{p}.layers"), "must be at least 1"));
                }
                ModelKind::MicropolarVolume { layers }
            }
        };
        self.check_keys_of_model(p, m, kind)?;
        Ok(kind)
    }

    /// Rejects the keys of a material section that the model does not take: the Kirchhoff–Love
    /// law and rest volume, the volume's layers, and the Cosserat-only parameters.
    fn check_keys_of_model(&self, p: &str, m: &MaterialSection, kind: ModelKind) -> Result<(), SceneError> {
        if m.law.is_some() && !matches!(kind, ModelKind::KirchhoffLove(_)) {
            return Err(self.invalid(
                &format!("{p}.law"),
                "only the Kirchhoff–Love model (`model = \"kirchhoff_love\"`) takes a hyperelastic law",
            ));
        }
        if m.rest_volume.is_some() && !matches!(kind, ModelKind::KirchhoffLove(_)) {
            return Err(self.invalid(
                &format!("{p}.rest_volume"),
                "only the Kirchhoff–Love model (`model = \"kirchhoff_love\"`) takes a rest-volume measure",
            ));
        }
        if m.layers.is_some() && !matches!(kind, ModelKind::MicropolarVolume { .. }) {
            return Err(self.invalid(
                &format!("{p}.layers"),
                "only the micropolar volume model (`model = \"micropolar_volume\"`) has layers",
            ));
        }
        let cosserat_only = [
            ("length_scale", m.length_scale.is_some()),
            ("mu_c_factor", m.mu_c_factor.is_some()),
            ("curvature_coefficients", m.curvature_coefficients.is_some()),
            ("bending_correction", m.bending_correction.is_some()),
            ("angular_inertia_density", m.angular_inertia_density.is_some()),
            ("curved_terms", m.curved_terms.is_some()),
            ("membrane_volume", m.membrane_volume.is_some()),
            ("axl", m.axl.is_some()),
            ("strain_interpolation", m.strain_interpolation.is_some()),
            ("curvature_source", m.curvature_source.is_some()),
            ("normal_weighting", m.normal_weighting.is_some()),
        ];
        let not_for_volume = [
            "bending_correction",
            "curved_terms",
            "membrane_volume",
            "axl",
            "strain_interpolation",
            "curvature_source",
            "normal_weighting",
        ];
        let rejected = match kind {
            ModelKind::KirchhoffLove(_) => cosserat_only.iter().find(|(_, given)| *given),
            ModelKind::MicropolarVolume { .. } => {
                cosserat_only.iter().find(|(key, given)| *given && not_for_volume.contains(key))
            }
            _ => None,
        };
        if let Some((key, _)) = rejected {
            return Err(self.invalid(
                &format!("{p}.{key}"),
                format!("does not apply to the {} model", model_label(kind)),
            ));
        }
        Ok(())
    }
}

/// Every generator parameter of the mesh section and whether it is given.
fn given_parameters(m: &MeshSection) -> Vec<(&'static str, bool)> {
    vec![
        ("lx", m.lx.is_some()),
        ("ly", m.ly.is_some()),
        ("nx", m.nx.is_some()),
        ("ny", m.ny.is_some()),
        ("radius", m.radius.is_some()),
        ("inner_radius", m.inner_radius.is_some()),
        ("n_radial", m.n_radial.is_some()),
        ("n_angular", m.n_angular.is_some()),
        ("slit", m.slit.is_some()),
        ("length", m.length.is_some()),
        ("n_around", m.n_around.is_some()),
        ("n_along", m.n_along.is_some()),
        ("level", m.level.is_some()),
        ("frequency", m.frequency.is_some()),
        ("min_z", m.min_z.is_some()),
        ("n_lon", m.n_lon.is_some()),
        ("n_lat", m.n_lat.is_some()),
        ("polar_hole_degrees", m.polar_hole_degrees.is_some()),
        ("width", m.width.is_some()),
        ("n_across", m.n_across.is_some()),
    ]
}

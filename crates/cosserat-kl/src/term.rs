//! The Kirchhoff–Love elastic energy of a Tri3 mesh as a potential term of `cosserat-assembly`.
//!
//! Unknowns are the end-of-step vertex velocities, positions `x = xⁿ + Δt v` exactly as in the Cosserat
//! shell term, so the gradient and Hessian with respect to `v` are `Δt` and `Δt²` times those with
//! respect to `x`. Stencils are evaluated in parallel and scattered in face order
//! (`cosserat_assembly::parallel::ordered_map`), so results are bit-identical for any number of threads.

use crate::energy::{N_STENCIL, StencilDerivatives, stencil_energy, stencil_gradient, stencil_hessian};
use crate::error::KlError;
use crate::material::{KlMaterial, MaterialConstants};
use crate::rest::StencilRest;
use crate::stencil::{Stencil, build_stencils};
use crate::thickness::ThicknessRule;
use cosserat_assembly::finite::all_finite;
use cosserat_assembly::parallel::{ChunkBuffers, ordered_map};
use cosserat_assembly::scatter::GroupScatter;
use cosserat_assembly::term::{Evaluation, PotentialTerm};
use cosserat_assembly::{AssemblyError, DofLayout, SparsityPattern};
use cosserat_fem::Tri3Mesh;
use nalgebra::{SVector, Vector3};
use std::sync::Mutex;

/// The elastic energy of a Kirchhoff–Love shell on a Tri3 mesh whose vertex `i` is displacement node `i`
/// of the system.
#[derive(Debug)]
pub struct KirchhoffLoveTerm {
    stencils: Vec<Stencil>,
    rest: Vec<StencilRest>,
    material: MaterialConstants,
    layout: DofLayout,
    scatter: Option<GroupScatter<6>>,
    values: Mutex<ChunkBuffers<f64>>,
    derivatives: Mutex<ChunkBuffers<StencilDerivatives>>,
}

/// The 18 rest coordinates of a stencil (zeros in absent slots).
fn stencil_coordinates(stencil: &Stencil, position: impl Fn(usize) -> Vector3<f64>) -> SVector<f64, N_STENCIL> {
    let mut x = SVector::<f64, N_STENCIL>::zeros();
    for (k, v) in stencil.vertices().iter().enumerate() {
        if let Some(v) = *v {
            let p: Vector3<f64> = position(v);
            x.fixed_rows_mut::<3>(3 * k).copy_from(&p);
        }
    }
    x
}

impl KirchhoffLoveTerm {
    /// The term of a shell of thickness `h` \[m\] whose rest state is `mesh`, in a system with `layout`.
    ///
    /// # Errors
    /// Invalid mesh ([`KlError::Mesh`]), material
    /// ([`KlError::InvalidParameter`]) or rest state ([`KlError::ThickerThanCurvature`]), and
    /// [`KlError::InvalidParameter`] if the layout has fewer displacement nodes than the mesh vertices.
    pub fn try_new(
        mesh: &Tri3Mesh,
        material: &KlMaterial,
        thickness: f64,
        rule: ThicknessRule,
        layout: DofLayout,
    ) -> Result<Self, KlError> {
        let constants = material.constants()?;
        if layout.n_disp_nodes < mesh.n_nodes() {
            return Err(KlError::InvalidParameter {
                name: "layout.n_disp_nodes",
                value: layout.n_disp_nodes as f64,
                reason: "must be at least the number of mesh vertices",
            });
        }
        let stencils = build_stencils(mesh)?;
        let rest = stencils
            .iter()
            .enumerate()
            .map(|(f, s)| {
                let x = stencil_coordinates(s, |v| mesh.nodes[v]);
                StencilRest::try_new(f, &x, s.present(), thickness, &rule)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            stencils,
            rest,
            material: constants,
            layout,
            scatter: None,
            values: Mutex::new(ChunkBuffers::new()),
            derivatives: Mutex::new(ChunkBuffers::new()),
        })
    }

    /// Number of faces (stencils).
    pub fn n_faces(&self) -> usize {
        self.stencils.len()
    }

    /// The stencils, in face order.
    pub fn stencils(&self) -> &[Stencil] {
        &self.stencils
    }

    /// The rest data, in face order.
    pub fn rest(&self) -> &[StencilRest] {
        &self.rest
    }

    /// The material constants.
    pub fn material(&self) -> &MaterialConstants {
        &self.material
    }

    /// The elastic energy \[J\] of the shell with vertex positions `x` (one per mesh vertex at least).
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] naming the first face whose energy is not finite.
    ///
    /// # Panics
    /// If `x` has fewer entries than the mesh has vertices.
    #[track_caller]
    pub fn energy_at(&self, x: &[Vector3<f64>]) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        for (f, s) in self.stencils.iter().enumerate() {
            let v = stencil_energy(&stencil_coordinates(s, |i| x[i]), &self.rest[f], &self.material);
            total += self.finite(v, f)?;
        }
        Ok(total)
    }

    fn finite(&self, v: f64, face: usize) -> Result<f64, AssemblyError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(AssemblyError::NonFinite {
                term: self.name(),
                location: "face",
                index: face,
            })
        }
    }

    fn blocks(&self, f: usize) -> [Option<usize>; 6] {
        self.stencils[f].vertices().map(|v| v.map(|i| self.layout.disp_block(i)))
    }

    fn current(&self, f: usize, eval: &Evaluation<'_>) -> SVector<f64, N_STENCIL> {
        stencil_coordinates(&self.stencils[f], |i| {
            eval.state.x[i] + eval.layout.velocity(eval.u, i) * eval.dt
        })
    }

    fn derivatives_into(&self, f: usize, eval: &Evaluation<'_>, with_hessian: bool, out: &mut StencilDerivatives) {
        let x = self.current(f, eval);
        let dt = eval.dt;
        if with_hessian {
            *out = stencil_hessian(&x, &self.rest[f], &self.material);
            out.hessian *= dt * dt;
        } else {
            let (value, gradient) = stencil_gradient(&x, &self.rest[f], &self.material);
            out.value = value;
            out.gradient = gradient;
        }
        out.gradient *= dt;
    }

    fn assemble(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        mut hessian: Option<(&SparsityPattern, &mut [f64])>,
    ) -> Result<f64, AssemblyError> {
        let scatter = self.scatter.as_ref().expect("term used before bind()");
        let with_hessian = hessian.is_some();
        let mut total = 0.0;
        let mut buffers = self.derivatives.lock().unwrap_or_else(|e| e.into_inner());
        ordered_map(
            self.n_faces(),
            eval.parallelism,
            &mut buffers,
            StencilDerivatives::zeros,
            |f, slot| self.derivatives_into(f, eval, with_hessian, slot),
            |f, d| {
                let finite = d.value.is_finite()
                    && all_finite(d.gradient.as_slice())
                    && (!with_hessian || all_finite(d.hessian.as_slice()));
                if !finite {
                    return Err(AssemblyError::NonFinite {
                        term: self.name(),
                        location: "face",
                        index: f,
                    });
                }
                total += d.value;
                scatter.add_gradient(f, &d.gradient, grad);
                if let Some((pattern, values)) = hessian.as_mut() {
                    scatter.add_hessian(f, &d.hessian, pattern, values);
                }
                Ok(())
            },
        )?;
        Ok(total)
    }
}

impl PotentialTerm for KirchhoffLoveTerm {
    fn is_elastic(&self) -> bool {
        true
    }

    fn name(&self) -> String {
        format!("kirchhoff_love_{}", self.material.model().name())
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        (0..self.n_faces())
            .map(|f| self.blocks(f).into_iter().flatten().collect())
            .collect()
    }

    fn bind(&mut self, pattern: &SparsityPattern) {
        let blocks = (0..self.n_faces()).map(|f| self.blocks(f)).collect();
        self.scatter = Some(GroupScatter::new(pattern, blocks));
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        let mut buffers = self.values.lock().unwrap_or_else(|e| e.into_inner());
        ordered_map(
            self.n_faces(),
            eval.parallelism,
            &mut buffers,
            || 0.0,
            |f, slot| *slot = stencil_energy(&self.current(f, eval), &self.rest[f], &self.material),
            |f, &v: &f64| {
                total += self.finite(v, f)?;
                Ok(())
            },
        )?;
        Ok(total)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        self.assemble(eval, grad, None)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        self.assemble(eval, grad, Some((pattern, values)))
    }
}

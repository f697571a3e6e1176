//! The element loop of the elastic terms: per element an [`ElementKernel`] computes the energy, its
//! gradient and its Hessian on the element's unknowns; [`ElementAssembly`] runs it over all elements in
//! parallel, consumes the results in element order and scatters them into the global vector and matrix.
//!
//! The Cosserat shell ([`crate::shell::ShellTerm`]) and the comparison models' element terms share this
//! loop, so each of them only says what one element computes. Consuming in element order
//! ([`ordered_map`]) keeps every sum bit-identical for any number of threads.

use crate::dofs::DofLayout;
use crate::error::AssemblyError;
use crate::finite::all_finite;
use crate::parallel::{ChunkBuffers, ordered_map};
use crate::pattern::SparsityPattern;
use crate::scatter::ElementScatter;
use crate::term::Evaluation;
use cosserat_material::element::ElementDerivatives;
use nalgebra::Vector3;
use std::sync::Mutex;

/// What one element of a term computes, on its `NE = 3 NB` unknowns in `NB` blocks of three.
///
/// The kernel is called from several threads at once, each time for one element and with its own slot
/// of results and scratch.
pub trait ElementKernel<const NE: usize, const NB: usize>: Sync {
    /// Per-element working storage the kernel reuses from one element to the next (e.g. a point's local
    /// derivatives); kept beside each element's results so that an evaluation allocates nothing.
    type Scratch: Send + Sync;

    /// A fresh scratch.
    fn scratch() -> Self::Scratch;

    /// The name of the term, for error messages.
    fn term_name(&self) -> String;

    /// Number of elements.
    fn n_elements(&self) -> usize;

    /// The global blocks of element `e`, in the order of its unknowns.
    fn blocks(&self, e: usize) -> [usize; NB];

    /// The energy of element `e`.
    fn element_value(&self, e: usize, eval: &Evaluation<'_>) -> f64;

    /// The energy and gradient of element `e`, and (`with_hessian`) its Hessian, into `out`.
    ///
    /// `out` and `scratch` are reused from element to element and still hold an earlier element's
    /// numbers, so the kernel overwrites (or first clears) everything the loop reads: the value, the
    /// gradient and, with the Hessian, its upper block triangle. The scatter reads only that triangle
    /// ([`ElementScatter::add_hessian`]); a kernel may leave the rest unwritten.
    fn element_derivatives(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        with_hessian: bool,
        out: &mut ElementDerivatives<NE>,
        scratch: &mut Self::Scratch,
    );
}

/// One element's place in the chunk buffers: its results, and the scratch its kernel writes into.
#[derive(Debug)]
struct ElementSlot<const NE: usize, S> {
    derivatives: ElementDerivatives<NE>,
    scratch: S,
}

/// The element loop of one term: its scatter positions and the reusable chunk buffers of element
/// results.
#[derive(Debug)]
pub struct ElementAssembly<const NE: usize, const NB: usize, S> {
    scatter: Option<ElementScatter<NB>>,
    /// Chunk buffers of element energies (energy-only evaluations).
    values: Mutex<ChunkBuffers<f64>>,
    /// Chunk buffers of element derivatives (gradient and Hessian evaluations).
    derivatives: Mutex<ChunkBuffers<ElementSlot<NE, S>>>,
}

impl<const NE: usize, const NB: usize, S: Send + Sync> Default for ElementAssembly<NE, NB, S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NE: usize, const NB: usize, S: Send + Sync> ElementAssembly<NE, NB, S> {
    /// A loop not yet bound to a pattern.
    pub fn new() -> Self {
        const { assert!(NE == 3 * NB, "an element has three unknowns per block") };
        Self {
            scatter: None,
            values: Mutex::new(ChunkBuffers::new()),
            derivatives: Mutex::new(ChunkBuffers::new()),
        }
    }

    /// The blocks of every element, as coupling groups for the sparsity pattern
    /// ([`crate::PotentialTerm::coupling_groups`]).
    pub fn coupling_groups<K: ElementKernel<NE, NB, Scratch = S>>(kernel: &K) -> Vec<Vec<usize>> {
        (0..kernel.n_elements()).map(|e| kernel.blocks(e).to_vec()).collect()
    }

    /// The scatter positions of every element of `kernel` in `pattern`, for [`Self::bind`].
    pub fn scatter<K: ElementKernel<NE, NB, Scratch = S>>(pattern: &SparsityPattern, kernel: &K) -> ElementScatter<NB> {
        ElementScatter::new(pattern, (0..kernel.n_elements()).map(|e| kernel.blocks(e)).collect())
    }

    /// Uses `scatter` for the elements' results from now on ([`crate::PotentialTerm::bind`]).
    pub fn bind(&mut self, scatter: ElementScatter<NB>) {
        self.scatter = Some(scatter);
    }

    fn bound_scatter(&self) -> &ElementScatter<NB> {
        self.scatter.as_ref().expect("term used before bind()")
    }

    /// The total energy of `kernel`'s elements.
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] naming the first element (in element order) whose energy is not
    /// finite.
    pub fn value<K: ElementKernel<NE, NB, Scratch = S>>(
        &self,
        kernel: &K,
        eval: &Evaluation<'_>,
    ) -> Result<f64, AssemblyError> {
        let mut total = 0.0;
        let mut buffers = self.values.lock().unwrap_or_else(|e| e.into_inner());
        ordered_map(
            kernel.n_elements(),
            eval.parallelism,
            &mut buffers,
            || 0.0,
            |e, slot| *slot = kernel.element_value(e, eval),
            |e, &v: &f64| {
                if !v.is_finite() {
                    return Err(non_finite(kernel.term_name(), e));
                }
                total += v;
                Ok(())
            },
        )?;
        Ok(total)
    }

    /// The total energy; adds the gradient into `grad`.
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] naming the first element whose energy or gradient is not finite.
    ///
    /// # Panics
    /// If called before [`Self::bind`] (programmer error).
    pub fn gradient<K: ElementKernel<NE, NB, Scratch = S>>(
        &self,
        kernel: &K,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let scatter = self.bound_scatter();
        let mut total = 0.0;
        self.for_each_element(kernel, eval, false, |e, d| {
            total += d.value;
            scatter.add_gradient(e, &d.gradient, grad);
        })?;
        Ok(total)
    }

    /// The total energy; adds the gradient into `grad` and the Hessian into the values of `pattern`.
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] naming the first element whose energy, gradient or Hessian is not
    /// finite.
    ///
    /// # Panics
    /// If called before [`Self::bind`] (programmer error).
    pub fn hessian<K: ElementKernel<NE, NB, Scratch = S>>(
        &self,
        kernel: &K,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let scatter = self.bound_scatter();
        let mut total = 0.0;
        self.for_each_element(kernel, eval, true, |e, d| {
            total += d.value;
            scatter.add_gradient(e, &d.gradient, grad);
            scatter.add_hessian(e, &d.hessian, pattern, values);
        })?;
        Ok(total)
    }

    /// Computes every element's derivatives in parallel and passes the finite ones to `consume` in
    /// element order, stopping at the first that is not.
    fn for_each_element<K: ElementKernel<NE, NB, Scratch = S>>(
        &self,
        kernel: &K,
        eval: &Evaluation<'_>,
        with_hessian: bool,
        mut consume: impl FnMut(usize, &ElementDerivatives<NE>) + Send,
    ) -> Result<(), AssemblyError> {
        let mut buffers = self.derivatives.lock().unwrap_or_else(|e| e.into_inner());
        ordered_map(
            kernel.n_elements(),
            eval.parallelism,
            &mut buffers,
            || ElementSlot {
                derivatives: ElementDerivatives::zeros(),
                scratch: K::scratch(),
            },
            |e, slot| {
                let out = &mut slot.derivatives;
                kernel.element_derivatives(e, eval, with_hessian, out, &mut slot.scratch);
                mark_non_finite(out, with_hessian);
            },
            |e, ElementSlot { derivatives: d, .. }| {
                if !d.value.is_finite() {
                    return Err(non_finite(kernel.term_name(), e));
                }
                consume(e, d);
                Ok(())
            },
        )
    }
}

fn non_finite(term: String, e: usize) -> AssemblyError {
    AssemblyError::NonFinite {
        term,
        location: "element",
        index: e,
    }
}

/// Sets the value of an element's results to NaN if its gradient or (`with_hessian`) its Hessian has a
/// non-finite entry, so that the consumer checks one number.
///
/// This runs on the thread that computed the element, while its numbers are in that core's cache; a
/// check by the (serial) consumer would read them once more from a farther cache.
#[inline]
fn mark_non_finite<const NE: usize>(d: &mut ElementDerivatives<NE>, with_hessian: bool) {
    if !(all_finite(d.gradient.as_slice()) && (!with_hessian || all_finite(d.hessian.as_slice()))) {
        d.value = f64::NAN;
    }
}

/// The blocks of an element whose unknowns are the velocities of its `NU` displacement nodes followed
/// by the angular velocities of its `NR` rotation nodes (`NB = NU + NR`).
pub fn displacement_rotation_blocks<const NU: usize, const NR: usize, const NB: usize>(
    layout: &DofLayout,
    disp: &[usize; NU],
    rot: &[usize; NR],
) -> [usize; NB] {
    const { assert!(NB == NU + NR, "one block per node") };
    std::array::from_fn(|i| {
        if i < NU {
            layout.disp_block(disp[i])
        } else {
            layout.rot_block(rot[i - NU])
        }
    })
}

/// The end-of-step positions `xⁿ + Δt v` of the given displacement nodes.
//
// Filled in a loop rather than by `std::array::from_fn`: the shell's elements call this once per
// evaluation and element, and the loop compiles to fewer instructions.
#[inline]
pub fn end_of_step_positions<const N: usize>(eval: &Evaluation<'_>, nodes: &[usize; N]) -> [Vector3<f64>; N] {
    let mut x = [Vector3::zeros(); N];
    for (x, &i) in x.iter_mut().zip(nodes) {
        *x = eval.state.x[i] + eval.layout.velocity(eval.u, i) * eval.dt;
    }
    x
}

/// The angular velocities `ω` (unknowns) of the given rotation nodes.
#[inline]
pub fn angular_velocities<const N: usize>(eval: &Evaluation<'_>, nodes: &[usize; N]) -> [Vector3<f64>; N] {
    let mut omega = [Vector3::zeros(); N];
    for (o, &k) in omega.iter_mut().zip(nodes) {
        *o = eval.layout.omega(eval.u, k);
    }
    omega
}

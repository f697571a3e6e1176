//! The predicted strains of the mixed-integration-point Newton method (Magisano, Leonetti and Garcea
//! 2017): after a step `α δu` from `u`, each quadrature point's strain at `u` plus `α` times its
//! linearisation along `δu`. A shell's Hessians weight their second-order terms with the stresses of
//! these strains instead of the stresses at the iterate (see
//! `cosserat_material::kernel::point_hessian_predicted_into`).

use cosserat_material::strain_space::StrainVector;

/// The strains of a shell's points at the last linearisation, their rates along its direction, and
/// the predicted strains once a step along it was taken.
#[derive(Debug, Default)]
pub(crate) struct StrainPrediction {
    base: Vec<StrainVector>,
    rate: Vec<StrainVector>,
    predicted: Option<Vec<StrainVector>>,
}

impl StrainPrediction {
    /// The buffers of the strains and their rates for `n` points, to be filled by a linearisation.
    pub(crate) fn linearization_buffers(&mut self, n: usize) -> (&mut [StrainVector], &mut [StrainVector]) {
        self.base.resize(n, StrainVector::zeros());
        self.rate.resize(n, StrainVector::zeros());
        (&mut self.base, &mut self.rate)
    }

    /// The step `α δu` along the last linearisation was taken.
    pub(crate) fn advance(&mut self, alpha: f64) {
        let predicted = self.predicted.get_or_insert_with(Vec::new);
        predicted.clear();
        predicted.extend(self.base.iter().zip(&self.rate).map(|(b, r)| b + r * alpha));
    }

    /// Forgets the predicted strains.
    pub(crate) fn clear(&mut self) {
        self.predicted = None;
    }

    /// The predicted strains of points `first..first + n`, if there are any for all of them.
    pub(crate) fn points(&self, first: usize, n: usize) -> Option<&[StrainVector]> {
        self.predicted.as_ref()?.get(first..first + n)
    }
}

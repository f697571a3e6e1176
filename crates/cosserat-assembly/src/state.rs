//! The state of a system at the start of a time step.

use nalgebra::{Quaternion, Vector3};

/// Positions, rotations and their rates at `tⁿ`, for all nodes and quadrature points of all shells.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemState {
    /// Positions `xⁿ` of the displacement nodes \[m\].
    pub x: Vec<Vector3<f64>>,
    /// Velocities `vⁿ` of the displacement nodes \[m/s\].
    pub v: Vec<Vector3<f64>>,
    /// Unit quaternions `qⁿ` of the rotation nodes (relative to the rest state).
    pub q: Vec<Quaternion<f64>>,
    /// Spatial angular velocities `ωⁿ` of the rotation nodes \[rad/s\].
    pub omega: Vec<Vector3<f64>>,
    /// Unit quaternions of the quadrature points (history-dependent state, model.md §1.6).
    pub q_points: Vec<Quaternion<f64>>,
    /// The membrane stress \[N/m\] each shell element's stabilisation held in the last committed step,
    /// at the element's first point (history-dependent too; zero elsewhere, at rest and where a
    /// shell's stabilisation holds no stress; see `ShellTerm::follow_tension`).
    pub held_tension: Vec<f64>,
}

impl SystemState {
    /// A state at rest: given positions, zero velocities and identity rotations.
    pub fn at_rest(x: Vec<Vector3<f64>>, n_rot_nodes: usize, n_points: usize) -> Self {
        let n = x.len();
        Self {
            x,
            v: vec![Vector3::zeros(); n],
            q: vec![Quaternion::identity(); n_rot_nodes],
            omega: vec![Vector3::zeros(); n_rot_nodes],
            q_points: vec![Quaternion::identity(); n_points],
            held_tension: vec![0.0; n_points],
        }
    }
}

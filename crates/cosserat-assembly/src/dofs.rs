//! The layout of the unknowns: nodal velocities of all displacement nodes, then nodal angular
//! velocities of all rotation nodes, three numbers each.

/// Where each node's three unknowns sit in the global vector (in blocks of three).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DofLayout {
    /// Number of displacement nodes (velocity unknowns).
    pub n_disp_nodes: usize,
    /// Number of rotation nodes (angular-velocity unknowns).
    pub n_rot_nodes: usize,
}

impl DofLayout {
    /// Number of 3-blocks.
    pub fn n_blocks(&self) -> usize {
        self.n_disp_nodes + self.n_rot_nodes
    }

    /// Number of scalar unknowns.
    pub fn n_dofs(&self) -> usize {
        3 * self.n_blocks()
    }

    /// Block of displacement node `i`.
    #[inline]
    pub fn disp_block(&self, i: usize) -> usize {
        i
    }

    /// Block of rotation node `k`.
    #[inline]
    pub fn rot_block(&self, k: usize) -> usize {
        self.n_disp_nodes + k
    }

    /// The velocity of displacement node `i` in an unknown vector.
    #[inline]
    pub fn velocity(&self, u: &[f64], i: usize) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2])
    }

    /// The angular velocity of rotation node `k` in an unknown vector.
    #[inline]
    pub fn omega(&self, u: &[f64], k: usize) -> nalgebra::Vector3<f64> {
        let o = 3 * self.rot_block(k);
        nalgebra::Vector3::new(u[o], u[o + 1], u[o + 2])
    }
}

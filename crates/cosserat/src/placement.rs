//! Where a scene's nodes are in the system: for each shell of the scene, the map from its nodes (as the
//! scene's regions select them, numbered per shell) to the system's displacement and rotation nodes,
//! with the shell's own mesh for loads along edges.
//!
//! A Cosserat or Kirchhoff–Love shell is a block of the system's nodes ([`NodeMap::Offset`]); the
//! volumetric model puts a column of slab nodes under each vertex of the scene's mid-surface
//! ([`NodeMap::Columns`]), so a boundary condition holds the whole column and a load is shared by it.

use nalgebra::Vector3;

/// The system nodes of a shell's nodes.
#[derive(Debug, Clone, PartialEq)]
pub enum NodeMap {
    /// Shell node `i` is system node `start + i`.
    Offset(usize),
    /// Shell node `i` is the column of system nodes `columns[i]`.
    Columns(Vec<Vec<usize>>),
}

impl NodeMap {
    /// The system nodes of the shell nodes `local` (sorted, without repeats).
    pub fn nodes(&self, local: &[usize]) -> Vec<usize> {
        let mut out: Vec<usize> = match self {
            NodeMap::Offset(start) => local.iter().map(|&i| start + i).collect(),
            NodeMap::Columns(columns) => local.iter().flat_map(|&i| columns[i].iter().copied()).collect(),
        };
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Weights on shell nodes carried over to system nodes: a column shares its node's weight equally.
    pub fn weights(&self, local: &[(usize, f64)]) -> Vec<(usize, f64)> {
        match self {
            NodeMap::Offset(start) => local.iter().map(|&(i, w)| (start + i, w)).collect(),
            NodeMap::Columns(columns) => local
                .iter()
                .flat_map(|&(i, w)| {
                    let share = w / columns[i].len() as f64;
                    columns[i].iter().map(move |&k| (k, share))
                })
                .collect(),
        }
    }
}

/// One shell of a scene in the system.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellPlacement {
    /// The shell's name.
    pub name: String,
    /// Its displacement nodes.
    pub disp: NodeMap,
    /// Its rotation nodes (empty for a model without rotations).
    pub rot: NodeMap,
    /// Rest positions of its displacement nodes, in shell numbering \[m\].
    pub rest_disp: Vec<Vector3<f64>>,
    /// Rest positions of its rotation nodes, in shell numbering \[m\].
    pub rest_rot: Vec<Vector3<f64>>,
    /// Its displacement elements in shell numbering (3 or 6 nodes, corners first).
    pub disp_elements: Vec<Vec<usize>>,
    /// Its rotation elements in shell numbering.
    pub rot_elements: Vec<Vec<usize>>,
}

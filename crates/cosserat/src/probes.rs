//! Probes: named point or region quantities written to `probes.csv` at every output time.

use cosserat_assembly::{ShellLayout, SystemState};
use cosserat_geometry::rotation::rotation_matrix;
use cosserat_scene::spec::{ProbeQuantity, ProbeReduction, ProbeSpec};
use nalgebra::Vector3;

#[derive(Debug, Clone)]
struct Probe {
    columns: [String; 3],
    quantity: ProbeQuantity,
    /// Global displacement nodes with their rest positions, or global rotation nodes (directors).
    nodes: Vec<(usize, Vector3<f64>)>,
}

/// The probes of a scene.
#[derive(Debug, Clone)]
pub struct Probes {
    probes: Vec<Probe>,
}

impl Probes {
    /// Resolves probe selections to global nodes.
    pub fn new(specs: &[ProbeSpec], layouts: &[ShellLayout]) -> Self {
        let probes = specs
            .iter()
            .map(|p| {
                let layout = &layouts[p.selection.shell];
                let nodes: Vec<(usize, Vector3<f64>)> = match p.quantity {
                    ProbeQuantity::Director => p
                        .selection
                        .rot_nodes
                        .iter()
                        .map(|&k| (layout.rot_nodes.start + k, layout.rest_rot_positions[k]))
                        .collect(),
                    _ => p
                        .selection
                        .disp_nodes
                        .iter()
                        .map(|&i| (layout.disp_nodes.start + i, layout.rest_disp_positions[i]))
                        .collect(),
                };
                // A "nearest" selection holds one node by construction; "mean" averages all.
                let nodes = match p.reduction {
                    ProbeReduction::Nearest => nodes.into_iter().take(1).collect(),
                    ProbeReduction::Mean => nodes,
                };
                Probe {
                    columns: p.columns(),
                    quantity: p.quantity,
                    nodes,
                }
            })
            .collect();
        Self { probes }
    }

    /// All column names, in order.
    pub fn columns(&self) -> Vec<String> {
        self.probes.iter().flat_map(|p| p.columns.iter().cloned()).collect()
    }

    /// The values of all columns in a state.
    pub fn values(&self, _layouts: &[ShellLayout], state: &SystemState) -> Vec<f64> {
        let mut out = Vec::with_capacity(3 * self.probes.len());
        for p in &self.probes {
            let mut sum = Vector3::zeros();
            for (i, rest) in &p.nodes {
                sum += match p.quantity {
                    ProbeQuantity::Displacement => state.x[*i] - rest,
                    ProbeQuantity::Position => state.x[*i],
                    ProbeQuantity::Velocity => state.v[*i],
                    ProbeQuantity::Director => rotation_matrix(&state.q[*i]).column(2).into_owned(),
                };
            }
            let mean = sum / p.nodes.len().max(1) as f64;
            out.extend_from_slice(mean.as_slice());
        }
        out
    }
}

//! Probes: named point or region quantities written to `probes.csv` at every output time.

use crate::placement::ShellPlacement;
use cosserat_assembly::SystemState;
use cosserat_geometry::rotation::rotation_matrix;
use cosserat_scene::spec::{ProbeQuantity, ProbeReduction, ProbeSpec};
use nalgebra::Vector3;

#[derive(Debug, Clone)]
struct Probe {
    columns: [String; 3],
    quantity: ProbeQuantity,
    /// System displacement nodes with their rest positions, or system rotation nodes (directors).
    nodes: Vec<(usize, Vector3<f64>)>,
}

/// The probes of a scene.
#[derive(Debug, Clone)]
pub struct Probes {
    probes: Vec<Probe>,
}

impl Probes {
    /// Resolves probe selections to system nodes; `rest` holds the rest positions of all system
    /// displacement nodes. A probe averages over its nodes: a `nearest` probe has one scene node, which
    /// may stand for several system nodes (a column of the volumetric slab).
    pub fn new(specs: &[ProbeSpec], placements: &[ShellPlacement], rest: &[Vector3<f64>]) -> Self {
        let probes = specs
            .iter()
            .map(|p| {
                let placement = &placements[p.selection.shell];
                let (local, map) = match p.quantity {
                    ProbeQuantity::Director => (&p.selection.rot_nodes, &placement.rot),
                    _ => (&p.selection.disp_nodes, &placement.disp),
                };
                let local = match p.reduction {
                    ProbeReduction::Nearest => &local[..local.len().min(1)],
                    ProbeReduction::Mean => &local[..],
                };
                let nodes = map
                    .nodes(local)
                    .into_iter()
                    .map(|i| (i, rest.get(i).copied().unwrap_or_else(Vector3::zeros)))
                    .collect();
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
    pub fn values(&self, state: &SystemState) -> Vec<f64> {
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

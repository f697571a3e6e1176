//! Output frames: the current state of all shells as a triangle surface with point data.
//!
//! Every output point is an (element, reference point) pair, so quadratic elements can be sampled
//! finely enough to look curved: subdivision level 0 writes the corner triangles, level 1 splits each
//! Tri6 into 4 triangles through its own nodes (shared between elements), level `s ≥ 2` samples each
//! element on a grid of `2ˢ` segments per edge. Point data: displacement, velocity, the three directors
//! (columns of the rotation, interpolated from the rotation nodes by normalised quaternion averaging)
//! and the angular velocity. (Contact appends its obstacles to a frame:
//! [`crate::contact_run::ContactRun::decorate_frame`].)

use cosserat_assembly::{ElementPair, ShellLayout, SystemState};
use cosserat_fem::{ShapeFunctions, Tri3, Tri6};
use cosserat_geometry::rotation::{rotation_matrix, same_hemisphere};
use cosserat_io::{DataArray, VtuFrame};
use nalgebra::{Quaternion, Vector3};
use std::collections::HashMap;

/// One output point: an element of a shell and a reference point in it.
#[derive(Debug, Clone, Copy)]
struct Sample {
    shell: usize,
    elem: usize,
    xi: [f64; 2],
}

/// The fixed sampling of all shells for output.
#[derive(Debug, Clone)]
pub struct OutputMesh {
    samples: Vec<Sample>,
    triangles: Vec<[usize; 3]>,
}

/// Reference coordinates of the Tri6 nodes in our order.
const TRI6_NODES: [[f64; 2]; 6] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];

impl OutputMesh {
    /// The sampling of `layouts` at a subdivision level.
    pub fn new(layouts: &[ShellLayout], subdivision: usize) -> Self {
        let mut samples = Vec::new();
        let mut triangles = Vec::new();
        for (s, layout) in layouts.iter().enumerate() {
            let quadratic = layout.pair != ElementPair::Tri3Tri3;
            if !quadratic || subdivision <= 1 {
                // Shared nodes: one sample per displacement node.
                let mut index: HashMap<usize, usize> = HashMap::new();
                for (e, el) in layout.disp_elements.iter().enumerate() {
                    let refs: &[[f64; 2]] = if quadratic { &TRI6_NODES } else { &TRI6_NODES[..3] };
                    let ids: Vec<usize> = el
                        .iter()
                        .zip(refs)
                        .map(|(&node, &xi)| {
                            *index.entry(node).or_insert_with(|| {
                                samples.push(Sample { shell: s, elem: e, xi });
                                samples.len() - 1
                            })
                        })
                        .collect();
                    if quadratic && subdivision == 1 {
                        triangles.extend([
                            [ids[0], ids[3], ids[5]],
                            [ids[3], ids[1], ids[4]],
                            [ids[5], ids[4], ids[2]],
                            [ids[3], ids[4], ids[5]],
                        ]);
                    } else {
                        triangles.push([ids[0], ids[1], ids[2]]);
                    }
                }
            } else {
                let n = 1usize << subdivision;
                for e in 0..layout.disp_elements.len() {
                    // Row-major grid of points (i, j) with i + j ≤ n.
                    let mut row_start = Vec::with_capacity(n + 1);
                    for j in 0..=n {
                        row_start.push(samples.len());
                        for i in 0..=(n - j) {
                            samples.push(Sample {
                                shell: s,
                                elem: e,
                                xi: [i as f64 / n as f64, j as f64 / n as f64],
                            });
                        }
                    }
                    let at = |i: usize, j: usize| row_start[j] + i;
                    for j in 0..n {
                        for i in 0..(n - j) {
                            triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                            if i + j + 1 < n {
                                triangles.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                            }
                        }
                    }
                }
            }
        }
        Self { samples, triangles }
    }

    /// Number of output points.
    pub fn n_points(&self) -> usize {
        self.samples.len()
    }

    /// The frame of a state at time `t`.
    pub fn frame(&self, layouts: &[ShellLayout], state: &SystemState, t: f64) -> VtuFrame {
        let mut columns = PointColumns::with_capacity(self.samples.len());
        for s in &self.samples {
            let layout = &layouts[s.shell];
            let el = &layout.disp_elements[s.elem];
            let weights: Vec<f64> = if el.len() == 6 {
                Tri6::values(s.xi).iter().copied().collect()
            } else {
                Tri3::values(s.xi).iter().copied().collect()
            };
            let mut x = Vector3::zeros();
            let mut rest = Vector3::zeros();
            let mut v = Vector3::zeros();
            for (&node, w) in el.iter().zip(&weights) {
                x += state.x[node] * *w;
                v += state.v[node] * *w;
                rest += layout.rest_disp_positions[node - layout.disp_nodes.start] * *w;
            }
            let rel = &layout.rot_elements[s.elem];
            let rw: Vec<f64> = if rel.len() == 6 {
                Tri6::values(s.xi).iter().copied().collect()
            } else {
                Tri3::values(s.xi).iter().copied().collect()
            };
            let reference = state.q[rel[0]];
            let mut q = Quaternion::new(0.0, 0.0, 0.0, 0.0);
            let mut w_ang = Vector3::zeros();
            for (&k, w) in rel.iter().zip(&rw) {
                q += same_hemisphere(&state.q[k], &reference) * *w;
                w_ang += state.omega[k] * *w;
            }
            columns.push(&x, &rest, &v, &rotation_matrix(&q.normalize()), &w_ang);
        }
        columns.into_frame(self.triangles.clone(), t)
    }
}

/// The point data of a shell frame, one entry per output point: position, displacement, velocity, the
/// three directors and the angular velocity (the output contract of architecture.md).
pub(crate) struct PointColumns {
    points: Vec<[f64; 3]>,
    displacement: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    directors: [Vec<[f64; 3]>; 3],
    omega: Vec<[f64; 3]>,
}

impl PointColumns {
    /// Empty columns for `n` points.
    pub(crate) fn with_capacity(n: usize) -> Self {
        Self {
            points: Vec::with_capacity(n),
            displacement: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            directors: std::array::from_fn(|_| Vec::with_capacity(n)),
            omega: Vec::with_capacity(n),
        }
    }

    /// Appends one point: position `x`, rest position, velocity, director frame `r` (columns d₁, d₂,
    /// d₃) and angular velocity.
    pub(crate) fn push(
        &mut self,
        x: &Vector3<f64>,
        rest: &Vector3<f64>,
        v: &Vector3<f64>,
        r: &nalgebra::Matrix3<f64>,
        omega: &Vector3<f64>,
    ) {
        let u = x - rest;
        self.points.push([x.x, x.y, x.z]);
        self.displacement.push([u.x, u.y, u.z]);
        self.velocity.push([v.x, v.y, v.z]);
        for (k, d) in self.directors.iter_mut().enumerate() {
            d.push([r[(0, k)], r[(1, k)], r[(2, k)]]);
        }
        self.omega.push([omega.x, omega.y, omega.z]);
    }

    /// The frame at time `t` over `triangles`.
    pub(crate) fn into_frame(self, triangles: Vec<[usize; 3]>, t: f64) -> VtuFrame {
        let mut frame = VtuFrame::new(self.points, triangles, t);
        frame.point_data = vec![
            DataArray::vectors("displacement", &self.displacement),
            DataArray::vectors("velocity", &self.velocity),
            DataArray::vectors("director1", &self.directors[0]),
            DataArray::vectors("director2", &self.directors[1]),
            DataArray::vectors("director3", &self.directors[2]),
            DataArray::vectors("angular_velocity", &self.omega),
        ];
        frame
    }
}

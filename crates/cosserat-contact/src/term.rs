//! Frictional contact as a term of the incremental potential: barrier energy of the candidate pairs plus
//! the lagged friction potential, in the end-of-step velocity unknowns.
//!
//! Per step the time stepper calls [`ContactTerm::begin_step`] (candidate pairs from the predicted swept
//! motion, lagged friction data from the start-of-step configuration), then Newton evaluates the term
//! through [`PotentialTerm`] and limits every step with [`ContactTerm::max_step_fraction`] (CCD over all
//! primitives, not only the candidates), and [`PotentialTerm::commit`] advances kinematic obstacles.
//! Positions of displacement nodes are `x = xⁿ + Δt v`, so gradients and Hessians with respect to the
//! unknowns are `Δt` and `Δt²` times those with respect to positions; obstacle vertices sit at their
//! end-of-step positions and carry no unknowns. Pair kernels run in parallel and are summed in pair
//! order (`cosserat_assembly::parallel::ordered_map`), so results are bit-identical for any number of
//! threads.

use crate::barrier::{Barrier, positive};
use crate::broad_phase::CandidatePairs;
use crate::candidate_cache::CandidateCache;
use crate::ccd::{distance_change_bound, edge_edge_ccd, point_triangle_ccd};
use crate::error::ContactError;
use crate::friction::FrictionSmoothing;
use crate::jet::PairJet;
use crate::mesh::{ContactMesh, ContactSurface, Obstacle, VertexSource};
use crate::mollifier::Mollifier;
use crate::pair::{ContactPair, FrictionPair, PairKind, project_psd};
use crate::parameters::ContactParameters;
use crate::stats::{ContactStats, Coverage};
use cosserat_assembly::parallel::{ChunkBuffers, ordered_map};
use cosserat_assembly::term::{Evaluation, PotentialTerm};
use cosserat_assembly::{AssemblyError, DofLayout, Parallelism, SparsityPattern, SystemState};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::sync::Mutex;
use std::time::Instant;

/// The contact term.
#[derive(Debug)]
pub struct ContactTerm {
    mesh: ContactMesh,
    params: ContactParameters,
    barrier: Barrier,
    obstacle_start: Vec<Vec<Vector3<f64>>>,
    obstacle_end: Vec<Vec<Vector3<f64>>>,
    edge_rest_length2: Vec<f64>,
    candidates: CandidatePairs,
    pairs: Vec<ContactPair>,
    friction_pairs: Vec<FrictionPair>,
    smoothing: FrictionSmoothing,
    known_block_pairs: BTreeSet<(usize, usize)>,
    pattern_stale: bool,
    parallelism: Parallelism,
    stats: Mutex<ContactStats>,
    cache: Mutex<CandidateCache>,
    values: Mutex<ChunkBuffers<(f64, f64)>>,
    jets: Mutex<ChunkBuffers<Option<PairJet>>>,
}

/// Everything one evaluation needs, gathered once.
struct Frame<'a> {
    positions: Vec<Vector3<f64>>,
    layout: &'a DofLayout,
    u: &'a [f64],
    dt: f64,
}

impl ContactTerm {
    /// The contact term of shell `surfaces` (triangles over global displacement nodes with rest
    /// positions `rest_positions`) and `obstacles`.
    ///
    /// # Errors
    /// Invalid parameters or meshes ([`ContactError`] names the body, triangle and vertex).
    pub fn try_new(
        surfaces: Vec<ContactSurface>,
        obstacles: Vec<Obstacle>,
        params: ContactParameters,
        rest_positions: &[Vector3<f64>],
    ) -> Result<Self, ContactError> {
        params.validate()?;
        let barrier = Barrier::try_new(params.stiffness, params.barrier_width)?;
        if let Some(v) = rest_positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(ContactError::NonFinite {
                what: "rest position",
                vertex: v,
            });
        }
        let mesh = ContactMesh::try_new(&surfaces, &obstacles, rest_positions.len())?;
        let obstacle_start: Vec<Vec<Vector3<f64>>> = obstacles.iter().map(|o| o.positions.clone()).collect();
        let rest = mesh.positions(|i| rest_positions[i], |o, v| obstacle_start[o][v]);
        let edge_rest_length2: Vec<f64> = mesh
            .edges()
            .iter()
            .map(|e| (rest[e[1] as usize] - rest[e[0] as usize]).norm_squared())
            .collect();
        let cache = CandidateCache::new(
            params.barrier_width + params.candidate_margin,
            median(&edge_rest_length2).sqrt(),
        );
        Ok(Self {
            mesh,
            barrier,
            obstacle_end: obstacle_start.clone(),
            obstacle_start,
            edge_rest_length2,
            candidates: CandidatePairs::default(),
            pairs: Vec::new(),
            friction_pairs: Vec::new(),
            smoothing: FrictionSmoothing::new(params.stick_velocity, 1.0),
            params,
            known_block_pairs: BTreeSet::new(),
            pattern_stale: false,
            parallelism: Parallelism::Rayon,
            stats: Mutex::new(ContactStats::default()),
            cache: Mutex::new(cache),
            values: Mutex::new(ChunkBuffers::new()),
            jets: Mutex::new(ChunkBuffers::new()),
        })
    }

    /// The contact geometry.
    pub fn mesh(&self) -> &ContactMesh {
        &self.mesh
    }

    /// The parameters.
    pub fn parameters(&self) -> &ContactParameters {
        &self.params
    }

    /// The barrier.
    pub fn barrier(&self) -> &Barrier {
        &self.barrier
    }

    /// The candidate pairs of the current step.
    pub fn pairs(&self) -> &[ContactPair] {
        &self.pairs
    }

    /// The lagged friction pairs of the current step.
    pub fn friction_pairs(&self) -> &[FrictionPair] {
        &self.friction_pairs
    }

    /// Whether the broad phases and CCD run on the rayon pool (default) or on the calling thread.
    /// Evaluations follow the potential's own setting.
    pub fn set_parallelism(&mut self, parallelism: Parallelism) {
        self.parallelism = parallelism;
    }

    /// A copy of the counters.
    pub fn stats(&self) -> ContactStats {
        *self.stats.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Positions of obstacle `obstacle` at the start of the step \[m\].
    ///
    /// # Panics
    /// If the obstacle does not exist.
    #[track_caller]
    pub fn obstacle_positions(&self, obstacle: usize) -> &[Vector3<f64>] {
        &self.obstacle_start[obstacle]
    }

    /// Sets the end-of-step positions of a kinematic obstacle (before [`ContactTerm::begin_step`]); they
    /// become its start positions at [`PotentialTerm::commit`]. Static obstacles need no call.
    ///
    /// # Errors
    /// [`ContactError::NoSuchObstacle`], [`ContactError::WrongLength`], [`ContactError::NonFinite`].
    pub fn set_obstacle_positions(
        &mut self,
        obstacle: usize,
        positions: Vec<Vector3<f64>>,
    ) -> Result<(), ContactError> {
        let n_obstacles = self.obstacle_end.len();
        let slot = self
            .obstacle_end
            .get_mut(obstacle)
            .ok_or(ContactError::NoSuchObstacle { obstacle, n_obstacles })?;
        if positions.len() != slot.len() {
            return Err(ContactError::WrongLength {
                what: "obstacle positions",
                expected: slot.len(),
                got: positions.len(),
            });
        }
        if let Some(v) = positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(ContactError::NonFinite {
                what: "obstacle position",
                vertex: v,
            });
        }
        *slot = positions;
        Ok(())
    }

    /// Contact-vertex positions with nodes at `xⁿ + scale Δt u` and obstacles at their end positions
    /// (`end = true`) or start positions.
    fn vertex_positions(
        &self,
        state: &SystemState,
        layout: &DofLayout,
        u: Option<&[f64]>,
        scale_dt: f64,
        end: bool,
    ) -> Vec<Vector3<f64>> {
        let obstacles = if end { &self.obstacle_end } else { &self.obstacle_start };
        self.mesh.positions(
            |i| match u {
                Some(u) => state.x[i] + layout.velocity(u, i) * scale_dt,
                None => state.x[i],
            },
            |o, v| obstacles[o][v],
        )
    }

    fn check_inputs(&self, state: &SystemState, layout: &DofLayout, u: &[f64], dt: f64) -> Result<(), ContactError> {
        positive("dt", dt)?;
        if u.len() != layout.n_dofs() {
            return Err(ContactError::WrongLength {
                what: "unknowns",
                expected: layout.n_dofs(),
                got: u.len(),
            });
        }
        let needed = self.mesh.vertices().iter().filter_map(|v| match v {
            VertexSource::Node(i) => Some(*i),
            VertexSource::Obstacle { .. } => None,
        });
        let n = needed.max().map_or(0, |m| m + 1);
        if state.x.len() < n || layout.n_disp_nodes < n {
            return Err(ContactError::WrongLength {
                what: "displacement nodes of the state",
                expected: n,
                got: state.x.len().min(layout.n_disp_nodes),
            });
        }
        if let Some(i) = (0..n).find(|&i| !state.x[i].iter().all(|c| c.is_finite())) {
            return Err(ContactError::NonFinite {
                what: "start-of-step position",
                vertex: i,
            });
        }
        if let Some(k) = (0..3 * n).find(|&k| !u[3 * layout.disp_block(k / 3) + k % 3].is_finite()) {
            return Err(ContactError::NonFinite {
                what: "unknowns",
                vertex: k / 3,
            });
        }
        Ok(())
    }

    fn make_pair(&self, kind: PairKind, primitives: [u32; 2]) -> ContactPair {
        let bodies = self.mesh.bodies();
        let (vertices, b0, b1, mollifier) = match kind {
            PairKind::PointTriangle => {
                let (v, t) = (primitives[0], primitives[1] as usize);
                let tri = self.mesh.triangles()[t];
                let bv = self.mesh.vertex_body(v as usize);
                ([v, tri[0], tri[1], tri[2]], bv, self.mesh.triangle_body(t), None)
            }
            PairKind::EdgeEdge => {
                let (e, f) = (primitives[0] as usize, primitives[1] as usize);
                let (ea, eb) = (self.mesh.edges()[e], self.mesh.edges()[f]);
                let m = Mollifier::from_rest_lengths(self.edge_rest_length2[e], self.edge_rest_length2[f]);
                (
                    [ea[0], ea[1], eb[0], eb[1]],
                    self.mesh.edge_body(e),
                    self.mesh.edge_body(f),
                    Some(m),
                )
            }
        };
        ContactPair {
            kind,
            vertices,
            primitives,
            thickness: bodies[b0].thickness + bodies[b1].thickness,
            mollifier,
            friction: self.params.friction.get(bodies[b0].id, bodies[b1].id),
        }
    }

    fn block_of(&self, layout: &DofLayout, v: u32) -> Option<usize> {
        self.mesh.node(v as usize).map(|i| layout.disp_block(i))
    }

    /// Starts a step from `state` with time step `dt` and predicted unknowns `u` (e.g. the initial guess
    /// of Newton): finds the candidate pairs over the predicted motion `xⁿ → xⁿ + s Δt v` (`s` the sweep
    /// factor, obstacles from their start to their end positions, boxes inflated by thickness, barrier
    /// width and margin; box overlaps are kept only if the distance can drop that far given the rate
    /// bound of the motion) and the lagged friction data at `xⁿ`.
    ///
    /// Returns whether the set of coupled node blocks grew since the last [`PotentialTerm::bind`]
    /// ([`ContactTerm::fits_pattern`] tells exactly whether a given pattern still suffices): the
    /// Hessian's pattern must then be rebuilt (from [`PotentialTerm::coupling_groups`], the union of all
    /// block pairs coupled so far) before the next Hessian evaluation, which otherwise panics on the
    /// missing block. Call it again whenever `dt` changes (step retries).
    ///
    /// # Errors
    /// Wrong lengths, a non-positive `dt`, non-finite positions, or a candidate pair whose gap at the
    /// start of the step is not positive ([`ContactError::Intersection`]).
    pub fn begin_step(
        &mut self,
        state: &SystemState,
        layout: &DofLayout,
        dt: f64,
        u: &[f64],
    ) -> Result<bool, ContactError> {
        self.check_inputs(state, layout, u, dt)?;
        let clock = Instant::now();
        let start = self.vertex_positions(state, layout, None, 0.0, false);
        let end = self.vertex_positions(state, layout, Some(u), self.params.sweep_factor * dt, true);
        let reach = self.params.barrier_width + self.params.candidate_margin;
        let candidates = self.candidate_pairs(&start, &end, reach);
        let broad = clock.elapsed();
        // Keep the box overlaps that can really come within reach: the distance can drop by at most
        // the rate bound of the swept motion.
        let mut candidates = candidates;
        let mut pairs = Vec::with_capacity(candidates.len());
        let gather = |pair: &ContactPair| pair.vertices.map(|v| start[v as usize]);
        for kind in [PairKind::PointTriangle, PairKind::EdgeEdge] {
            let list = match kind {
                PairKind::PointTriangle => &mut candidates.point_triangle,
                PairKind::EdgeEdge => &mut candidates.edge_edge,
            };
            let mut kept = Vec::with_capacity(list.len());
            for &p in list.iter() {
                let pair = self.make_pair(kind, p);
                let x = gather(&pair);
                let dx = pair.vertices.map(|v| end[v as usize] - start[v as usize]);
                let d = pair.classify(&x).1.sqrt();
                let gap = d - pair.thickness;
                if !(gap > 0.0) {
                    return Err(ContactError::Intersection {
                        kind: pair.kind.name(),
                        first: pair.primitives[0] as usize,
                        second: pair.primitives[1] as usize,
                        gap,
                        distance: d,
                        thickness: pair.thickness,
                    });
                }
                if gap - distance_change_bound(&dx, kind == PairKind::PointTriangle) < reach {
                    kept.push(p);
                    pairs.push(pair);
                }
            }
            *list = kept;
        }
        self.friction_pairs = pairs
            .iter()
            .filter_map(|pair| FrictionPair::from_lagged(pair, &gather(pair), &self.barrier))
            .collect();
        self.smoothing = FrictionSmoothing::new(self.params.stick_velocity, dt);
        for pair in &pairs {
            let blocks = pair.vertices.map(|v| self.block_of(layout, v));
            for a in blocks.iter().flatten() {
                for b in blocks.iter().flatten() {
                    if a < b && self.known_block_pairs.insert((*a, *b)) {
                        self.pattern_stale = true;
                    }
                }
            }
        }
        self.candidates = candidates;
        self.pairs = pairs;
        let mut stats = self.stats.lock().unwrap_or_else(|e| e.into_inner());
        stats.n_candidates = self.pairs.len();
        stats.n_friction = self.friction_pairs.len();
        stats.broad_phase_time += broad;
        Ok(self.pattern_stale)
    }

    /// The global displacement nodes of each candidate pair (obstacle vertices left out; their slots
    /// repeat a node of the same pair), for the sparsity pattern.
    pub fn coupled_node_quads(&self) -> Vec<[usize; 4]> {
        self.pairs
            .iter()
            .filter_map(|pair| {
                let nodes: Vec<usize> = pair.vertices.iter().filter_map(|&v| self.mesh.node(v as usize)).collect();
                let first = *nodes.first()?;
                Some(std::array::from_fn(|k| nodes.get(k).copied().unwrap_or(first)))
            })
            .collect()
    }

    /// The pairs of blocks the candidates of the run so far have coupled (the term's share of the
    /// Hessian's pattern, which only grows).
    pub fn block_pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.known_block_pairs.iter().copied()
    }

    /// Restores the coupled block pairs and the obstacles' positions of a committed state (to resume a
    /// run from a checkpoint); the potential's dynamic pattern must be rebuilt afterwards.
    ///
    /// # Errors
    /// [`ContactError::WrongLength`] when the obstacles or their vertices do not match.
    pub fn restore(
        &mut self,
        block_pairs: impl IntoIterator<Item = (usize, usize)>,
        obstacles: Vec<Vec<Vector3<f64>>>,
    ) -> Result<(), ContactError> {
        let fits = obstacles.len() == self.obstacle_start.len()
            && obstacles.iter().zip(&self.obstacle_start).all(|(a, b)| a.len() == b.len());
        if !fits {
            return Err(ContactError::WrongLength {
                what: "obstacle positions",
                expected: self.obstacle_start.iter().map(Vec::len).sum(),
                got: obstacles.iter().map(Vec::len).sum(),
            });
        }
        self.known_block_pairs = block_pairs.into_iter().collect();
        self.pattern_stale = true;
        self.obstacle_end.clone_from(&obstacles);
        self.obstacle_start = obstacles;
        Ok(())
    }

    /// Whether `pattern` couples every pair of blocks the candidates couple.
    pub fn fits_pattern(&self, pattern: &SparsityPattern) -> bool {
        self.known_block_pairs
            .iter()
            .all(|&(a, b)| b < pattern.n_blocks() && pattern.block_position(a, b).is_some())
    }

    /// CCD of all primitives moving linearly from `x0` to `x1`: the smallest safe fraction over every pair
    /// found by a swept broad phase (reach `d̂`).
    fn ccd_fraction(&self, x0: &[Vector3<f64>], x1: &[Vector3<f64>]) -> f64 {
        if x0.iter().chain(x1).any(|p| !p.iter().all(|c| c.is_finite())) {
            return 0.0;
        }
        let clock = Instant::now();
        let found = self.candidate_pairs(x0, x1, self.params.barrier_width);
        let broad = clock.elapsed();
        let clock = Instant::now();
        let settings = &self.params.ccd;
        let pair_fraction = |kind: PairKind, p: [u32; 2]| {
            let pair = self.make_pair(kind, p);
            let a: [Vector3<f64>; 4] = pair.vertices.map(|v| x0[v as usize]);
            let d: [Vector3<f64>; 4] = pair.vertices.map(|v| x1[v as usize] - x0[v as usize]);
            match kind {
                PairKind::PointTriangle => point_triangle_ccd(&a, &d, pair.thickness, settings),
                PairKind::EdgeEdge => edge_edge_ccd(&a, &d, pair.thickness, settings),
            }
        };
        let items: Vec<(PairKind, [u32; 2])> = found
            .point_triangle
            .iter()
            .map(|&p| (PairKind::PointTriangle, p))
            .chain(found.edge_edge.iter().map(|&p| (PairKind::EdgeEdge, p)))
            .collect();
        let alpha = match self.parallelism {
            Parallelism::Sequential => items.iter().map(|&(k, p)| pair_fraction(k, p)).fold(1.0, f64::min),
            Parallelism::Rayon => items
                .par_iter()
                .with_min_len(64)
                .map(|&(k, p)| pair_fraction(k, p))
                .reduce(|| 1.0, f64::min),
        };
        let mut stats = self.stats.lock().unwrap_or_else(|e| e.into_inner());
        stats.n_ccd_queries += 1;
        stats.broad_phase_time += broad;
        stats.ccd_time += clock.elapsed();
        alpha
    }

    /// The largest safe fraction `α ∈ [0, 1]` of the Newton step `du` from the unknowns `u`: along
    /// `xⁿ + Δt (u + α' du)`, `α' ∈ [0, α]`, no pair of primitives (all of them, not only candidates)
    /// gets closer than `min(s g₀, d̂)` above its thickness, with `g₀` its gap at `u` and `s` the CCD
    /// fraction (pairs never within `d̂` are not limited). Obstacles stay at their end positions.
    /// Returns 0 for invalid input (wrong lengths, non-finite values) or an infeasible start.
    pub fn max_step_fraction(&self, state: &SystemState, layout: &DofLayout, u: &[f64], du: &[f64], dt: f64) -> f64 {
        if self.check_inputs(state, layout, u, dt).is_err() || du.len() != u.len() {
            return 0.0;
        }
        let x0 = self.vertex_positions(state, layout, Some(u), dt, true);
        let u1: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + b).collect();
        let x1 = self.vertex_positions(state, layout, Some(&u1), dt, true);
        let alpha = self.ccd_fraction(&x0, &x1);
        let mut stats = self.stats.lock().unwrap_or_else(|e| e.into_inner());
        stats.n_step_limits += 1;
        stats.step_fraction_sum += alpha;
        stats.n_step_cuts += usize::from(alpha < 1.0);
        alpha
    }

    /// The safe fraction of each obstacle's motion from its start to its end positions, with the nodes
    /// held at `xⁿ` and the other obstacles at their start (a static obstacle's fraction is 1). Each
    /// obstacle is checked alone because obstacles never interact with one another: one obstacle
    /// blocked by a shell must not hold back the others. Below 1, the start of the step is infeasible
    /// for that obstacle's target and its motion must be shortened (with new end positions).
    pub fn obstacle_motion_fractions(&self, state: &SystemState) -> Vec<f64> {
        let layout = DofLayout {
            n_disp_nodes: state.x.len(),
            n_rot_nodes: 0,
        };
        let x0 = self.vertex_positions(state, &layout, None, 0.0, false);
        (0..self.obstacle_end.len())
            .map(|k| {
                if self.obstacle_end[k] == self.obstacle_start[k] {
                    return 1.0;
                }
                let x1 = self.mesh.positions(
                    |i| state.x[i],
                    |o, v| {
                        if o == k {
                            self.obstacle_end[o][v]
                        } else {
                            self.obstacle_start[o][v]
                        }
                    },
                );
                self.ccd_fraction(&x0, &x1)
            })
            .collect()
    }

    /// All pairs within reach at `x = xⁿ + Δt u` (obstacles at their end positions): the smallest gap,
    /// how many pairs are active and how many of those are not candidates of the current step (then
    /// [`ContactTerm::begin_step`] must be called again with `u` and the step repeated).
    pub fn coverage(&self, state: &SystemState, layout: &DofLayout, u: &[f64], dt: f64) -> Coverage {
        let mut out = Coverage {
            min_gap: f64::INFINITY,
            n_active: 0,
            n_uncovered: 0,
        };
        if self.check_inputs(state, layout, u, dt).is_err() {
            out.min_gap = f64::NAN;
            return out;
        }
        let x = self.vertex_positions(state, layout, Some(u), dt, true);
        let found = self.candidate_pairs(&x, &x, self.params.barrier_width);
        let lists = [
            (
                PairKind::PointTriangle,
                &found.point_triangle,
                &self.candidates.point_triangle,
            ),
            (PairKind::EdgeEdge, &found.edge_edge, &self.candidates.edge_edge),
        ];
        for (kind, pairs, known) in lists {
            for &p in pairs {
                let pair = self.make_pair(kind, p);
                let gap = pair.gap(&pair.vertices.map(|v| x[v as usize]));
                out.min_gap = out.min_gap.min(gap);
                if self.barrier.is_active(gap) {
                    out.n_active += 1;
                    if known.binary_search(&p).is_err() {
                        out.n_uncovered += 1;
                    }
                }
            }
        }
        out
    }

    /// The candidate pairs of the motion `start → end` within `reach` (see [`CandidateCache`]).
    fn candidate_pairs(&self, start: &[Vector3<f64>], end: &[Vector3<f64>], reach: f64) -> CandidatePairs {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        let found = cache.candidate_pairs(&self.mesh, start, end, reach, self.parallelism);
        self.stats.lock().unwrap_or_else(|e| e.into_inner()).cache = cache.counters();
        found
    }

    fn frame<'a>(&self, eval: &Evaluation<'a>) -> Frame<'a> {
        Frame {
            positions: self.vertex_positions(eval.state, eval.layout, Some(eval.u), eval.dt, true),
            layout: eval.layout,
            u: eval.u,
            dt: eval.dt,
        }
    }

    fn gather(frame: &Frame<'_>, vertices: &[u32; 4]) -> [Vector3<f64>; 4] {
        vertices.map(|v| frame.positions[v as usize])
    }

    /// Displacements over the step: `Δt v` for nodes, end minus start for obstacle vertices.
    fn displacements(&self, frame: &Frame<'_>, vertices: &[u32; 4]) -> [Vector3<f64>; 4] {
        vertices.map(|v| match self.mesh.vertices()[v as usize] {
            VertexSource::Node(i) => frame.layout.velocity(frame.u, i) * frame.dt,
            VertexSource::Obstacle { obstacle, vertex } => {
                self.obstacle_end[obstacle][vertex] - self.obstacle_start[obstacle][vertex]
            }
        })
    }

    /// A pair whose gap is not positive (or whose energy is not finite): an infeasible trial state, which
    /// the Newton line search backs off from.
    fn non_finite(&self, kind: PairKind, index: usize) -> AssemblyError {
        let pair = match kind {
            PairKind::PointTriangle => "point-triangle pair",
            PairKind::EdgeEdge => "edge-edge pair",
        };
        AssemblyError::Infeasible {
            term: self.name(),
            reason: format!("{pair} {index} touches or crosses (no positive gap)"),
        }
    }

    fn record(&self, clock: Instant, active: usize, min_gap: f64) {
        let mut stats = self.stats.lock().unwrap_or_else(|e| e.into_inner());
        stats.n_evaluations += 1;
        stats.n_active = active;
        stats.min_gap = min_gap;
        stats.energy_time += clock.elapsed();
    }

    /// Adds `dt ∇` and `dt² ∇²` of a pair jet into the global arrays.
    fn scatter(
        &self,
        frame: &Frame<'_>,
        vertices: &[u32; 4],
        jet: &PairJet,
        project: bool,
        grad: &mut [f64],
        hessian: &mut Option<(&SparsityPattern, &mut [f64])>,
    ) {
        let blocks = vertices.map(|v| self.block_of(frame.layout, v));
        let dt = frame.dt;
        for (i, b) in blocks.iter().enumerate() {
            if let Some(b) = b {
                for c in 0..3 {
                    grad[3 * b + c] += dt * jet.gradient[3 * i + c];
                }
            }
        }
        let Some((pattern, values)) = hessian.as_mut() else {
            return;
        };
        let h = if project {
            project_psd(&jet.hessian, blocks.map(|b| b.is_some()))
        } else {
            jet.hessian
        };
        let dt2 = dt * dt;
        for i in 0..4 {
            for j in 0..4 {
                let (Some(a), Some(b)) = (blocks[i], blocks[j]) else {
                    continue;
                };
                if a > b || (a == b && i > j) {
                    continue;
                }
                let k = pattern
                    .block_position(a, b)
                    .expect("contact block pair missing from the pattern: rebuild it after begin_step");
                for c in 0..3 {
                    let start = pattern.col_start(3 * b + c) + 3 * k;
                    let rows = if a == b { c + 1 } else { 3 };
                    for r in 0..rows {
                        values[start + r] += dt2 * h[(3 * i + r, 3 * j + c)];
                    }
                }
            }
        }
    }

    fn assemble(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        mut hessian: Option<(&SparsityPattern, &mut [f64])>,
    ) -> Result<f64, AssemblyError> {
        let clock = Instant::now();
        let frame = self.frame(eval);
        let mut total = 0.0;
        let (mut active, mut min_gap) = (0, f64::INFINITY);
        {
            let mut buffers = self.jets.lock().unwrap_or_else(|e| e.into_inner());
            ordered_map(
                self.pairs.len(),
                eval.parallelism,
                &mut buffers,
                || None,
                |p, slot| {
                    let pair = &self.pairs[p];
                    *slot = pair.energy_jet(&Self::gather(&frame, &pair.vertices), &self.barrier);
                },
                |p, jet| {
                    let Some(jet) = jet else { return Ok(()) };
                    let pair = &self.pairs[p];
                    if !jet.is_finite() {
                        return Err(self.non_finite(pair.kind, p));
                    }
                    active += 1;
                    total += jet.value;
                    self.scatter(&frame, &pair.vertices, jet, self.params.project_pd, grad, &mut hessian);
                    Ok(())
                },
            )?;
        }
        for pair in &self.pairs {
            min_gap = min_gap.min(pair.gap(&Self::gather(&frame, &pair.vertices)));
        }
        for (p, fp) in self.friction_pairs.iter().enumerate() {
            let jet = fp.energy_jet(&self.displacements(&frame, &fp.vertices), &self.smoothing);
            if !jet.is_finite() {
                return Err(AssemblyError::NonFinite {
                    term: self.name(),
                    location: "friction pair",
                    index: p,
                });
            }
            total += jet.value;
            self.scatter(&frame, &fp.vertices, &jet, false, grad, &mut hessian);
        }
        self.record(clock, active, min_gap);
        Ok(total)
    }
}

impl PotentialTerm for ContactTerm {
    fn name(&self) -> String {
        "contact".into()
    }

    fn is_dynamic(&self) -> bool {
        true
    }

    fn begin_step(
        &mut self,
        state: &SystemState,
        layout: &DofLayout,
        dt: f64,
        u: &[f64],
    ) -> Result<bool, AssemblyError> {
        ContactTerm::begin_step(self, state, layout, dt, u).map_err(|e| AssemblyError::Infeasible {
            term: self.name(),
            reason: e.to_string(),
        })
    }

    fn needs_resolve(&self, eval: &Evaluation<'_>) -> bool {
        self.coverage(eval.state, eval.layout, eval.u, eval.dt).n_uncovered > 0
    }

    fn max_step_fraction(&self, eval: &Evaluation<'_>, du: &[f64]) -> f64 {
        ContactTerm::max_step_fraction(self, eval.state, eval.layout, eval.u, du, eval.dt)
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        self.known_block_pairs.iter().map(|&(a, b)| vec![a, b]).collect()
    }

    fn bind(&mut self, _pattern: &SparsityPattern) {
        self.pattern_stale = false;
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        let clock = Instant::now();
        let frame = self.frame(eval);
        let mut total = 0.0;
        let (mut active, mut min_gap) = (0, f64::INFINITY);
        {
            let mut buffers = self.values.lock().unwrap_or_else(|e| e.into_inner());
            ordered_map(
                self.pairs.len(),
                eval.parallelism,
                &mut buffers,
                || (0.0, 0.0),
                |p, slot| {
                    let pair = &self.pairs[p];
                    let x = Self::gather(&frame, &pair.vertices);
                    *slot = (pair.energy(&x, &self.barrier), pair.gap(&x));
                },
                |p, &(e, gap)| {
                    if !e.is_finite() {
                        return Err(self.non_finite(self.pairs[p].kind, p));
                    }
                    min_gap = min_gap.min(gap);
                    if self.barrier.is_active(gap) {
                        active += 1;
                    }
                    total += e;
                    Ok(())
                },
            )?;
        }
        for (p, fp) in self.friction_pairs.iter().enumerate() {
            let e = fp.energy(&self.displacements(&frame, &fp.vertices), &self.smoothing);
            if !e.is_finite() {
                return Err(AssemblyError::NonFinite {
                    term: self.name(),
                    location: "friction pair",
                    index: p,
                });
            }
            total += e;
        }
        self.record(clock, active, min_gap);
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

    fn commit(&mut self, _state: &mut SystemState, _layout: &DofLayout, _u: &[f64], _dt: f64) {
        self.obstacle_start.clone_from(&self.obstacle_end);
    }

    fn active_energy_terms(&self) -> Vec<String> {
        let mut names = vec!["contact_barrier".to_string()];
        if self.params.friction.any() {
            names.push("contact_friction".to_string());
        }
        names
    }
}

/// The median of a non-empty list (0 for an empty one).
fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

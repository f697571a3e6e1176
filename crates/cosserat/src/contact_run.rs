//! Contact in a simulation: the contact term built from a scene's [`ContactSpec`] and the model's
//! contact triangles, the kinematic obstacles it moves before every step, the statistics a run
//! collects about it (active pairs, the smallest gap reached, the time spent in contact energies,
//! broad phases and CCD), and the queries of the contact state that tests and studies ask.
//!
//! A scene without a `[contact]` section builds none of this. Shells contribute their displacement
//! elements as flat triangles: a Tri3 element as it is, a Tri6 element split into four through its
//! mid-edge nodes (node order: corners 0, 1, 2, then mid-edges 3 = (0, 1), 4 = (1, 2), 5 = (2, 0)).
//! Surface ids are the shell indices, obstacle ids follow them, so friction coefficients between named
//! bodies map onto the term's friction table.

use crate::error::SimulationError;
use crate::model::Model;
use cosserat_assembly::term::{Evaluation, NodeRotations};
use cosserat_assembly::{IncrementalPotential, Parallelism, PotentialTerm, TermHandle};
use cosserat_contact::{ContactParameters, ContactStats, ContactSurface, ContactTerm, Coverage, Obstacle};
use cosserat_geometry::Num;
use cosserat_io::{BroadPhaseRecord, ContactRecord, DataArray, VtuFrame};
use cosserat_scene::spec::{ContactBody, ContactSpec, MotionSpec, SurfaceMesh};
use nalgebra::Vector3;

/// The flat contact triangles of displacement elements (3 or 6 nodes each, corners first): Tri3
/// elements as they are, Tri6 elements split into four through their mid-edge nodes.
pub fn surface_triangles(elements: &[Vec<usize>]) -> Vec<[usize; 3]> {
    let mut out = Vec::with_capacity(4 * elements.len());
    for el in elements {
        if el.len() == 6 {
            out.extend([
                [el[0], el[3], el[5]],
                [el[3], el[1], el[4]],
                [el[5], el[4], el[2]],
                [el[3], el[4], el[5]],
            ]);
        } else {
            out.push([el[0], el[1], el[2]]);
        }
    }
    out
}

/// A contact obstacle: where it is, and its scripted motion if it moves.
#[derive(Debug)]
struct ObstacleScript {
    /// Rest positions (the motion maps these).
    rest: Vec<Vector3<f64>>,
    /// Triangles (for output frames).
    triangles: Vec<[usize; 3]>,
    motion: Option<MotionSpec>,
    /// The end-of-step positions last given to the contact term.
    current: Vec<Vector3<f64>>,
}

/// Contact statistics over the committed states of a run, from the term's counters after each step.
///
/// Newton's last evaluation of a step is at its converged state, and the step's candidate pairs cover
/// every pair within the barrier there (the time stepper solves again otherwise), so the counters of
/// that evaluation give the active pairs and the smallest gap of the committed state without another
/// broad phase.
#[derive(Debug, Clone)]
pub struct ContactMonitor {
    steps: usize,
    active_sum: usize,
    active_max: usize,
    min_gap: f64,
}

impl Default for ContactMonitor {
    fn default() -> Self {
        Self {
            steps: 0,
            active_sum: 0,
            active_max: 0,
            min_gap: f64::INFINITY,
        }
    }
}

impl ContactMonitor {
    /// Records the state a step converged to, from the term's counters.
    pub fn record(&mut self, term: &ContactTerm) {
        let s = term.stats();
        self.steps += 1;
        self.active_sum += s.n_active;
        self.active_max = self.active_max.max(s.n_active);
        if s.min_gap.is_finite() {
            self.min_gap = self.min_gap.min(s.min_gap);
        }
    }

    /// The smallest gap (distance minus the thicknesses) reached in a committed state \[m\] (`+∞`
    /// while no pair was a candidate).
    pub fn min_gap(&self) -> f64 {
        self.min_gap
    }

    /// The most pairs within the barrier in a committed state.
    pub fn max_active_pairs(&self) -> usize {
        self.active_max
    }
}

/// An obstacle's vertex positions in the contact term and in the output frames \[m\] (they differ when
/// setting a scripted position failed).
pub type ObstaclePositions = (Vec<Vector3<f64>>, Vec<Vector3<f64>>);

/// The state of a run's contact between two steps ([`ContactRun::snapshot`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactState {
    /// Block pairs coupled in the Hessian's pattern.
    pub block_pairs: Vec<(usize, usize)>,
    /// Per obstacle: its positions in the contact term and in the output frames \[m\].
    pub obstacles: Vec<ObstaclePositions>,
    /// The monitor: steps, sum and most of the active pairs, smallest gap \[m\].
    pub monitor: (usize, usize, usize, f64),
    /// The largest and the last obstacle lag \[m\].
    pub lags: (f64, f64),
    /// The contact term's counters and times since the run started.
    pub totals: ContactStats,
}

/// The contact of a run: its term in the potential, the kinematic obstacles and the statistics.
pub struct ContactRun {
    term: TermHandle<ContactTerm>,
    obstacles: Vec<ObstacleScript>,
    monitor: ContactMonitor,
    /// The largest distance of an obstacle vertex from its scripted target at the end of a step \[m\].
    max_lag: f64,
    /// The same at the end of the last step \[m\].
    last_lag: f64,
    /// The term's counters before the run was resumed (zero for a run from the start).
    earlier: ContactStats,
}

impl ContactRun {
    /// Builds the contact term of a scene and inserts it into the potential, then checks that no pair
    /// starts closer than its thickness.
    ///
    /// # Errors
    /// Invalid parameters or meshes, a shell whose model has no contact surface, or an initial state
    /// with a pair closer than its thickness.
    pub fn build(
        spec: &ContactSpec,
        model: &dyn Model,
        potential: &mut IncrementalPotential,
    ) -> Result<Self, SimulationError> {
        let n_shells = model.placements().len();
        let surfaces = spec
            .surfaces
            .iter()
            .map(|s| {
                let triangles = model.contact_triangles(s.shell).ok_or_else(|| {
                    SimulationError::Setup(format!(
                        "contact: shell `{}`: this model does not take part in contact",
                        model.placements()[s.shell].name
                    ))
                })?;
                Ok(ContactSurface {
                    id: s.shell,
                    triangles,
                    thickness: s.thickness,
                })
            })
            .collect::<Result<Vec<_>, SimulationError>>()?;
        let obstacles: Vec<Obstacle> = spec
            .obstacles
            .iter()
            .enumerate()
            .map(|(o, ob)| Obstacle {
                id: n_shells + o,
                positions: ob.positions_at(0.0),
                triangles: ob.triangles.clone(),
                thickness: ob.thickness,
            })
            .collect();
        let mut params = ContactParameters::new(spec.stiffness, spec.barrier_width);
        params.stick_velocity = spec.stick_velocity;
        params.project_pd = spec.project_pd;
        params.ccd.min_gap_fraction = spec.min_gap_fraction;
        let id = |b: ContactBody| match b {
            ContactBody::Shell(s) => s,
            ContactBody::Obstacle(o) => n_shells + o,
        };
        for f in &spec.friction {
            params.friction.set(id(f.bodies[0]), id(f.bodies[1]), f.coefficient)?;
        }
        let term = ContactTerm::try_new(surfaces, obstacles, params, model.rest_positions())?;
        let run = Self {
            term: potential.insert(term),
            obstacles: spec
                .obstacles
                .iter()
                .map(|o| ObstacleScript {
                    rest: o.positions.clone(),
                    triangles: o.triangles.clone(),
                    motion: o.motion.clone(),
                    current: o.positions_at(0.0),
                })
                .collect(),
            monitor: ContactMonitor::default(),
            max_lag: 0.0,
            last_lag: 0.0,
            earlier: ContactStats::default(),
        };
        let coverage = run.coverage(potential);
        if coverage.min_gap.is_nan() || coverage.min_gap <= 0.0 {
            return Err(SimulationError::Setup(format!(
                "contact: the initial state has a pair of contact primitives closer than their thicknesses \
                 (smallest gap {:e} m); move the bodies apart or reduce the thicknesses",
                coverage.min_gap
            )));
        }
        Ok(run)
    }

    /// Moves the kinematic obstacles to their targets at `t_end`, as far as the shells at the start of
    /// the step allow: an obstacle whose full motion would bring it closer to a shell than CCD's
    /// minimum gap goes the safe fraction of its way (the others are not held back).
    pub fn before_step(&mut self, potential: &mut IncrementalPotential, t_end: f64) {
        if self.obstacles.iter().all(|o| o.motion.is_none()) {
            return;
        }
        let (term, state, _) = potential.term_and_state_mut(self.term);
        let mut targets: Vec<Option<Vec<Vector3<f64>>>> = Vec::with_capacity(self.obstacles.len());
        for (k, o) in self.obstacles.iter().enumerate() {
            let target = o.motion.as_ref().map(|m| {
                let map = m.map_at(t_end);
                o.rest.iter().map(map).collect::<Vec<_>>()
            });
            if let Some(target) = &target
                && let Err(e) = term.set_obstacle_positions(k, target.clone())
            {
                log::warn!(
                    "obstacle {k}: its scripted position at t = {} is unusable ({e}); it stays",
                    Num(t_end)
                );
                targets.push(None);
                continue;
            }
            targets.push(target);
        }
        let fractions = term.obstacle_motion_fractions(state);
        self.last_lag = 0.0;
        for (k, (o, target)) in self.obstacles.iter_mut().zip(&targets).enumerate() {
            let Some(target) = target else { continue };
            let alpha = fractions[k];
            let start = term.obstacle_positions(k).to_vec();
            let end: Vec<Vector3<f64>> = if alpha < 1.0 {
                start.iter().zip(target).map(|(a, b)| a + (b - a) * alpha).collect()
            } else {
                target.clone()
            };
            let lag = end.iter().zip(target).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
            self.max_lag = self.max_lag.max(lag);
            self.last_lag = self.last_lag.max(lag);
            if term.set_obstacle_positions(k, end.clone()).is_ok() {
                o.current = end;
            }
        }
    }

    /// Records the committed state of a step.
    pub fn after_step(&mut self, potential: &IncrementalPotential) {
        self.monitor.record(potential.term(self.term));
    }

    /// What the next steps depend on, for a checkpoint: the couplings the candidates have added to the
    /// Hessian's pattern (it only grows, and its ordering decides the round-off of the solves), the
    /// obstacles' positions, and the statistics. Friction is lagged from the start of each step and
    /// the barrier stiffness is fixed, so neither carries state between steps.
    pub fn snapshot(&self, potential: &IncrementalPotential) -> ContactState {
        let term = self.term(potential);
        let m = &self.monitor;
        ContactState {
            block_pairs: term.block_pairs().collect(),
            obstacles: (0..self.obstacles.len())
                .map(|k| (term.obstacle_positions(k).to_vec(), self.obstacles[k].current.clone()))
                .collect(),
            monitor: (m.steps, m.active_sum, m.active_max, m.min_gap),
            lags: (self.max_lag, self.last_lag),
            totals: self.totals(potential),
        }
    }

    /// The contact term's counters and times since the run started (across a resume).
    fn totals(&self, potential: &IncrementalPotential) -> ContactStats {
        self.term(potential).stats().continuing(&self.earlier)
    }

    /// Restores a [`ContactRun::snapshot`] and rebuilds the potential's pattern with its couplings.
    ///
    /// # Errors
    /// A reason when the snapshot does not fit this scene's contact.
    pub fn restore(&mut self, potential: &mut IncrementalPotential, saved: &ContactState) -> Result<(), String> {
        let n_blocks = potential.parts.layout.n_blocks();
        if saved.block_pairs.iter().any(|&(a, b)| a >= n_blocks || b >= n_blocks) {
            return Err("the contact couplings do not fit this scene's unknowns".into());
        }
        let fits = saved.obstacles.len() == self.obstacles.len()
            && saved
                .obstacles
                .iter()
                .zip(&self.obstacles)
                .all(|((start, current), o)| start.len() == o.rest.len() && current.len() == o.rest.len());
        if !fits {
            return Err("the contact obstacles or their vertices do not match the scene's".into());
        }
        for (o, (_, current)) in self.obstacles.iter_mut().zip(&saved.obstacles) {
            o.current.clone_from(current);
        }
        let (steps, active_sum, active_max, min_gap) = saved.monitor;
        self.monitor = ContactMonitor {
            steps,
            active_sum,
            active_max,
            min_gap,
        };
        (self.max_lag, self.last_lag) = saved.lags;
        self.earlier = saved.totals;
        let starts = saved.obstacles.iter().map(|(start, _)| start.clone()).collect();
        self.term_mut(potential)
            .restore(saved.block_pairs.iter().copied(), starts)
            .map_err(|e| format!("contact: {e}"))?;
        potential.rebuild_dynamic_pattern();
        Ok(())
    }

    /// The contact term.
    pub fn term<'a>(&self, potential: &'a IncrementalPotential) -> &'a ContactTerm {
        potential.term(self.term)
    }

    /// The contact term, mutably.
    pub fn term_mut<'a>(&self, potential: &'a mut IncrementalPotential) -> &'a mut ContactTerm {
        potential.term_mut(self.term)
    }

    /// The statistics of the steps so far.
    pub fn monitor(&self) -> &ContactMonitor {
        &self.monitor
    }

    /// The run record's contact section; `step_seconds` is the time of all steps, for the shares.
    pub fn record(&self, potential: &IncrementalPotential, step_seconds: f64) -> ContactRecord {
        let term = potential.term(self.term);
        let s = self.totals(potential);
        let energy = s.energy_time.as_secs_f64();
        let ccd = s.ccd_time.as_secs_f64();
        let broad = s.broad_phase_time.as_secs_f64();
        let share = |x: f64| if step_seconds > 0.0 { x / step_seconds } else { 0.0 };
        let mesh = term.mesh();
        let m = &self.monitor;
        ContactRecord {
            n_vertices: mesh.n_vertices(),
            n_triangles: mesh.triangles().len(),
            n_edges: mesh.edges().len(),
            energy_seconds: energy,
            ccd_seconds: ccd,
            broad_phase_seconds: broad,
            share_of_step: share(energy + ccd + broad),
            energy_share: share(energy),
            ccd_share: share(ccd),
            broad_phase_share: share(broad),
            n_evaluations: s.n_evaluations,
            n_ccd_queries: s.n_ccd_queries,
            mean_step_fraction: (s.n_step_limits > 0).then(|| s.step_fraction_sum / s.n_step_limits as f64),
            n_step_cuts: s.n_step_cuts,
            broad_phase: BroadPhaseRecord {
                queries: s.cache.queries,
                requeries: s.cache.requeries,
                builds: s.cache.builds,
                uncached: s.cache.uncached,
            },
            mean_active_pairs: if m.steps > 0 {
                m.active_sum as f64 / m.steps as f64
            } else {
                0.0
            },
            max_active_pairs: m.active_max,
            min_gap: m.min_gap.is_finite().then_some(m.min_gap),
            max_obstacle_lag: self.max_lag,
            final_obstacle_lag: self.last_lag,
        }
    }

    /// Appends the obstacles to a frame: their points and triangles, the point array `obstacle` (0 for
    /// shell points, `k + 1` for obstacle `k`), displacements from their rest positions and zeros in
    /// every other point array.
    pub fn decorate_frame(&self, frame: &mut VtuFrame) {
        if self.obstacles.is_empty() {
            return;
        }
        let mut marker = vec![0.0; frame.points.len()];
        for (k, o) in self.obstacles.iter().enumerate() {
            let first = frame.points.len();
            frame.points.extend(o.current.iter().map(|p| [p.x, p.y, p.z]));
            frame.triangles.extend(o.triangles.iter().map(|t| t.map(|v| first + v)));
            marker.extend(std::iter::repeat_n((k + 1) as f64, o.current.len()));
            for array in &mut frame.point_data {
                let n = array.n_components;
                if array.name == "displacement" && n == 3 {
                    for (p, r) in o.current.iter().zip(&o.rest) {
                        array.values.extend((p - r).iter());
                    }
                } else {
                    array.values.extend(std::iter::repeat_n(0.0, n * o.current.len()));
                }
            }
        }
        frame.point_data.push(DataArray::scalars("obstacle", marker));
    }

    /// Positions of the contact vertices in the current state (shell nodes, then obstacle vertices at
    /// their start-of-step positions) and the contact triangles over them.
    pub fn geometry(&self, potential: &IncrementalPotential) -> SurfaceMesh {
        let term = potential.term(self.term);
        let state = &potential.parts.state;
        let mesh = term.mesh();
        let positions = mesh.positions(|i| state.x[i], |o, v| term.obstacle_positions(o)[v]);
        let triangles = mesh.triangles().iter().map(|t| t.map(|v| v as usize)).collect();
        (positions, triangles)
    }

    /// All contact pairs within reach of the current state: the smallest gap, the number of pairs
    /// within the barrier (a broad phase over every primitive).
    pub fn coverage(&self, potential: &IncrementalPotential) -> Coverage {
        let term = potential.term(self.term);
        let layout = &potential.parts.layout;
        let u = vec![0.0; layout.n_dofs()];
        term.coverage(&potential.parts.state, layout, &u, potential.dt())
    }

    /// Pairs of contact triangles (shells split into flat triangles, and obstacles) that intersect in
    /// the current state, by an exact-sign test over the whole mesh.
    pub fn intersections(&self, potential: &IncrementalPotential) -> Vec<(usize, usize)> {
        let (positions, triangles) = self.geometry(potential);
        cosserat_contact::intersecting_pairs(&triangles, &positions)
    }

    /// The contact force on every displacement node in the current state \[N\] (minus the gradient of
    /// the barrier energy with respect to the positions; friction acts over a step and is zero for a
    /// state at rest).
    ///
    /// # Errors
    /// [`SimulationError::Evaluation`] if the current state is infeasible for the barrier.
    pub fn forces(&self, potential: &IncrementalPotential) -> Result<Vec<Vector3<f64>>, SimulationError> {
        let term = potential.term(self.term);
        let layout = &potential.parts.layout;
        let dt = potential.dt();
        let u = vec![0.0; layout.n_dofs()];
        let rotations = NodeRotations::Matrices(vec![nalgebra::Matrix3::identity(); layout.n_rot_nodes]);
        let eval = Evaluation {
            state: &potential.parts.state,
            layout,
            u: &u,
            dt,
            rotations: &rotations,
            parallelism: Parallelism::Sequential,
        };
        let mut grad = vec![0.0; layout.n_dofs()];
        PotentialTerm::gradient(term, &eval, &mut grad)?;
        // The term's gradient is with respect to the velocity unknowns: Δt times the positional one.
        Ok((0..layout.n_disp_nodes).map(|i| -layout.velocity(&grad, i) / dt).collect())
    }
}

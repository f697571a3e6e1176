//! Checkpoints of a run and runs resumed from them ([`crate::checkpoint`]).

use super::Simulation;
use crate::checkpoint::{CHECKPOINT_DIR, Checkpoint, SCENE_COPY, STATE_FILE, SceneOrigin, StepperState, state_path};
use crate::error::SimulationError;
use crate::outcome::OutputSchedule;
use cosserat_io::RunWriter;
use cosserat_scene::spec::TimeSpec;
use cosserat_solver::{QuasiStaticSettings, QuasiStaticStepper, TimeStepper};
use std::path::Path;

impl Simulation {
    /// Says where the scene came from (the file and the overrides `KEY=VALUE`), for the checkpoints:
    /// `cosserat resume` builds the scene again from them. A scene read from a file knows its file.
    pub fn set_scene_origin(&mut self, origin: SceneOrigin) {
        self.restart.origin = Some(origin);
    }

    /// Continues the next [`Simulation::run`] from `checkpoint` instead of from the start: the state,
    /// the stepper, the counters and the outputs of the run so far are taken over, the rows and frames
    /// the earlier run wrote after the checkpoint are removed and written again, and the run ends as a
    /// run that was never stopped would have, bit for bit.
    ///
    /// # Errors
    /// [`SimulationError::Resume`] when the checkpoint was written for another scene (its fingerprint
    /// differs), another kind of run, or a system of another size.
    pub fn resume_from(&mut self, dir: &Path, checkpoint: Checkpoint) -> Result<(), SimulationError> {
        let refuse = |reason: String| SimulationError::Resume {
            path: state_path(dir),
            reason,
        };
        if checkpoint.fingerprint != self.restart.fingerprint {
            return Err(refuse(format!(
                "the scene differs from the one the checkpoint was written for (fingerprint {:08x}, now {:08x}); \
                 the checkpoint's scene file is saved as {}",
                checkpoint.fingerprint,
                self.restart.fingerprint,
                dir.join(CHECKPOINT_DIR).join(SCENE_COPY).display()
            )));
        }
        let kind_fits = matches!(
            (&checkpoint.stepper, &self.time),
            (StepperState::Dynamic { .. }, TimeSpec::Dynamic { .. })
                | (StepperState::QuasiStatic { .. }, TimeSpec::QuasiStatic { .. })
        );
        if !kind_fits {
            return Err(refuse("the checkpoint is of another kind of run".into()));
        }
        let (state, saved) = (&self.potential.parts.state, &checkpoint.state);
        let sizes = |s: &cosserat_assembly::SystemState| (s.x.len(), s.q.len(), s.q_points.len());
        if sizes(state) != sizes(saved) {
            return Err(refuse(format!(
                "the checkpoint's system has {:?} (nodes, rotation nodes, points), the scene's {:?}",
                sizes(saved),
                sizes(state)
            )));
        }
        if checkpoint.contact.is_some() != self.contact.is_some() {
            return Err(refuse("the checkpoint and the scene disagree on contact".into()));
        }
        self.potential.parts.state = checkpoint.state.clone();
        self.stats = checkpoint.stats.clone();
        self.t_reached = checkpoint.t_reached;
        self.restart.wall_before = checkpoint.wall_seconds;
        self.restart.resumed_from = Some(checkpoint.step());
        self.restart.pending = Some(checkpoint);
        Ok(())
    }

    /// The run's outputs: a fresh directory, or the earlier run's taken over at the checkpoint.
    pub(super) fn open_outputs(&self, dir: &Path, resume: Option<&Checkpoint>) -> Result<RunWriter, SimulationError> {
        let columns = self.probe_columns();
        let folder = dir.join(CHECKPOINT_DIR);
        if let Some(c) = resume {
            let formats = cosserat_io::FrameFormats {
                usd: false,
                ..self.frame_formats
            };
            let writer = RunWriter::resume(dir, &columns, c.probe_rows, &c.frame_times, formats)?;
            cosserat_io::remove_temporaries(&folder)?;
            return Ok(writer);
        }
        let mut writer = RunWriter::create(dir, &columns)?;
        writer.set_formats(self.frame_formats)?;
        // A checkpoint of an earlier run in `dir` does not belong to this one.
        for file in [STATE_FILE, SCENE_COPY] {
            let _ = std::fs::remove_file(folder.join(file));
        }
        cosserat_io::remove_temporaries(&folder)?;
        if self.restart.every.is_some()
            && let Some(origin) = &self.restart.origin
        {
            std::fs::create_dir_all(&folder)
                .map_err(|e| SimulationError::Setup(format!("{}: {e}", folder.display())))?;
            let text = std::fs::read(&origin.path)
                .map_err(|e| SimulationError::Setup(format!("{}: {e}", origin.path.display())))?;
            cosserat_io::write_atomic(&folder.join(SCENE_COPY), &text)?;
        }
        Ok(writer)
    }

    /// Wall-clock time of the whole run so far \[s\].
    pub(super) fn wall_seconds(&self) -> f64 {
        self.restart.wall_before + self.restart.started.elapsed().as_secs_f64()
    }

    /// Whether the step just completed ends with a checkpoint.
    pub(super) fn checkpoint_due(&self) -> bool {
        self.restart.every.is_some_and(|n| self.stats.steps.is_multiple_of(n))
    }

    /// Writes the checkpoint of the state after the step just completed.
    pub(super) fn write_checkpoint(&self, writer: &RunWriter, stepper: StepperState) -> Result<(), SimulationError> {
        let checkpoint = Checkpoint {
            scene: self.name.clone(),
            fingerprint: self.restart.fingerprint,
            origin: self.restart.origin.clone(),
            wall_seconds: self.wall_seconds(),
            t_reached: self.t_reached,
            stepper,
            state: self.potential.parts.state.clone(),
            stats: self.stats.clone(),
            probe_rows: writer.probe_rows(),
            frame_times: writer.frame_times(),
            contact: self.contact.as_ref().map(|c| c.snapshot(&self.potential)),
        };
        checkpoint.write(writer.dir())?;
        Ok(())
    }

    /// Restores the contact's state of a checkpoint (its couplings grow the Hessian's pattern).
    fn restore_contact(&mut self, checkpoint: &Checkpoint) -> Result<(), SimulationError> {
        if let (Some(contact), Some(saved)) = (&mut self.contact, &checkpoint.contact) {
            contact
                .restore(&mut self.potential, saved)
                .map_err(|reason| SimulationError::Setup(format!("resuming: {reason}")))?;
        }
        Ok(())
    }

    /// Sets a new time stepper and the output schedule to where the checkpoint's run stood. The
    /// stepper was made for the scene's first pattern, as in the run that was never stopped, and then
    /// takes over the pattern that contact had grown.
    pub(super) fn resume_dynamic(
        &mut self,
        checkpoint: &Checkpoint,
        stepper: &mut TimeStepper,
        schedule: &mut OutputSchedule,
    ) -> Result<(), SimulationError> {
        let StepperState::Dynamic {
            t,
            dt,
            next_output,
            newton,
            ref last_step,
        } = checkpoint.stepper
        else {
            return Err(SimulationError::Setup(
                "resuming: not a time-stepping checkpoint".into(),
            ));
        };
        self.restore_contact(checkpoint)?;
        if self.contact.is_some() {
            stepper.adopt_pattern(&self.potential)?;
        }
        stepper.set_time(t);
        stepper.set_dt(dt);
        stepper
            .set_last_step(last_step.clone())
            .map_err(|reason| SimulationError::Setup(format!("resuming: {reason}")))?;
        stepper.solver_mut().restore(newton);
        schedule.resume_at(next_output);
        Ok(())
    }

    /// A quasi-static stepper where the checkpoint's run stood, and the index of the next level.
    pub(super) fn resume_quasi_static(
        &mut self,
        checkpoint: &Checkpoint,
        settings: &QuasiStaticSettings,
        n_levels: usize,
    ) -> Result<(QuasiStaticStepper, usize), SimulationError> {
        let StepperState::QuasiStatic {
            levels_done,
            load_factor,
            predictor,
            increment_limit,
            newton,
        } = checkpoint.stepper.clone()
        else {
            return Err(SimulationError::Setup("resuming: not a quasi-static checkpoint".into()));
        };
        if levels_done > n_levels {
            return Err(SimulationError::Setup(format!(
                "resuming: the checkpoint has reached level {levels_done}, the scene has {n_levels}"
            )));
        }
        // A grown pattern gets a new solver of the scene's settings, as in a step.
        self.restore_contact(checkpoint)?;
        let mut stepper = QuasiStaticStepper::new(&mut self.potential, settings)?;
        stepper
            .resume(load_factor, predictor, increment_limit)
            .map_err(|reason| SimulationError::Setup(format!("resuming: {reason}")))?;
        stepper.solver_mut().restore(newton);
        Ok((stepper, levels_done))
    }
}

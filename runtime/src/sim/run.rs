//! A run in pieces: [`start`](Simulator::start), [`advance_to`](Simulator::advance_to)
//! and [`finish`](Simulator::finish), with what happens between two steps (the
//! window of the statistics, the policy's update, the sample).

use std::time::Instant;

use super::Simulator;
use super::parts::{Fresh, Phase, RunState};
use super::stats::Stats;
use crate::settings::Update;
use crate::trace::Sink;
use crate::{Model, SimError, Summary};

impl<M: Model> Simulator<M> {
    /// Run from the model's initial state and initial algebraic guess (or from
    /// [`Settings::initial`](crate::Settings::initial) when given) over `[t_start, t_end]`, sending samples and
    /// update times to `sink`: [`start`](Self::start),
    /// [`advance_to`](Self::advance_to)`(t_end)`, [`finish`](Self::finish).
    ///
    /// On error the sink keeps everything recorded before the failure.
    pub fn run<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<Summary, SimError> {
        self.start(sink)?;
        self.advance_to(self.set.window.t_end, sink)?;
        self.finish(sink)
    }

    /// Begin a run at `t_start`: the initial state, the first control update and the
    /// first sample. Starting again restarts the run.
    pub fn start<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        let m = self.pt.z.len();
        self.stats = Stats::new(m);
        self.ctl.reset(&self.set.layers.gains);
        self.drift.fill(0.0);
        let t0 = self.set.window.t_start;
        self.pt.t = t0;
        self.pt.tb = t0;
        match &self.set.initial {
            Some(init) => {
                self.pt.x.copy_from_slice(&init.x0);
                self.pt.z.copy_from_slice(&init.z0);
            }
            None => {
                self.model.initial_state(&mut self.pt.x);
                self.model.initial_alg(&mut self.pt.z);
            }
        }
        self.eps_k.copy_from_slice(&self.set.layers.eps);
        self.run = RunState::new(Phase::Running, t0);
        self.start_search();
        self.fresh = Fresh::default();
        sink.begin(&self.layout)?;
        self.eval_point(t0);
        self.check_finite()?;
        self.track_reaching()?;
        self.update(sink)?;
        self.record(false, sink)?;
        Ok(())
    }

    /// Integrate to `t` (at most `t_end`; a run not started yet is started first).
    /// Samples and updates go to `sink` as in [`run`](Self::run); the sample at `t`
    /// itself is recorded when the run continues or is finished.
    ///
    /// With a search of `mu` ([`Layers::adapt_mu`](crate::settings::Layers::adapt_mu)) the
    /// run goes in pieces that end at the search's frames, where it may move `mu`.
    pub fn advance_to<S: Sink + ?Sized>(&mut self, t: f64, sink: &mut S) -> Result<(), SimError> {
        if self.run.phase == Phase::Idle {
            self.start(sink)?;
        }
        let target = t.min(self.set.window.t_end);
        while let Some(end) = self.search.as_ref().map(|s| s.end_toward(target)) {
            if !(end <= target && self.run.phase == Phase::Running) {
                break;
            }
            self.advance_piece(end, sink)?;
            self.end_search_frame()?;
        }
        self.advance_piece(t, sink)
    }

    /// [`advance_to`](Self::advance_to) without the search's frames.
    fn advance_piece<S: Sink + ?Sized>(&mut self, t: f64, sink: &mut S) -> Result<(), SimError> {
        match self.run.phase {
            Phase::Idle => self.start(sink)?,
            Phase::Finished => {
                return Err(SimError::Backwards {
                    requested: t,
                    now: self.pt.t,
                    finished: true,
                });
            }
            Phase::Running => {}
        }
        let target = t.min(self.set.window.t_end);
        if target.is_nan() || target < self.pt.t {
            return Err(SimError::Backwards {
                requested: t,
                now: self.pt.t,
                finished: false,
            });
        }
        self.resume(sink)?;
        if target > self.pt.t {
            self.run.origin = self.pt.t;
            self.run.k = 0;
            self.run.grid_target = target;
            self.run.n = self.grid_steps(target);
        }
        while self.pt.t < target {
            self.step(target)?;
            self.after_step(sink)?;
            if self.deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(SimError::Deadline { t: self.pt.t });
            }
        }
        Ok(())
    }

    /// End the run: the last sample, the sink's `finish`, and the summary. Finishing
    /// before `t_end` is allowed (the summary says where the run ended).
    pub fn finish<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<Summary, SimError> {
        if self.run.phase == Phase::Idle {
            self.start(sink)?;
        }
        if self.run.phase == Phase::Running {
            self.resume(sink)?;
            let step = self.stats.steps;
            if self.run.recorded != Some(step) {
                self.record(true, sink)?;
            }
            sink.finish()?;
            self.run.phase = Phase::Finished;
        }
        if !self.fresh.jacobian {
            self.ctl
                .eval_jacobian(&self.model, self.pt.t, &self.pt.x, &self.pt.z);
            self.fresh.jacobian = true;
        }
        self.ctl.z_star(&self.pt.z, &mut self.scratch.z_star);
        self.z_eq_now()?;
        let wall = self.run.clock.map_or(0.0, |c| c.elapsed().as_secs_f64());
        Ok(self.summary(wall))
    }

    /// Before the next step of a piece: evaluate again what the caller's change of the
    /// model made stale, make a requested update, and record the sample left pending
    /// at the end of the previous piece.
    pub(super) fn resume<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        if self.fresh.stale {
            self.fresh.stale = false;
            self.fresh.f = false;
            self.eval_point(self.pt.t);
            if self.located() {
                self.rate_at(self.pt.t);
            }
            self.check_finite()?;
        }
        if self.run.update_requested {
            self.run.update_requested = false;
            self.update(sink)?;
        }
        if self.run.pending_record {
            self.run.pending_record = false;
            if sink.wants(self.stats.steps, self.pt.t) {
                self.record(false, sink)?;
            }
        }
        Ok(())
    }

    /// After an accepted step: finiteness, reaching, the window, the policy's update
    /// and the sample.
    pub(super) fn after_step<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        self.check_finite()?;
        self.track_reaching()?;
        self.stats.steps_since_update += 1;
        let due = match self.set.law.update() {
            None => true,
            Some(Update::Fixed { period: p }) => {
                if self.set.integration.integrator.is_adaptive() {
                    self.pt.t >= self.pt.tb + p
                } else {
                    let period = ((p / self.set.integration.step).round() as u64).max(1);
                    self.stats.steps_since_update >= period
                }
            }
            Some(Update::Monitor { .. }) => {
                let forced = self.located() && std::mem::take(&mut self.run.force_update);
                let asked = !forced && self.monitor_due();
                if asked && self.steady() {
                    // The rows that asked (only their blocks with block-local updates);
                    // in the reaching phase every row, as the contracting layers need.
                    self.update_asked(sink)?;
                    false
                } else {
                    forced || asked
                }
            }
        };
        if due {
            self.update(sink)?;
        }
        let last = self.pt.t >= self.set.window.t_end;
        if last {
            self.record(true, sink)?;
        } else if self.pt.t >= self.run.grid_target {
            self.run.pending_record = true;
        } else if sink.wants(self.stats.steps, self.pt.t) {
            self.record(false, sink)?;
        }
        if let Some(limit) = self.set.integration.max_steps {
            if self.stats.steps + self.stats.rejected >= limit && !last {
                return Err(SimError::StepLimit {
                    limit,
                    t: self.pt.t,
                });
            }
        }
        Ok(())
    }

    /// Record the reaching time, enter the statistics window, enforce the reaching limit,
    /// and update the maxima and the loss record with the step just taken.
    pub(super) fn track_reaching(&mut self) -> Result<(), SimError> {
        let t = self.pt.t;
        let s = &self.ctl.s;
        let was_reached = self.stats.reaching_time.is_some();
        if !was_reached {
            if s.iter()
                .zip(&self.set.layers.eps)
                .all(|(s, e)| s.abs() <= *e)
            {
                self.stats.reaching_time = Some(t);
            } else if t - self.set.window.t_start > self.set.window.reaching_limit {
                let outside: Vec<usize> = (0..s.len())
                    .filter(|&i| s[i].abs() > self.set.layers.eps[i])
                    .collect();
                return Err(SimError::ReachingTimeout {
                    limit: self.set.window.reaching_limit,
                    t,
                    names: outside
                        .iter()
                        .map(|&i| self.model.constraint_name(i).to_string())
                        .collect(),
                    s: outside.iter().map(|&i| s[i]).collect(),
                });
            }
        }
        let st = &mut self.stats;
        for (i, si) in s.iter().enumerate() {
            let w = self.ctl.residual(i).abs();
            st.seen_s[i] = st.seen_s[i].max(si.abs()).max(self.measure.max_s[i]);
            st.seen_w[i] = st.seen_w[i].max(w);
        }
        if was_reached && st.steps > 0 {
            st.loss.observe(
                t,
                self.measure.h,
                &self.measure,
                &self.set.layers.eps,
                self.set.bound_tol,
            );
        }
        let in_window = st.stats_from.is_some();
        if !in_window
            && st.reaching_time.is_some()
            && t >= self.set.window.t_start + self.set.window.settle
        {
            st.stats_from = Some(t);
        }
        if st.stats_from.is_some() {
            for (i, (ms, mw)) in st.max_s.iter_mut().zip(&mut st.max_w).enumerate() {
                // The step that opens the window counts with its end only.
                let over_step = if in_window {
                    self.measure.max_s[i]
                } else {
                    0.0
                };
                *ms = ms.max(s[i].abs()).max(over_step);
                *mw = mw.max(self.ctl.residual(i).abs());
            }
        }
        Ok(())
    }
}

//! The pilot simulation and the automatic design procedure (docs/method.md section 5, T
//! corollary 4.1): run the simulator once, estimate `|beta_i|` and `M_i` from what it
//! did with a [`PilotEstimator`], and choose `mu_i`, `k_i` from those bounds.
//!
//! The simulator is not modified: the pilot is a [`Sink`] that receives every step's
//! sample. Between two updates the simulator holds `v` and sets `z(t) = z_b + v (t - t_b)`
//! exactly, so `v` is recovered from the first sample after an update as
//! `(z - z_b) / (t - t_b)`; then `w^(r) = J_Omega v + beta` (T 2.5) is evaluated from
//! the model at every sample of the interval, and at the update point itself with the
//! new `v` (the interval's reference, see [`PilotEstimator`]).

use std::cmp::Ordering;
use std::io;
use std::time::{Duration, Instant};

use super::{
    ConstraintSpec, Design, DesignError, GainChoice, LayerBound, MuSearch, PilotError,
    PilotEstimate, PilotEstimator, design, design_at,
};
use crate::settings::AlphaChoice;
use crate::trace::{Layout, Sample, Sink};
use crate::{Model, Settings, SimError, Simulator, Summary};

/// Why a pilot run or an automatic design failed.
#[derive(Debug, thiserror::Error)]
pub enum PilotRunError {
    /// The pilot simulation itself failed.
    #[error("pilot simulation failed: {0}")]
    Sim(#[from] SimError),
    /// The samples could not give an estimate (e.g. no interval inside the window).
    #[error("pilot estimate failed: {0}")]
    Pilot(#[from] PilotError),
    /// The design formulas rejected the estimated bounds.
    #[error("design failed: {0}")]
    Design(#[from] DesignError),
    /// The arguments do not fit the model.
    #[error("{0}")]
    Mismatch(String),
    /// The pilots took more wall time than [`AutoDesignOptions::budget`].
    #[error(
        "the pilot runs took more than their budget of {budget:?}: pass {pass} was at t = {t} of its pilot"
    )]
    OverBudget {
        /// The budget.
        budget: Duration,
        /// The pass whose pilot was stopped (from 1).
        pass: usize,
        /// How far that pilot had come.
        t: f64,
    },
    /// The pilot left a layer after reaching: its gains were too weak for the model's
    /// drift, and the motion it measured is not the one a design is for. The pilot was
    /// stopped there.
    #[error(
        "the pilot (gains {gain_min:e} .. {gain_max:e}) left the layer of constraint {constraint} at t = {t}: |s|/eps = {ratio:.3}"
    )]
    LayerLost {
        /// The constraint that left first.
        constraint: usize,
        /// When.
        t: f64,
        /// Its `|s| / eps` there.
        ratio: f64,
        /// The smallest and largest gain of the pilot.
        gain_min: f64,
        /// See `gain_min`.
        gain_max: f64,
        /// When `J_s` was nearly singular in the pilot (its smallest pivot below
        /// [`NEAR_SINGULAR`](crate::summary::NEAR_SINGULAR) of its earlier largest value): then
        /// no gain keeps the layer there.
        near_singular_at: Option<f64>,
    },
}

/// What a pilot run measured: the bounds (raw maxima, no safety factor) and the run's
/// statistics.
#[derive(Debug, Clone)]
pub struct PilotRun {
    /// `|beta_i|` and `M_i` seen in the feeding window.
    pub estimate: PilotEstimate,
    /// The pilot simulation's summary.
    pub summary: Summary,
}

/// Runs `model` under `settings` and estimates `|beta_i|` and `M_i` (T 3.5) of every
/// constraint from the motion in the statistics window of the run: feeding starts at the
/// first control update after all `|s_i| <= eps_i` held and `t >= t_start + settle`
/// (the reaching phase, with its large tensions, is left out, as in the thesis). The
/// estimate is the raw maximum; multiply by a safety factor before designing if the
/// pilot is short.
///
/// A pilot with located crossings that leaves a layer after reaching (beyond
/// `(1 + bound_tol) eps_i` at a step end) is stopped there with [`PilotRunError::LayerLost`]: a pilot whose gains are
/// too weak for the model's drift can crawl for a long time outside its layers, and
/// what it measures then is not a motion to design for.
///
/// Cost: per step one `beta` and one `J_Omega` evaluation on top of the simulation.
/// Works with the DBSMC laws ([`Law::Dbsmc`](crate::settings::Law::Dbsmc) and
/// [`Law::StepEnd`](crate::settings::Law::StepEnd), monitored or at a fixed period);
/// [`Law::Spsm`](crate::settings::Law::Spsm) has no held control and is rejected.
pub fn pilot_run<M: Model + ?Sized>(
    model: &M,
    settings: &Settings,
) -> Result<PilotRun, PilotRunError> {
    match pilot_run_until_lost(model, settings, None)? {
        PilotOutcome::Held(run) => Ok(run),
        PilotOutcome::Lost { error, .. } => Err(error),
    }
}

/// [`pilot_run`], but a pilot that left a layer is returned with what it measured up
/// to there.
fn pilot_run_until_lost<M: Model + ?Sized>(
    model: &M,
    settings: &Settings,
    deadline: Option<Instant>,
) -> Result<PilotOutcome, PilotRunError> {
    if settings.law == crate::settings::Law::Spsm {
        return Err(PilotRunError::Mismatch(
            "a pilot run needs a held control: use the monitor or fixed policy, not SPSM".into(),
        ));
    }
    let mut sink = PilotSink::new(model, settings);
    let mut sim = Simulator::new(model, settings.clone())?;
    sim.set_deadline(deadline);
    let result = sim.run(&mut sink);
    let Some((constraint, t, ratio)) = sink.lost else {
        let summary = result?;
        if let Some(e) = sink.error.take() {
            return Err(e.into());
        }
        let estimate = sink.estimator.estimate(1.0)?;
        return Ok(PilotOutcome::Held(PilotRun { estimate, summary }));
    };
    // Stopped by the sink at the loss: the summary of the run up to there.
    let summary = sim.finish(&mut crate::trace::NoTrace)?;
    let near_singular_at = summary
        .min_pivot_ratio
        .filter(|(r, _)| *r < crate::summary::NEAR_SINGULAR)
        .map(|(_, t)| t);
    let fold = |f: fn(f64, f64) -> f64, init| settings.layers.gains.iter().copied().fold(init, f);
    let error = PilotRunError::LayerLost {
        constraint,
        t,
        ratio,
        gain_min: fold(f64::min, f64::INFINITY),
        gain_max: fold(f64::max, 0.0),
        near_singular_at,
    };
    let partial = match (sink.error.take(), sink.estimator.estimate(1.0)) {
        (None, Ok(estimate)) => Some(PilotRun { estimate, summary }),
        _ => None,
    };
    Ok(PilotOutcome::Lost { partial, error })
}

/// What [`pilot_run_until_lost`] gives.
enum PilotOutcome {
    /// The pilot kept its layers to the end.
    Held(PilotRun),
    /// The pilot left a layer and was stopped there.
    Lost {
        /// What it measured up to the loss (`None` when that gave no drift data).
        partial: Option<PilotRun>,
        /// The [`PilotRunError::LayerLost`].
        error: PilotRunError,
    },
}

/// The estimator fed by the simulator's samples.
struct PilotSink<'a, M: Model + ?Sized> {
    model: &'a M,
    estimator: PilotEstimator,
    eps: Vec<f64>,
    /// `(1 + bound_tol)`: beyond it a layer counts as left.
    tol: f64,
    /// Whether to stop at a layer left: with crossings located only (with the thesis's
    /// step-end rule a step's overshoot is part of the procedure).
    watch: bool,
    /// The first layer left after reaching: constraint, time, `|s| / eps`.
    lost: Option<(usize, f64, f64)>,
    window_from: f64,
    /// Whether all `|s_i| <= eps_i` held at some sample (the reaching phase is over).
    reached: bool,
    /// Whether observations are being fed (from the first update inside the window).
    feeding: bool,
    /// An update was reported and its sample not yet seen.
    update_pending: bool,
    /// The update point whose `v` is not known yet: `(t_b, x_b, z_b)`.
    deferred: Option<f64>,
    xb: Vec<f64>,
    zb: Vec<f64>,
    /// The held `v` of the current interval, once known.
    v: Vec<f64>,
    v_known: bool,
    pattern: Vec<(usize, usize)>,
    jvals: Vec<f64>,
    beta: Vec<f64>,
    w_r: Vec<f64>,
    error: Option<PilotError>,
}

impl<'a, M: Model + ?Sized> PilotSink<'a, M> {
    fn new(model: &'a M, settings: &Settings) -> Self {
        let (n, m) = (model.n_states(), model.n_constraints());
        let pattern = model.jacobian_pattern().to_vec();
        PilotSink {
            model,
            estimator: PilotEstimator::new(m),
            eps: settings.layers.eps.clone(),
            tol: 1.0 + settings.bound_tol,
            watch: matches!(settings.law, crate::settings::Law::Dbsmc(_)),
            lost: None,
            window_from: settings.window.t_start + settings.window.settle,
            reached: false,
            feeding: false,
            update_pending: false,
            deferred: None,
            xb: vec![0.0; n],
            zb: vec![0.0; m],
            v: vec![0.0; m],
            v_known: false,
            jvals: vec![0.0; pattern.len()],
            pattern,
            beta: vec![0.0; m],
            w_r: vec![0.0; m],
            error: None,
        }
    }

    /// `w^(r) = J_Omega v + beta` at `(t, x, z)` with the held `v`, into `self.w_r`
    /// (and `beta` into `self.beta`).
    fn eval(&mut self, t: f64, x: &[f64], z: &[f64]) {
        self.model.beta(t, x, z, &mut self.beta);
        self.model.jacobian(t, x, z, &mut self.jvals);
        self.w_r.copy_from_slice(&self.beta);
        for (&(i, j), a) in self.pattern.iter().zip(&self.jvals) {
            self.w_r[i] += a * self.v[j];
        }
    }

    fn observe(&mut self, t: f64, x: &[f64], z: &[f64]) -> Result<(), PilotError> {
        self.eval(t, x, z);
        self.estimator.observe(t, &self.beta, &self.w_r)
    }

    fn feed(&mut self, s: &Sample<'_>) -> Result<(), PilotError> {
        if !self.reached && s.s.iter().zip(&self.eps).all(|(s, e)| s.abs() <= *e) {
            self.reached = true;
        }
        if !self.feeding {
            if !(self.update_pending && self.reached && s.t >= self.window_from) {
                self.update_pending = false;
                return Ok(());
            }
            self.feeding = true;
        }
        // 1. The first sample after an update reveals the held v; observe the update
        //    point with it (the interval's reference).
        if let Some(tb) = self.deferred {
            let dt = s.t - tb;
            if dt > 0.0 {
                for ((v, z), zb) in self.v.iter_mut().zip(s.z).zip(&self.zb) {
                    *v = (z - zb) / dt;
                }
                self.v_known = true;
                self.deferred = None;
                let (xb, zb) = (std::mem::take(&mut self.xb), std::mem::take(&mut self.zb));
                let r = self.observe(tb, &xb, &zb);
                self.xb = xb;
                self.zb = zb;
                r?;
            }
        }
        // 2. This sample belongs to the running interval (if its v is known); at an
        //    update point it is the interval's end, taken with the old v.
        if self.v_known {
            self.observe(s.t, s.x, s.z)?;
        }
        // 3. An update at this sample starts a new interval whose v is not known yet.
        if self.update_pending {
            self.update_pending = false;
            self.estimator.mark_update(s.t)?;
            self.deferred = Some(s.t);
            self.xb.copy_from_slice(s.x);
            self.zb.copy_from_slice(s.z);
            self.v_known = false;
        }
        Ok(())
    }
}

impl<M: Model + ?Sized> Sink for PilotSink<'_, M> {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        Ok(())
    }
    fn algebraic_outputs(&self) -> bool {
        // The estimator reads x, z and s only: no z_eq or z* per step.
        false
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        if self.reached && self.watch {
            let left =
                s.s.iter()
                    .zip(&self.eps)
                    // Beyond the tolerance, or NaN: left.
                    .position(|(s, e)| {
                        !matches!(
                            s.abs().partial_cmp(&(self.tol * e)),
                            Some(Ordering::Less | Ordering::Equal)
                        )
                    });
            if let Some(i) = left {
                self.lost = Some((i, s.t, s.s[i].abs() / self.eps[i]));
                return Err(io::Error::other("the pilot left a layer"));
            }
        }
        if self.error.is_none() {
            if let Err(e) = self.feed(s) {
                self.error = Some(e);
            }
        }
        Ok(())
    }
    fn update(&mut self, _: f64) -> io::Result<()> {
        // The sample at the update time follows (the simulator records after updating).
        self.update_pending = true;
        Ok(())
    }
}

/// Design specs from pilot bounds: constraint `i` of index `indices[i]` with layer
/// `eps[i]`, `M_i = estimate.m[i]`, `|beta_i| = estimate.beta_abs[i]`.
pub fn pilot_specs(
    indices: &[usize],
    eps: &[f64],
    estimate: &PilotEstimate,
    layer: LayerBound,
) -> Result<Vec<ConstraintSpec>, PilotRunError> {
    let m = indices.len();
    if eps.len() != m || estimate.m.len() != m || estimate.beta_abs.len() != m {
        return Err(PilotRunError::Mismatch(format!(
            "{m} constraints but {} eps values and {} estimates",
            eps.len(),
            estimate.m.len()
        )));
    }
    Ok((0..m)
        .map(|i| ConstraintSpec {
            r: indices[i],
            eps: eps[i],
            m: estimate.m[i],
            beta_abs: estimate.beta_abs[i],
            layer,
        })
        .collect())
}

/// Where the design's `mu_i` come from.
#[derive(Debug, Clone, PartialEq)]
pub enum MuChoice {
    /// Maximise each `T_i^min(mu_i)` ([`design`]).
    Search(MuSearch),
    /// Given, one per constraint: only the gains and `T_min` are designed
    /// ([`design_at`]), and every pilot runs at these `mu_i`.
    Given(Vec<f64>),
}

impl Default for MuChoice {
    /// The default search.
    fn default() -> Self {
        MuChoice::Search(MuSearch::default())
    }
}

/// How [`auto_design`] runs its pilots and designs.
#[derive(Debug, Clone)]
pub struct AutoDesignOptions {
    /// How `k_i` follows from `mu_i` in the design.
    pub gain: GainChoice,
    /// Which bound enters (T 3.14).
    pub layer: LayerBound,
    /// Number of pilot -> design passes (at least 1).
    pub passes: usize,
    /// Factor (>= 1) applied to the pilot bounds before designing.
    pub safety: f64,
    /// Searched or given `mu_i`.
    pub mu: MuChoice,
    /// How many times the first pilot may run again with ten times its gains when it
    /// leaves a layer ([`PilotRunError::LayerLost`]).
    pub pilot_retries: usize,
    /// The most wall time all pilots together may take; beyond it the design stops with
    /// [`PilotRunError::OverBudget`]. `None`: no limit.
    pub budget: Option<Duration>,
}

impl Default for AutoDesignOptions {
    /// Relaxed gains with the general (T 3.14) bound, two passes, no safety factor, `mu`
    /// searched, up to 4 retries of the first pilot (gains up to 10^4 times the given),
    /// no time budget.
    fn default() -> Self {
        AutoDesignOptions {
            gain: GainChoice::Relaxed,
            layer: LayerBound::General,
            passes: 2,
            safety: 1.0,
            mu: MuChoice::default(),
            pilot_retries: 4,
            budget: None,
        }
    }
}

/// One pass of [`auto_design`]: the pilot's `mu`, gains and alpha, what it measured,
/// and the design made from it.
#[derive(Debug, Clone)]
pub struct DesignPass {
    /// The pilot's surface parameters.
    pub mu: Vec<f64>,
    /// The pilot's gains.
    pub gains: Vec<f64>,
    /// The pilot's alpha choice.
    pub alpha: AlphaChoice,
    /// The pilot's measurements (this pass only).
    pub pilot: PilotRun,
    /// Whether this (designed) pilot left a layer and was stopped there: its
    /// measurements are those up to the loss, and no pass follows. The final run may
    /// then leave its layers too (and says so).
    pub pilot_left_layer: bool,
    /// The design from the largest bounds of this and the earlier passes.
    pub design: Design,
}

/// The result of [`auto_design`]: the last pass's design, and every pass.
#[derive(Debug, Clone)]
pub struct AutoDesign {
    /// The final design (the last pass).
    pub design: Design,
    /// All passes, first to last.
    pub passes: Vec<DesignPass>,
}

/// The design procedure of docs/method.md section 5 (T corollary 4.1), automated: estimate
/// `|beta_i|` and `M_i` from a pilot run, maximise `T_i^min(mu_i)` with the gain choice
/// substituted, and repeat the pilot with the new design.
///
/// The pilot needs some `mu` and gains before there is a design. The first pass uses
/// `pilot.mu` and `pilot.gains` with the **exact** alpha: then `s' = -K sgn(s)` up to the
/// drift within an interval, so a gain above the drift keeps the motion in the layers
/// whatever `|beta|` turns out to be. What is above the drift depends on the model (a
/// long chain's links near its pin drift many orders of magnitude faster than a double
/// pendulum's): a first pilot that leaves a layer is stopped and runs again with ten
/// times its gains, up to [`AutoDesignOptions::pilot_retries`] times; the pilot that
/// held is the one [`DesignPass`] records. A designed pilot (second pass on) that leaves
/// a layer is stopped too: what it measured up to there enters the last design, and the
/// passes end there ([`DesignPass::pilot_left_layer`]); running again with a design
/// from larger bounds is a feedback loop (larger gains, larger measured drift) that
/// need not settle. Later passes use the previous design's `mu_i`, `k_i` with
/// the **cheap** alpha, the configuration the designed gains are meant for (every
/// [`GainChoice`] except `Fixed` includes the `mu^(r-1) |beta|` the cheap alpha
/// neglects; with `Fixed` the later passes keep the exact alpha), so the bounds are measured on motion like the final run's. `M` depends on
/// the design through `J_Omega'` times the held `v` (larger gains, larger `v`), which is
/// why one pass is not enough in general; two passes are the default. Each pass designs
/// from the largest bounds seen in all passes so far (they are bounds on the motion, and
/// a chaotic model visits different states under different designs), so the sequence of
/// designs does not oscillate between optimistic and pessimistic estimates. `eps` replaces
/// `pilot.eps`, and [`MuChoice::Given`] `mu` replaces `pilot.mu`; everything else of
/// `pilot` (step, integrator, policy, reaching rule, duration, settle time) is used as
/// given.
pub fn auto_design<M: Model + ?Sized>(
    model: &M,
    eps: &[f64],
    pilot: &Settings,
    options: &AutoDesignOptions,
) -> Result<AutoDesign, PilotRunError> {
    if options.passes == 0 {
        return Err(PilotRunError::Mismatch(
            "auto_design needs at least one pass".into(),
        ));
    }
    if !(options.safety.is_finite() && options.safety >= 1.0) {
        return Err(PilotError::BadSafety(options.safety).into());
    }
    let m = model.n_constraints();
    if m == 0 {
        // An ODE: there is no mu or gain to design (it runs with empty ones).
        return Err(DesignError::NoConstraints.into());
    }
    let mut settings = pilot.clone();
    settings.layers.eps = eps.to_vec();
    settings.alpha = AlphaChoice::Exact;
    if let MuChoice::Given(mu) = &options.mu {
        if mu.len() != m {
            return Err(PilotRunError::Mismatch(format!(
                "{m} constraints but {} given mu values",
                mu.len()
            )));
        }
        settings.layers.mu = mu.clone();
    }
    let started = Instant::now();
    let deadline = options.budget.map(|b| started + b);
    let mut passes: Vec<DesignPass> = Vec::with_capacity(options.passes.min(8));
    let (mut beta_max, mut m_max) = (vec![0.0f64; m], vec![0.0f64; m]);
    for pass in 0..options.passes {
        // Only the first pilot runs again: its gains are a guess, the later ones designed.
        let mut retries = if pass == 0 { options.pilot_retries } else { 0 };
        let (run, left) = loop {
            let outcome = match pilot_run_until_lost(model, &settings, deadline) {
                Err(PilotRunError::Sim(SimError::Deadline { t })) => {
                    return Err(PilotRunError::OverBudget {
                        budget: options.budget.unwrap_or_default(),
                        pass: pass + 1,
                        t,
                    });
                }
                other => other?,
            };
            match outcome {
                PilotOutcome::Held(run) => break (run, false),
                // The first pilot's gains are below the drift: ten times them.
                PilotOutcome::Lost { .. } if retries > 0 => {
                    retries -= 1;
                    settings.layers.gains.iter_mut().for_each(|k| *k *= 10.0);
                }
                // A designed pilot left its layers: the drift is larger than the bounds
                // it was designed from. What it measured up to there enters the last
                // design, and the passes end (designing again from it is a feedback
                // loop: larger gains, larger measured drift).
                PilotOutcome::Lost {
                    partial: Some(partial),
                    ..
                } if pass > 0 => break (partial, true),
                PilotOutcome::Lost { error, .. } => return Err(error),
            }
        };
        for i in 0..m {
            beta_max[i] = beta_max[i].max(run.estimate.beta_abs[i]);
            m_max[i] = m_max[i].max(run.estimate.m[i]);
        }
        let scaled = PilotEstimate {
            beta_abs: beta_max.iter().map(|b| b * options.safety).collect(),
            m: m_max.iter().map(|m| m * options.safety).collect(),
            ..run.estimate.clone()
        };
        let specs = pilot_specs(model.indices(), eps, &scaled, options.layer)?;
        let d = match &options.mu {
            MuChoice::Search(search) => design(&specs, options.gain, search)?,
            MuChoice::Given(mu) => design_at(&specs, mu, options.gain)?,
        };
        passes.push(DesignPass {
            mu: settings.layers.mu.clone(),
            gains: settings.layers.gains.clone(),
            alpha: settings.alpha,
            pilot: run,
            pilot_left_layer: left,
            design: d.clone(),
        });
        if left {
            break;
        }
        settings.layers.mu = d.constraints.iter().map(|c| c.mu).collect();
        settings.layers.gains = d.constraints.iter().map(|c| c.k).collect();
        // A fixed gain has no mu^(r-1) |beta| term, so only the exact alpha fits it.
        settings.alpha = match options.gain {
            GainChoice::Fixed(_) => AlphaChoice::Exact,
            _ => AlphaChoice::Cheap,
        };
    }
    let design = passes[passes.len() - 1].design.clone();
    Ok(AutoDesign { design, passes })
}

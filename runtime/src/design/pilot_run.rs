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

use std::io;

use super::{
    ConstraintSpec, Design, DesignError, GainChoice, LayerBound, MuSearch, PilotError,
    PilotEstimate, PilotEstimator, design, design_at,
};
use crate::{AlphaChoice, Layout, Model, Sample, Settings, SimError, Simulator, Sink, Summary};

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
/// Cost: per step one `beta` and one `J_Omega` evaluation on top of the simulation.
/// Works with [`Policy::Monitor`](crate::Policy::Monitor) and
/// [`Policy::Fixed`](crate::Policy::Fixed); [`Policy::Spsm`](crate::Policy::Spsm) has no
/// held control and is rejected.
pub fn pilot_run<M: Model + ?Sized>(
    model: &M,
    settings: &Settings,
) -> Result<PilotRun, PilotRunError> {
    if settings.policy == crate::Policy::Spsm {
        return Err(PilotRunError::Mismatch(
            "a pilot run needs a held control: use the monitor or fixed policy, not SPSM".into(),
        ));
    }
    let mut sink = PilotSink::new(model, settings);
    let summary = Simulator::new(model, settings.clone())?.run(&mut sink)?;
    if let Some(e) = sink.error.take() {
        return Err(e.into());
    }
    let estimate = sink.estimator.estimate(1.0)?;
    Ok(PilotRun { estimate, summary })
}

/// The estimator fed by the simulator's samples.
struct PilotSink<'a, M: Model + ?Sized> {
    model: &'a M,
    estimator: PilotEstimator,
    eps: Vec<f64>,
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
            eps: settings.eps.clone(),
            window_from: settings.t_start + settings.settle,
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
}

impl Default for AutoDesignOptions {
    /// Relaxed gains with the general (T 3.14) bound, two passes, no safety factor, `mu`
    /// searched.
    fn default() -> Self {
        AutoDesignOptions {
            gain: GainChoice::Relaxed,
            layer: LayerBound::General,
            passes: 2,
            safety: 1.0,
            mu: MuChoice::default(),
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
/// drift within an interval, so a modest gain keeps the motion in the layers whatever
/// `|beta|` turns out to be. Later passes use the previous design's `mu_i`, `k_i` with
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
    settings.eps = eps.to_vec();
    settings.alpha = AlphaChoice::Exact;
    if let MuChoice::Given(mu) = &options.mu {
        if mu.len() != m {
            return Err(PilotRunError::Mismatch(format!(
                "{m} constraints but {} given mu values",
                mu.len()
            )));
        }
        settings.mu = mu.clone();
    }
    let mut passes: Vec<DesignPass> = Vec::with_capacity(options.passes.min(8));
    let (mut beta_max, mut m_max) = (vec![0.0f64; m], vec![0.0f64; m]);
    for _ in 0..options.passes {
        let run = pilot_run(model, &settings)?;
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
            mu: settings.mu.clone(),
            gains: settings.gains.clone(),
            alpha: settings.alpha,
            pilot: run,
            design: d.clone(),
        });
        settings.mu = d.constraints.iter().map(|c| c.mu).collect();
        settings.gains = d.constraints.iter().map(|c| c.k).collect();
        // A fixed gain has no mu^(r-1) |beta| term, so only the exact alpha fits it.
        settings.alpha = match options.gain {
            GainChoice::Fixed(_) => AlphaChoice::Exact,
            _ => AlphaChoice::Cheap,
        };
    }
    let design = passes[passes.len() - 1].design.clone();
    Ok(AutoDesign { design, passes })
}

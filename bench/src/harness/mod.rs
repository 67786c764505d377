//! The work-precision harness: scenes, methods with their accuracy knobs, runs,
//! records, CSV and charts.

mod chart;
mod designed;

use dae_runtime::settings::{Law, StepEnd};
use std::io::{self, Write};

use dae_runtime::{
    Model, Settings, Simulator, settings::Initial, settings::Integrator, trace::NoTrace,
};

use crate::baseline::{BaselineError, IndexOneRk4, IndexOneSettings};
#[cfg(feature = "bdf")]
use crate::baseline::{BdfSettings, bdf_index1};

/// The error of a [`Method::Bdf`] run in a build without the `bdf` feature.
pub const BDF_MISSING: &str =
    "the BDF baseline needs dae-bench's `bdf` feature (cargo ... --features bdf)";

pub use chart::{CostAxis, ErrorAxis, chart};
pub use designed::{DesignedBounds, designed_bounds};

/// A model, a consistent start, an end time and the truth at the end.
#[derive(Debug, Clone)]
pub struct Scene<'a, M: Model + ?Sized> {
    /// Scene name (file names and chart titles).
    pub name: String,
    /// The model.
    pub model: &'a M,
    /// Initial states (on the constraint manifold for work-precision).
    pub x0: Vec<f64>,
    /// Initial algebraic unknowns (consistent with `x0`, e.g. from
    /// [`consistent_alg`](crate::baseline::consistent_alg)).
    pub z0: Vec<f64>,
    /// End time (the start is 0).
    pub t_end: f64,
    /// Indices into `x` of the quantities compared with the truth (positions).
    pub compare: Vec<usize>,
    /// The truth of those quantities at `t_end`.
    pub truth: Vec<f64>,
    /// Bounds on `|beta_i|` along the solution, for the DBSMC and SPSM gains
    /// `k_i = gain_factor * mu^(r_i - 1) * beta_bound_i` (see [`pilot_beta_bound`]).
    pub beta_bound: Vec<f64>,
}

impl<M: Model + ?Sized> Scene<'_, M> {
    /// Largest absolute difference between `x[compare]` and the truth.
    pub fn position_error(&self, x: &[f64]) -> f64 {
        self.compare
            .iter()
            .zip(&self.truth)
            .fold(0.0f64, |m, (&i, t)| m.max((x[i] - t).abs()))
    }

    /// The scene's start, for [`Settings::initial`] and the baselines' `initial`.
    pub fn initial(&self) -> Initial {
        Initial {
            x0: self.x0.clone(),
            z0: self.z0.clone(),
        }
    }

    /// DBSMC with monitoring at layer `eps`, time constant `mu` and gains
    /// [`Scene::gains`]`(mu, gain_factor)`, with the runtime's error-controlled steps and
    /// located crossings ([`DbsmcStep::Adaptive`]).
    pub fn dbsmc(&self, eps: f64, mu: f64, gain_factor: f64) -> Method {
        Method::Dbsmc {
            eps,
            mu,
            step: DbsmcStep::Adaptive,
            gain_factor,
        }
    }

    /// The same with the rule used before crossings were located: RK4 with the step
    /// chosen so that one step moves `s` by at most a fifth of the layer
    /// (`h = 0.2 eps / max k_i`, in `[1e-6, h_max]`), crossings noticed at step ends.
    pub fn dbsmc_step_rule(&self, eps: f64, mu: f64, gain_factor: f64, h_max: f64) -> Method {
        Method::Dbsmc {
            eps,
            mu,
            step: DbsmcStep::StepEnd(step_rule(eps, &self.gains(mu, gain_factor), h_max)),
            gain_factor,
        }
    }

    /// Gains `k_i = factor * mu^(r_i - 1) * beta_bound_i`.
    pub fn gains(&self, mu: f64, factor: f64) -> Vec<f64> {
        self.model
            .indices()
            .iter()
            .zip(&self.beta_bound)
            .map(|(&r, b)| factor * mu.powi(r as i32 - 1) * b.max(1e-12))
            .collect()
    }
}

/// Largest `|beta_i(t, x, z)|` along a run of baseline (a) (RK4 with step `h`, `z` from
/// `s = 0` with time constants `mu`) from `(x0, z0)` over `[0, t_end]`: the pilot run
/// of the thesis' design procedure, generic over the model.
pub fn pilot_beta_bound<M: Model + ?Sized>(
    model: &M,
    x0: &[f64],
    z0: &[f64],
    t_end: f64,
    mu: f64,
    h: f64,
) -> Result<Vec<f64>, BaselineError> {
    let m = model.n_constraints();
    let mut run = IndexOneRk4::new(
        model,
        IndexOneSettings {
            mu: vec![mu; m],
            step: h,
            t_start: 0.0,
            t_end,
            newton_tol: 1e-12,
            initial: Some(Initial {
                x0: x0.to_vec(),
                z0: z0.to_vec(),
            }),
        },
    )?;
    let mut bound = vec![0.0f64; m];
    let mut beta = vec![0.0; m];
    while run.time() < t_end - 0.5 * h {
        run.step(h)?;
        model.beta(run.time(), run.state(), run.alg(), &mut beta);
        for (b, v) in bound.iter_mut().zip(&beta) {
            *b = b.max(v.abs());
        }
    }
    Ok(bound)
}

/// `h = 0.2 eps / max k_i` clamped to `[1e-6, h_max]`: one step moves `s` by at most a
/// fifth of the layer (the rule of the step-end crossings).
pub fn step_rule(eps: f64, gains: &[f64], h_max: f64) -> f64 {
    let k = gains.iter().fold(0.0f64, |a, b| a.max(*b));
    (0.2 * eps / k).clamp(1e-6, h_max.max(1e-6))
}

/// How a DBSMC run is integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DbsmcStep {
    /// Dormand-Prince 5(4) with the tolerance derived from the layer, crossings located
    /// inside the steps (the runtime's default for `daec run`).
    Adaptive,
    /// RK4 with this fixed step, crossings located inside the steps.
    Located(f64),
    /// RK4 with this fixed step, crossings noticed at step ends (the thesis's rule).
    StepEnd(f64),
}

impl DbsmcStep {
    fn knob(self) -> String {
        match self {
            DbsmcStep::Adaptive => "adaptive".into(),
            DbsmcStep::Located(h) => format!("h={h:.3e} located"),
            DbsmcStep::StepEnd(h) => format!("h={h:.3e}"),
        }
    }

    fn apply(self, settings: Settings) -> Settings {
        match self {
            DbsmcStep::Adaptive => settings.integrator(Integrator::DormandPrince),
            DbsmcStep::Located(h) => settings.integrator(Integrator::Rk4).step(h),
            DbsmcStep::StepEnd(h) => settings
                .integrator(Integrator::Rk4)
                .step(h)
                .law(StepEnd::default()),
        }
    }
}

/// A method with the value of its accuracy knob.
#[derive(Debug, Clone, PartialEq)]
pub enum Method {
    /// DBSMC with monitoring, layers `eps`, time constants `mu`, gains from
    /// [`Scene::gains`].
    Dbsmc {
        /// Layer half width (all constraints).
        eps: f64,
        /// Surface time constant (all constraints).
        mu: f64,
        /// How it is integrated.
        step: DbsmcStep,
        /// Gain factor over `mu^(r-1) |beta|`.
        gain_factor: f64,
    },
    /// SPSM (the runtime's `Law::Spsm`), RK4 with step `step`.
    Spsm {
        /// Layer half width.
        eps: f64,
        /// Surface time constant.
        mu: f64,
        /// RK4 step.
        step: f64,
        /// Gain factor over `mu^(r-1) |beta|`.
        gain_factor: f64,
    },
    /// DBSMC with monitoring and a per-constraint design from the runtime's toolkit
    /// (see [`DesignedBounds::dbsmc`]): `mu_i` and relaxed gains `k_i` maximising the
    /// guaranteed period for the layer `eps`.
    DbsmcDesigned {
        /// Layer half width (all constraints).
        eps: f64,
        /// Designed surface parameters, per constraint.
        mu: Vec<f64>,
        /// Designed gains, per constraint.
        gains: Vec<f64>,
        /// How it is integrated.
        step: DbsmcStep,
    },
    /// Baseline (a): RK4 with `z` solved from `s = 0` at every stage.
    IndexOne {
        /// Stabilisation time constant.
        mu: f64,
        /// RK4 step.
        step: f64,
    },
    /// Baseline (c): diffsol BDF on the index-1 form.
    Bdf {
        /// Stabilisation time constant.
        mu: f64,
        /// `rtol = atol`.
        tol: f64,
    },
}

impl Method {
    /// The chart line this point belongs to (method and its fixed parameters).
    pub fn line(&self) -> String {
        match self {
            Method::Dbsmc { mu, step, .. } => match step {
                DbsmcStep::StepEnd(_) => format!("DBSMC mu={mu} (step rule)"),
                _ => format!("DBSMC mu={mu}"),
            },
            Method::DbsmcDesigned { step, .. } => match step {
                DbsmcStep::StepEnd(_) => "DBSMC designed (step rule)".to_string(),
                _ => "DBSMC designed".to_string(),
            },
            Method::Spsm { eps, mu, .. } => format!("SPSM eps={eps} mu={mu}"),
            Method::IndexOne { mu, .. } => format!("index-1 RK4 mu={mu}"),
            Method::Bdf { mu, .. } => format!("BDF (diffsol) mu={mu}"),
        }
    }
    /// The swept knob and its value.
    pub fn knob(&self) -> String {
        match self {
            Method::Dbsmc { eps, step, .. } | Method::DbsmcDesigned { eps, step, .. } => {
                format!("eps={eps:.1e} {}", step.knob())
            }
            Method::Spsm { step, .. } | Method::IndexOne { step, .. } => format!("h={step:.3e}"),
            Method::Bdf { tol, .. } => format!("tol={tol:.1e}"),
        }
    }
}

/// One run of one method on one scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Scene name.
    pub scene: String,
    /// Chart line ([`Method::line`]).
    pub line: String,
    /// Knob value ([`Method::knob`]).
    pub knob: String,
    /// Whether the run finished.
    pub ok: bool,
    /// The error message of a failed run (empty otherwise).
    pub error: String,
    /// Largest constraint residual `|w_i|` over the run (all constraints).
    pub max_w: f64,
    /// Largest `|s_i|` over the run (DBSMC/SPSM: after reaching, infinite if never
    /// reached; index-1: left by the stage solves; BDF: not measured, NaN).
    pub max_s: f64,
    /// Position error at `t_end` against the truth ([`Scene::position_error`]).
    pub pos_err: f64,
    /// Best wall time of the repeats, seconds.
    pub wall: f64,
    /// `m x m` factorisations + solves with `J_s` (or `J_Omega`).
    pub j_solves: u64,
    /// Evaluations of `f`.
    pub f_evals: u64,
    /// Integration steps.
    pub steps: u64,
    /// Control updates (DBSMC; 0 for the other methods).
    pub updates: u64,
}

impl Method {
    /// The runtime settings of a DBSMC or SPSM run of `scene` (monitored updates for
    /// DBSMC, continuous `sat` for SPSM, no robustness counting, the scene's start);
    /// `None` for the baselines that do not run on the runtime's simulator.
    pub fn runtime_settings<M: Model + ?Sized>(&self, scene: &Scene<'_, M>) -> Option<Settings> {
        let m = scene.model.n_constraints();
        let (eps, mu, gains, step, policy) = match *self {
            Method::DbsmcDesigned {
                eps,
                ref mu,
                ref gains,
                step,
            } => (eps, mu.clone(), gains.clone(), step, Law::default()),
            Method::Dbsmc {
                eps,
                mu,
                step,
                gain_factor,
            } => (
                eps,
                vec![mu; m],
                scene.gains(mu, gain_factor),
                step,
                Law::default(),
            ),
            Method::Spsm {
                eps,
                mu,
                step,
                gain_factor,
            } => (
                eps,
                vec![mu; m],
                scene.gains(mu, gain_factor),
                DbsmcStep::StepEnd(step),
                Law::Spsm,
            ),
            _ => return None,
        };
        let settings = Settings::new(vec![eps; m], mu, gains)
            .t_end(scene.t_end)
            .law(policy)
            .check_robustness(false)
            .initial(scene.x0.clone(), scene.z0.clone());
        Some(step.apply(settings))
    }
}

struct Outcome {
    updates: u64,
    x: Vec<f64>,
    max_w: f64,
    max_s: f64,
    wall: f64,
    j_solves: u64,
    f_evals: u64,
    steps: u64,
}

fn max_of(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(*x))
}

fn run_once<M: Model + ?Sized>(scene: &Scene<'_, M>, method: &Method) -> Result<Outcome, String> {
    let model = scene.model;
    let m = model.n_constraints();
    match *method {
        Method::DbsmcDesigned { .. } | Method::Dbsmc { .. } | Method::Spsm { .. } => {
            let settings = method
                .runtime_settings(scene)
                .ok_or("no runtime settings for this method")?;
            let s = Simulator::new(model, settings)
                .and_then(|mut sim| sim.run(&mut NoTrace))
                .map_err(|e| e.to_string())?;
            Ok(Outcome {
                // The window's maxima once the layers were reached; before that the
                // residuals seen, and an infinite |s| (the layer never held).
                max_w: s
                    .max_abs_w
                    .as_deref()
                    .map_or_else(|| max_of(&s.seen_max_abs_w), max_of),
                max_s: s.max_abs_s.as_deref().map_or(f64::INFINITY, max_of),
                wall: s.wall_time,
                // Factorisations of J_s (J_Omega is also evaluated at every step's end
                // for the located crossings, but factored only at the updates).
                j_solves: s.solver.factorisations,
                updates: s.updates,
                f_evals: s.f_evals,
                steps: s.steps,
                x: s.x,
            })
        }
        Method::IndexOne { mu, step } => {
            let set = IndexOneSettings {
                mu: vec![mu; m],
                step,
                t_start: 0.0,
                t_end: scene.t_end,
                newton_tol: 1e-12,
                initial: Some(scene.initial()),
            };
            let s = IndexOneRk4::new(model, set)
                .and_then(|mut r| r.run(None))
                .map_err(|e| e.to_string())?;
            Ok(Outcome {
                max_w: max_of(&s.max_abs_w),
                max_s: max_of(&s.max_abs_s),
                wall: s.wall_time,
                j_solves: s.j_solves,
                f_evals: s.rhs_evals,
                steps: s.steps,
                updates: 0,
                x: s.x,
            })
        }
        #[cfg(not(feature = "bdf"))]
        Method::Bdf { .. } => Err(BDF_MISSING.to_string()),
        #[cfg(feature = "bdf")]
        Method::Bdf { mu, tol } => {
            let set = BdfSettings {
                mu: vec![mu; m],
                rtol: tol,
                atol: tol,
                t_start: 0.0,
                t_end: scene.t_end,
                initial: Some(scene.initial()),
            };
            let s = bdf_index1(model, &set, None).map_err(|e| e.to_string())?;
            Ok(Outcome {
                max_w: max_of(&s.max_abs_w),
                max_s: f64::NAN,
                wall: s.wall_time,
                j_solves: s.j_solves,
                f_evals: s.rhs_evals,
                steps: s.steps,
                updates: 0,
                x: s.x,
            })
        }
    }
}

/// Run `method` on `scene` `repeats` times (at least once); the wall time is the best
/// of the repeats, everything else comes from the first run (the runs are
/// deterministic).
pub fn run_method<M: Model + ?Sized>(
    scene: &Scene<'_, M>,
    method: &Method,
    repeats: usize,
) -> Record {
    let mut rec = Record {
        scene: scene.name.clone(),
        line: method.line(),
        knob: method.knob(),
        ok: false,
        error: String::new(),
        max_w: f64::NAN,
        max_s: f64::NAN,
        pos_err: f64::NAN,
        wall: f64::NAN,
        j_solves: 0,
        f_evals: 0,
        steps: 0,
        updates: 0,
    };
    match run_once(scene, method) {
        Err(e) => rec.error = e,
        Ok(o) => {
            let mut wall = o.wall;
            for _ in 1..repeats {
                if let Ok(again) = run_once(scene, method) {
                    wall = wall.min(again.wall);
                }
            }
            let pos_err = scene.position_error(&o.x);
            rec.ok = pos_err.is_finite();
            if !rec.ok {
                rec.error = "non-finite final state".into();
            }
            rec.max_w = o.max_w;
            rec.max_s = o.max_s;
            rec.pos_err = pos_err;
            rec.wall = wall;
            rec.j_solves = o.j_solves;
            rec.f_evals = o.f_evals;
            rec.steps = o.steps;
            rec.updates = o.updates;
        }
    }
    rec
}

/// Write records as CSV (header
/// `scene,line,knob,ok,max_w,max_s,pos_err,wall_s,j_solves,f_evals,steps,updates,error`).
pub fn write_csv<W: Write>(records: &[Record], mut out: W) -> io::Result<()> {
    writeln!(
        out,
        "scene,line,knob,ok,max_w,max_s,pos_err,wall_s,j_solves,f_evals,steps,updates,error"
    )?;
    for r in records {
        writeln!(
            out,
            "{},{},{},{},{:e},{:e},{:e},{:e},{},{},{},{},\"{}\"",
            r.scene,
            r.line,
            r.knob,
            r.ok,
            r.max_w,
            r.max_s,
            r.pos_err,
            r.wall,
            r.j_solves,
            r.f_evals,
            r.steps,
            r.updates,
            r.error.replace('"', "'")
        )?;
    }
    out.flush()
}

//! The stability suite: long runs with a streaming constraint-error envelope, and the
//! verdict table method x scene (holds / drifts / diverges, with the deciding figure).

use std::io::{self, Write};

use dae_runtime::{Model, Simulator, trace::Layout, trace::Sample, trace::Sink};

#[cfg(feature = "bdf")]
use crate::baseline::{BdfSettings, bdf_index1};
use crate::baseline::{IndexOneRk4, IndexOneSettings, largest_stable_step};
use crate::harness::{DbsmcStep, Method, Scene, run_method};

/// A streaming, decimated record of the constraint error: the largest `|w_i|` (over all
/// constraints) in consecutive time windows. Memory is one value per window, whatever
/// the number of steps.
#[derive(Debug, Clone)]
pub struct Envelope {
    window: f64,
    start: f64,
    current: f64,
    open: bool,
    /// End time of each closed window.
    pub times: Vec<f64>,
    /// Largest `|w|` in each closed window.
    pub max_w: Vec<f64>,
    /// Number of samples pushed.
    pub samples: u64,
}

impl Envelope {
    /// An envelope with windows of `window` seconds.
    pub fn new(window: f64) -> Self {
        Self {
            window,
            start: 0.0,
            current: 0.0,
            open: false,
            times: Vec::new(),
            max_w: Vec::new(),
            samples: 0,
        }
    }

    /// Add the residuals `w` at time `t`.
    pub fn push(&mut self, t: f64, w: &[f64]) {
        let v = w.iter().fold(
            0.0f64,
            |m, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
        );
        self.samples += 1;
        if !self.open {
            self.start = t;
            self.current = v;
            self.open = true;
        } else {
            self.current = if v.is_nan() {
                f64::NAN
            } else {
                self.current.max(v)
            };
        }
        if t - self.start >= self.window {
            self.close(t);
        }
    }

    fn close(&mut self, t: f64) {
        if self.open {
            self.times.push(t);
            self.max_w.push(self.current);
            self.open = false;
        }
    }

    /// Close the last, partial window.
    pub fn finish_window(&mut self, t: f64) {
        self.close(t);
    }

    /// Largest `|w|` over the windows whose end lies in the fraction `[from, to]` of the
    /// recorded span.
    pub fn max_between(&self, from: f64, to: f64) -> f64 {
        let (Some(&t0), Some(&t1)) = (self.times.first(), self.times.last()) else {
            return f64::NAN;
        };
        let (a, b) = (t0 + from * (t1 - t0), t0 + to * (t1 - t0));
        self.times
            .iter()
            .zip(&self.max_w)
            .filter(|(t, _)| **t >= a && **t <= b)
            .fold(
                0.0f64,
                |m, (_, w)| if w.is_nan() { f64::NAN } else { m.max(*w) },
            )
    }
}

impl Sink for Envelope {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        self.times.clear();
        self.max_w.clear();
        self.open = false;
        self.samples = 0;
        Ok(())
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.push(s.t, s.w);
        if s.last {
            self.close(s.t);
        }
        Ok(())
    }
    fn update(&mut self, _: f64) -> io::Result<()> {
        Ok(())
    }
}

/// Run `method` on `scene` (over the scene's `[0, t_end]`), streaming `|w|` into an
/// envelope with windows of `window` seconds. Returns the envelope and the final state.
pub fn envelope_run<M: Model + ?Sized>(
    scene: &Scene<'_, M>,
    method: &Method,
    window: f64,
) -> (Envelope, Result<Vec<f64>, String>) {
    let mut env = Envelope::new(window);
    let model = scene.model;
    let m = model.n_constraints();
    let result = match *method {
        Method::DbsmcDesigned { .. } | Method::Dbsmc { .. } | Method::Spsm { .. } => method
            .runtime_settings(scene)
            .ok_or_else(|| "no runtime settings for this method".to_string())
            .and_then(|settings| {
                Simulator::new(model, settings)
                    .and_then(|mut sim| sim.run(&mut env))
                    .map(|s| s.x)
                    .map_err(|e| e.to_string())
            }),
        Method::IndexOne { mu, step } => {
            let set = IndexOneSettings {
                mu: vec![mu; m],
                step,
                t_start: 0.0,
                t_end: scene.t_end,
                newton_tol: 1e-12,
                initial: Some(scene.initial()),
            };
            let mut obs = |t: f64, _: &[f64], w: &[f64]| env.push(t, w);
            let r = IndexOneRk4::new(model, set)
                .and_then(|mut r| r.run(Some(&mut obs)))
                .map(|s| s.x)
                .map_err(|e| e.to_string());
            env.finish_window(scene.t_end);
            r
        }
        #[cfg(not(feature = "bdf"))]
        Method::Bdf { .. } => Err(crate::harness::BDF_MISSING.to_string()),
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
            let mut obs = |t: f64, _: &[f64], w: &[f64]| env.push(t, w);
            let r = bdf_index1(model, &set, Some(&mut obs))
                .map(|s| s.x)
                .map_err(|e| e.to_string());
            env.finish_window(scene.t_end);
            r
        }
    };
    (env, result)
}

/// A stability verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The constraint error stays within the tolerance and does not grow.
    Holds,
    /// Finite, but the constraint error exceeds the tolerance or keeps growing.
    Drifts,
    /// The run failed, became non-finite, or the constraint error reached `0.1`.
    Diverges,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Holds => "holds",
            Verdict::Drifts => "drifts",
            Verdict::Diverges => "diverges",
        })
    }
}

/// One cell of the stability table.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityRow {
    /// Test and scene.
    pub scene: String,
    /// Method line and knob.
    pub method: String,
    /// The verdict.
    pub verdict: Verdict,
    /// The figure that decided it.
    pub figure: String,
    /// The deciding number: max `|w|` over the last half of the run (tests (i) to
    /// (iv); NaN for a failed run), the largest surviving step (test (v); NaN if none),
    /// or the BDF's mean step.
    pub value: f64,
}

/// Growth factor (late over early envelope) above which a run counts as drifting even
/// under the tolerance. Bounded runs on the test scenes stay below 8; a constraint
/// that is not stabilised grows by 70 over 1000 s of the double pendulum.
pub const DRIFT_GROWTH: f64 = 10.0;

/// Envelope values below this are round-off and do not count as growth.
pub const DRIFT_FLOOR: f64 = 1e-10;

/// Judge an envelope: `early` = max `|w|` over the first 10 % of the windows, `late` =
/// over the last half. Diverges if the run failed or `late >= 0.1`; drifts if
/// `late > tol` or `late / max(early, DRIFT_FLOOR) > DRIFT_GROWTH`; holds otherwise.
pub fn judge(env: &Envelope, result: &Result<Vec<f64>, String>, tol: f64) -> (Verdict, String) {
    judged(env, result, tol).0
}

fn judged(env: &Envelope, result: &Result<Vec<f64>, String>, tol: f64) -> ((Verdict, String), f64) {
    let verdict = verdict_of(env, result, tol);
    let late = if result.is_ok() {
        env.max_between(0.5, 1.0)
    } else {
        f64::NAN
    };
    (verdict, late)
}

fn verdict_of(env: &Envelope, result: &Result<Vec<f64>, String>, tol: f64) -> (Verdict, String) {
    if let Err(e) = result {
        return (Verdict::Diverges, format!("failed: {e}"));
    }
    let early = env.max_between(0.0, 0.1);
    let late = env.max_between(0.5, 1.0);
    let growth = late / early.max(DRIFT_FLOOR);
    let fig = format!(
        "max|w| first 10%: {early:.2e}, last 50%: {late:.2e} (x{growth:.1}), tol {tol:.0e}"
    );
    if !late.is_finite() || late >= 0.1 {
        (Verdict::Diverges, fig)
    } else if late > tol || growth > DRIFT_GROWTH {
        (Verdict::Drifts, fig)
    } else {
        (Verdict::Holds, fig)
    }
}

/// Run and judge one method on one scene (tests (i) to (iv)).
pub fn stability_row<M: Model + ?Sized>(
    test: &str,
    scene: &Scene<'_, M>,
    method: &Method,
    tol: f64,
    window: f64,
) -> StabilityRow {
    let (env, result) = envelope_run(scene, method, window);
    let ((verdict, figure), value) = judged(&env, &result, tol);
    StabilityRow {
        scene: format!("{test}: {}", scene.name),
        method: format!("{} {}", method.line(), method.knob()),
        verdict,
        figure,
        value,
    }
}

/// The same method with another fixed step (BDF has none and is returned unchanged);
/// DBSMC then runs RK4 at that step, its crossings located as before (or at step ends
/// if it used the step-end rule).
pub fn with_step(method: &Method, h: f64) -> Method {
    let mut m = method.clone();
    match &mut m {
        Method::Dbsmc { step, .. } | Method::DbsmcDesigned { step, .. } => {
            *step = match step {
                DbsmcStep::StepEnd(_) => DbsmcStep::StepEnd(h),
                _ => DbsmcStep::Located(h),
            }
        }
        Method::Spsm { step, .. } | Method::IndexOne { step, .. } => *step = h,
        Method::Bdf { .. } => {}
    }
    m
}

/// Test (v): the largest step in `[h_min, h_max]` (geometric bisection, `iters` halvings)
/// for which `method` survives `scene`: the run finishes with all values finite and
/// `max |w| <= tol`, and for DBSMC and SPSM also reaches its layers and keeps
/// `max |s_i| <= 2 eps` afterwards (as [`spsm_stable`](crate::baseline::spsm_stable)). For the
/// adaptive BDF the row reports the mean step it takes at its tolerance instead.
pub fn largest_step_row<M: Model + ?Sized>(
    scene: &Scene<'_, M>,
    method: &Method,
    tol: f64,
    h_min: f64,
    h_max: f64,
    iters: usize,
) -> StabilityRow {
    let name = format!("(v) largest step for max|w| <= {tol:.0e}: {}", scene.name);
    if let Method::Bdf { .. } = method {
        let r = run_method(scene, method, 1);
        let (verdict, figure) = if r.ok && r.max_w <= tol {
            (
                Verdict::Holds,
                format!(
                    "adaptive: mean step {:.2e} s ({} steps), max|w| {:.2e}",
                    scene.t_end / r.steps.max(1) as f64,
                    r.steps,
                    r.max_w
                ),
            )
        } else if r.ok {
            (Verdict::Drifts, format!("max|w| {:.2e} > tol", r.max_w))
        } else {
            (Verdict::Diverges, format!("failed: {}", r.error))
        };
        return StabilityRow {
            scene: name,
            method: format!("{} {}", method.line(), method.knob()),
            verdict,
            figure,
            value: scene.t_end / r.steps.max(1) as f64,
        };
    }
    let search = largest_stable_step(
        |h| {
            let r = run_method(scene, &with_step(method, h), 1);
            let layer = match method {
                Method::Dbsmc { eps, .. }
                | Method::DbsmcDesigned { eps, .. }
                | Method::Spsm { eps, .. } => r.max_s <= 2.0 * eps,
                _ => true,
            };
            r.ok && r.max_w <= tol && layer
        },
        h_min,
        h_max,
        iters,
    );
    let (verdict, figure) = match (search.stable, search.unstable) {
        (Some(s), Some(u)) => (
            Verdict::Holds,
            format!("survives h = {s:.3e}, fails at {u:.3e}"),
        ),
        (Some(s), None) => (
            Verdict::Holds,
            format!("survives the largest tried h = {s:.3e}"),
        ),
        (None, _) => (Verdict::Diverges, format!("fails even at h = {h_min:.1e}")),
    };
    StabilityRow {
        scene: name,
        method: method.line(),
        verdict,
        figure,
        value: search.stable.unwrap_or(f64::NAN),
    }
}

/// Write the table as Markdown.
pub fn write_table<W: Write>(rows: &[StabilityRow], mut out: W) -> io::Result<()> {
    writeln!(out, "| test / scene | method | verdict | deciding figure |")?;
    writeln!(out, "|---|---|---|---|")?;
    // A `|` inside a cell (as in `max|w|`) would split it: escape it.
    let cell = |s: &str| s.replace('|', "\\|");
    for r in rows {
        writeln!(
            out,
            "| {} | {} | {} | {} |",
            cell(&r.scene),
            cell(&r.method),
            r.verdict,
            cell(&r.figure)
        )?;
    }
    out.flush()
}

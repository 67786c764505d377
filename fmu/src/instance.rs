//! One FMU instance, apart from the C interface: its variables, its set-up, its steps.
//!
//! An instance is set up (parameters and `eps` may be set), then initialised
//! ([`Instance::exit_initialization`]: the online design of `daec run` and the
//! consistent start), then stepped; the run is DBSMC across each communication step,
//! cut at its end ([`Simulator::advance_to`]).

use dae_runtime::design::{Online, consistent_start};
use dae_runtime::trace::NoTrace;
use dae_runtime::{Model, Simulator};

use crate::config::Config;
use crate::model::Driven;
use crate::variables::{self, Kind, Variable};

/// What a call that did not fail says: all well, or a warning for the log.
#[derive(Debug, PartialEq)]
pub enum Status {
    /// Nothing to report.
    Ok,
    /// The call did its work but something is not right (the layer was left).
    Warning(String),
}

/// Where the instance is in its life.
enum Stage<M: Driven> {
    /// Before `fmi2ExitInitializationMode`: the model alone.
    Setup(M),
    /// Stepping.
    Running(Box<Simulator<M>>),
    /// A step failed: only `fmi2Reset` or `fmi2FreeInstance` help.
    Failed(String),
}

/// One instance of the FMU's model.
pub(crate) struct Instance<M: Driven> {
    config: Config,
    vars: Vec<Variable>,
    stage: Stage<M>,
    eps: f64,
    start: f64,
    stop: Option<f64>,
    /// Each input's `[value, d1, .., dK]` as last set, and whether it changed since it
    /// went into the model.
    inputs: Vec<Vec<f64>>,
    inputs_changed: bool,
    /// Whether the loss of the layer has been reported.
    loss_reported: bool,
    // Scratch for the constraint errors (`w`, `s`, `alpha_hat`, `mu`, the initial point).
    w: Vec<f64>,
    /// Where each constraint's `w` starts in `w` (its `w_i`).
    w_offsets: Vec<usize>,
    s: Vec<f64>,
    ah: Vec<f64>,
    mu: Vec<f64>,
    x0: Vec<f64>,
    z0: Vec<f64>,
}

impl<M: Driven> Instance<M> {
    /// A new instance of `model` with the choices of `config`.
    pub(crate) fn new(model: M, config: Config) -> Self {
        let vars = variables::of(&model, config.eps);
        let m = model.n_constraints();
        let w_offsets: Vec<usize> = model
            .indices()
            .iter()
            .scan(0, |at, &r| {
                let here = *at;
                *at += r;
                Some(here)
            })
            .collect();
        let w_len = model.indices().iter().sum();
        let inputs = (0..model.n_inputs())
            .map(|i| {
                let mut t = model.input_taylor(i).to_vec();
                t.resize(model.input_order(i) + 1, 0.0);
                t
            })
            .collect();
        let mut x0 = vec![0.0; model.n_states()];
        let mut z0 = vec![0.0; m];
        model.initial_state(&mut x0);
        model.initial_alg(&mut z0);
        Instance {
            eps: config.eps,
            start: config.start_time,
            stop: None,
            config,
            vars,
            stage: Stage::Setup(model),
            inputs,
            inputs_changed: false,
            loss_reported: false,
            w: vec![0.0; w_len],
            w_offsets,
            s: vec![0.0; m],
            ah: vec![0.0; m],
            mu: vec![1.0; m],
            x0,
            z0,
        }
    }

    fn model(&self) -> Result<&M, String> {
        match &self.stage {
            Stage::Setup(m) => Ok(m),
            Stage::Running(sim) => Ok(sim.model()),
            Stage::Failed(why) => Err(failed(why)),
        }
    }

    fn variable(&self, vr: u32) -> Result<&Variable, String> {
        self.vars.get(vr as usize).ok_or_else(|| {
            format!(
                "no variable has value reference {vr} (the references are 0 to {})",
                self.vars.len() - 1
            )
        })
    }

    /// `fmi2SetupExperiment`: the start time, and the stop time if there is one.
    pub(crate) fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), String> {
        if !matches!(self.stage, Stage::Setup(_)) {
            return Err("fmi2SetupExperiment after the initialization".into());
        }
        if !start.is_finite() || stop.is_some_and(|s| !(s.is_finite() && s > start)) {
            return Err(format!(
                "the experiment [{start}, {stop:?}]: the start must be finite and the stop finite and after it"
            ));
        }
        self.start = start;
        self.stop = stop;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: the online design for the layers `eps` from the
    /// consistent start at the start time, and the run started there.
    pub(crate) fn exit_initialization(&mut self) -> Result<(), String> {
        let stage = std::mem::replace(&mut self.stage, Stage::Failed(String::new()));
        let Stage::Setup(mut model) = stage else {
            self.stage = stage;
            return Err("fmi2ExitInitializationMode called twice".into());
        };
        let t0 = self.start;
        for (i, taylor) in self.inputs.iter().enumerate() {
            model.set_input(i, t0, taylor)?;
        }
        self.inputs_changed = false;
        let result = design(&model, &self.config, self.eps, t0, self.stop)
            .and_then(|settings| Simulator::new(model, settings).map_err(|e| e.to_string()));
        let mut sim = match result {
            Ok(sim) => sim,
            Err(e) => {
                self.stage = Stage::Failed(e.clone());
                return Err(e);
            }
        };
        if let Err(e) = sim.start(&mut NoTrace) {
            let why = e.to_string();
            self.stage = Stage::Failed(why.clone());
            return Err(why);
        }
        self.stage = Stage::Running(Box::new(sim));
        Ok(())
    }

    /// `fmi2GetReal`.
    pub(crate) fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        // The constraint errors come from one evaluation for the whole call.
        if vrs.iter().any(|&vr| {
            self.vars
                .get(vr as usize)
                .is_some_and(|v| v.kind == Kind::Error)
        }) {
            self.errors()?;
        }
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            let v = self.variable(vr)?;
            let (kind, i) = (v.kind, v.index);
            *o = match kind {
                Kind::Eps => self.eps,
                Kind::Param => self.model()?.param(i),
                Kind::Input => self.inputs[i][0],
                Kind::State => self.point()?.0[i],
                Kind::Alg => self.point()?.1[i],
                Kind::Error => self.w[self.w_offsets[i]],
            };
        }
        Ok(())
    }

    /// The current states and algebraic unknowns (the initial ones before the run).
    fn point(&self) -> Result<(&[f64], &[f64]), String> {
        match &self.stage {
            Stage::Setup(_) => Ok((&self.x0, &self.z0)),
            Stage::Running(sim) => Ok((sim.state(), sim.alg())),
            Stage::Failed(why) => Err(failed(why)),
        }
    }

    /// Every constraint's `w` at the current point, into `self.w`.
    fn errors(&mut self) -> Result<(), String> {
        let (t, x, z, model): (f64, &[f64], &[f64], &M) = match &self.stage {
            // `x0` and `z0` follow the parameters (`new`, `set_real`).
            Stage::Setup(m) => (self.start, &self.x0, &self.z0, m),
            Stage::Running(sim) => (sim.time(), sim.state(), sim.alg(), sim.model()),
            Stage::Failed(why) => return Err(failed(why)),
        };
        model.sliding(t, x, z, &self.mu, &mut self.w, &mut self.s, &mut self.ah);
        Ok(())
    }

    /// `fmi2SetReal`: `eps` and the parameters before the run, the inputs at any time.
    pub(crate) fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        for (&vr, &value) in vrs.iter().zip(values) {
            let v = self.variable(vr)?;
            let (kind, i, name) = (v.kind, v.index, v.name.clone());
            if !value.is_finite() {
                return Err(format!("`{name}` = {value}: a value must be finite"));
            }
            match (kind, &mut self.stage) {
                (Kind::Input, Stage::Failed(why)) => return Err(failed(why)),
                (Kind::Input, _) => {
                    self.inputs[i][0] = value;
                    self.inputs_changed = true;
                }
                (Kind::Eps, Stage::Setup(_)) if value > 0.0 => self.eps = value,
                (Kind::Eps, Stage::Setup(_)) => {
                    return Err(format!("`eps` = {value}: the layer must be > 0"));
                }
                (Kind::Param, Stage::Setup(m)) => {
                    m.set_param(i, value);
                    m.initial_state(&mut self.x0);
                    m.initial_alg(&mut self.z0);
                }
                (Kind::Eps | Kind::Param, _) => {
                    return Err(format!(
                        "`{name}` is a fixed parameter: set it before fmi2ExitInitializationMode"
                    ));
                }
                (Kind::State | Kind::Alg | Kind::Error, _) => {
                    return Err(format!("`{name}` is an output: it cannot be set"));
                }
            }
        }
        Ok(())
    }

    /// `fmi2SetRealInputDerivatives`: derivative `order` (1, 2, ..) of each input.
    pub(crate) fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), String> {
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = self.variable(vr)?;
            if v.kind != Kind::Input {
                return Err(format!("`{}` is not an input", v.name));
            }
            let (i, name) = (v.index, v.name.clone());
            let most = self.inputs[i].len() - 1;
            if order < 1 || order as usize > most || !value.is_finite() {
                return Err(format!(
                    "derivative {order} of `{name}` = {value}: the model reads derivatives 1 to {most}, finite"
                ));
            }
            self.inputs[i][order as usize] = value;
            self.inputs_changed = true;
        }
        Ok(())
    }

    /// `fmi2DoStep`: DBSMC from `t` (the instance's time) to `t + h`.
    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Result<Status, String> {
        let sim = match &mut self.stage {
            Stage::Running(sim) => sim,
            Stage::Setup(_) => return Err("fmi2DoStep before fmi2ExitInitializationMode".into()),
            Stage::Failed(why) => return Err(failed(why)),
        };
        let now = sim.time();
        if !(h.is_finite() && h > 0.0) || (t - now).abs() > 1e-9 * now.abs().max(1.0) {
            return Err(format!(
                "fmi2DoStep from t = {t} by {h}: the instance is at t = {now}, and the step must be > 0"
            ));
        }
        if self.inputs_changed {
            let inputs = &self.inputs;
            let set = sim.change_model(|m| {
                (0..inputs.len()).try_for_each(|i| m.set_input(i, now, &inputs[i]))
            });
            match set {
                Ok(Ok(())) => {}
                Ok(Err(e)) => return Err(e),
                Err(e) => return Err(self.fail(e.to_string())),
            }
            self.inputs_changed = false;
        }
        let target = t + h;
        if let Err(e) = sim.advance_to(target, &mut NoTrace) {
            return Err(self.fail(format!("at t = {}: {e}", target)));
        }
        let Stage::Running(sim) = &self.stage else {
            unreachable!("running")
        };
        if sim.time() < target - 1e-9 * target.abs().max(1.0) {
            return Err(format!(
                "the run ends at the stop time {} of fmi2SetupExperiment, before t = {target}",
                sim.time()
            ));
        }
        match sim.bound_loss() {
            Some(loss) if !self.loss_reported => {
                self.loss_reported = true;
                Ok(Status::Warning(format!(
                    "the layer was left: `{}` first at t = {}, worst |s|/eps = {} (`{}` at t = {}); the bound |s_i| <= eps no longer holds",
                    loss.first_constraint,
                    loss.first_time,
                    loss.worst_ratio,
                    loss.worst_constraint,
                    loss.worst_time
                )))
            }
            _ => Ok(Status::Ok),
        }
    }

    fn fail(&mut self, why: String) -> String {
        self.stage = Stage::Failed(why.clone());
        why
    }

    /// The time of the run (the start time before it).
    pub(crate) fn time(&self) -> f64 {
        match &self.stage {
            Stage::Running(sim) => sim.time(),
            _ => self.start,
        }
    }
}

fn failed(why: &str) -> String {
    format!("the instance failed earlier ({why}): call fmi2Reset or fmi2FreeInstance")
}

/// The settings of `daec run FILE --eps EPS` (its online design with the frame and the
/// search of `config`) from the consistent start at `t0`.
fn design<M: Model>(
    model: &M,
    config: &Config,
    eps: f64,
    t0: f64,
    stop: Option<f64>,
) -> Result<dae_runtime::Settings, String> {
    let m = model.n_constraints();
    let mut online = Online::frame(config.frame);
    match config.mu_search {
        Some(false) => online.search = None,
        Some(true) => online.search_up_to = usize::MAX,
        None => {}
    }
    let settings = online
        .settings(vec![eps; m])
        .map_err(|e| format!("online design: {e}"))?
        .t_start(t0)
        .t_end(stop.unwrap_or(f64::MAX));
    let mut x0 = vec![0.0; model.n_states()];
    let mut z0 = vec![0.0; m];
    model.initial_state(&mut x0);
    model.initial_alg(&mut z0);
    if m > 0 {
        z0 = consistent_start(model, t0, &x0, &z0)
            .map_err(|e| format!("no consistent algebraic start values: {e}"))?
            .z0;
    }
    Ok(settings.initial(x0, z0))
}

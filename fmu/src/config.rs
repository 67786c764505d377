//! What an FMU carries besides its library: the model's source and [`Config`], the
//! choices made when it was exported, both under `resources/`.

use serde::{Deserialize, Serialize};

/// The file of the model's source under `resources/`.
pub const SOURCE_FILE: &str = "model.dae";
/// The file of the [`Config`] under `resources/`.
pub const CONFIG_FILE: &str = "config.json";

/// The choices fixed when the FMU was exported. Everything else a run needs comes from
/// the online design (`dae_runtime::design::Online`), as in `daec run`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// The model of the source file that the FMU runs.
    pub model: String,
    /// Sizes and scalar parameters given at export (`--set N=10`). Sizes fix the
    /// number of variables, so they are not FMU parameters; a scalar parameter set here
    /// becomes its FMU parameter's start value.
    pub sets: Vec<(String, f64)>,
    /// The layer half-width `eps` of every constraint: the start value of the FMU
    /// parameter `eps`.
    pub eps: f64,
    /// The frame of the online design (`daec run --frame`).
    pub frame: f64,
    /// Whether the online design searches for `mu` during the run: `None` leaves it to
    /// the design (on up to its size limit), as `daec run` without `--mu-search`.
    pub mu_search: Option<bool>,
    /// The default experiment: start and stop time, communication step.
    pub start_time: f64,
    /// See [`Config::start_time`].
    pub stop_time: f64,
    /// See [`Config::start_time`].
    pub step_size: f64,
    /// The FMU's `guid`, which `fmi2Instantiate` checks against its argument.
    pub guid: String,
}

impl Config {
    /// The configuration of `model` with the defaults of `daec run` (frame 1/60 s, the
    /// search left to the design) and a default experiment of `stop_time` in frames.
    pub fn new(model: impl Into<String>, eps: f64, stop_time: f64) -> Config {
        Config {
            model: model.into(),
            sets: Vec::new(),
            eps,
            frame: 1.0 / 60.0,
            mu_search: None,
            start_time: 0.0,
            stop_time,
            step_size: 1.0 / 60.0,
            guid: String::new(),
        }
    }

    /// Checks what no type says: finite positive numbers and a stop after the start.
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [
            ("eps", self.eps),
            ("frame", self.frame),
            ("step_size", self.step_size),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v}: must be a finite number > 0"));
            }
        }
        if !(self.start_time.is_finite()
            && self.stop_time.is_finite()
            && self.stop_time > self.start_time)
        {
            return Err(format!(
                "the experiment [{}, {}]: the stop time must be finite and after the start",
                self.start_time, self.stop_time
            ));
        }
        Ok(())
    }
}

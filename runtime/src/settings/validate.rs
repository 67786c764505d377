//! What the types of [`Settings`] cannot say: lengths against the model, finite and
//! positive numbers, and the fixed step that SPSM needs.

use super::{GainRule, Law, Settings, StepEnd, Update};
use crate::SimError;

fn bad(field: &'static str, reason: String) -> Result<(), SimError> {
    Err(SimError::Settings { field, reason })
}

fn positive(field: &'static str, what: &str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        bad(field, format!("{what} {value} must be finite and > 0"))
    }
}

impl Settings {
    /// Check the settings against a model with `n` states and `m` constraints.
    pub(crate) fn validate(&self, n: usize, m: usize) -> Result<(), SimError> {
        let l = &self.layers;
        for (field, v, strict) in [
            ("eps", &l.eps, true),
            ("mu", &l.mu, true),
            ("gains", &l.gains, true),
            ("crossing_margin", &l.crossing_margin, false),
        ] {
            if v.len() != m {
                return bad(field, format!("{} values for {m} constraints", v.len()));
            }
            if let Some((i, x)) = v
                .iter()
                .enumerate()
                .find(|(_, x)| !x.is_finite() || (strict && **x <= 0.0) || **x < 0.0)
            {
                let need = if strict { "> 0" } else { ">= 0" };
                return bad(
                    field,
                    format!("value {i} is {x}, must be finite and {need}"),
                );
            }
        }
        self.validate_integration()?;
        let w = &self.window;
        if !(w.t_start.is_finite() && w.t_end.is_finite() && w.t_end > w.t_start) {
            return bad(
                "t_end",
                format!(
                    "[{}, {}] is not a finite, non-empty interval",
                    w.t_start, w.t_end
                ),
            );
        }
        if w.settle.is_nan() || w.settle < 0.0 {
            return bad("settle", format!("{} must be >= 0", w.settle));
        }
        if w.reaching_limit.is_nan() || w.reaching_limit <= 0.0 {
            return bad(
                "reaching_limit",
                format!("{} must be > 0", w.reaching_limit),
            );
        }
        if !(self.bound_tol >= 0.0 && self.bound_tol.is_finite()) {
            return bad(
                "bound_tol",
                format!("{} must be finite and >= 0", self.bound_tol),
            );
        }
        self.validate_law()?;
        if let Some(init) = &self.initial {
            for (field, v, len, what) in [
                ("initial.x0", &init.x0, n, "states"),
                ("initial.z0", &init.z0, m, "constraints"),
            ] {
                if v.len() != len {
                    return bad(field, format!("{} values for {len} {what}", v.len()));
                }
                if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    return bad(field, format!("value {i} is {x}, must be finite"));
                }
            }
        }
        Ok(())
    }

    /// The step is checked where the integrator uses it, the tolerances where they are
    /// given.
    fn validate_integration(&self) -> Result<(), SimError> {
        let int = &self.integration;
        if !int.integrator.is_adaptive() {
            positive("step", "step", int.step)?;
        }
        if let Some(tol) = int.tolerance {
            if !(tol.rtol.is_finite() && tol.rtol >= 0.0 && tol.atol.is_finite() && tol.atol >= 0.0)
                || tol.rtol + tol.atol <= 0.0
            {
                return bad(
                    "tolerance",
                    format!(
                        "rtol {} and atol {} must be finite, >= 0 and not both 0",
                        tol.rtol, tol.atol
                    ),
                );
            }
        }
        if int.max_step.is_nan() || int.max_step <= 0.0 {
            return bad("max_step", format!("{} must be > 0", int.max_step));
        }
        Ok(())
    }

    fn validate_law(&self) -> Result<(), SimError> {
        let update = |u: Update| match u {
            Update::Fixed { period } => positive("policy", "fixed period", period),
            Update::Monitor { .. } => Ok(()),
        };
        match self.law {
            Law::Spsm => {
                if self.integration.integrator.is_adaptive() {
                    return bad(
                        "integrator",
                        "SPSM is integrated with a fixed step: choose Euler or RK4".into(),
                    );
                }
            }
            Law::StepEnd(StepEnd {
                update: u, raise, ..
            }) => {
                update(u)?;
                if let Some(margin) = raise {
                    positive("raise_gains", "margin", margin)?;
                }
            }
            Law::Dbsmc(d) => {
                update(d.update)?;
                let tol = d.crossing_tol;
                if !(tol > 0.0 && tol < 0.5) {
                    return bad("crossing", format!("tolerance {tol} must be in (0, 0.5)"));
                }
                match d.gains {
                    GainRule::Fixed => {}
                    GainRule::Raise { margin } => positive("raise_gains", "margin", margin)?,
                    GainRule::FollowDrift {
                        safety,
                        graze,
                        raise,
                    } => {
                        positive("follow_drift", "safety", safety)?;
                        if let Some(t) = graze {
                            positive("graze", "min_return", t)?;
                        }
                        if let Some(margin) = raise {
                            positive("raise_gains", "margin", margin)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

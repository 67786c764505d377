//! What the types of [`Settings`] cannot say: lengths against the model, finite and
//! positive numbers, and the fixed step that SPSM needs.

use super::{GainRule, Hold, Law, Scope, Settings, Update};
use crate::SimError;

/// `Ok` if `ok`, else the settings error of `field` with the reason.
fn require(ok: bool, field: &'static str, reason: impl FnOnce() -> String) -> Result<(), SimError> {
    if ok {
        Ok(())
    } else {
        Err(SimError::Settings {
            field,
            reason: reason(),
        })
    }
}

fn positive(field: &'static str, what: &str, value: f64) -> Result<(), SimError> {
    let ok = value.is_finite() && value > 0.0;
    require(ok, field, || {
        format!("{what} {value} must be finite and > 0")
    })
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
            require(v.len() == m, field, || {
                format!("{} values for {m} constraints", v.len())
            })?;
            let bad = |x: f64| !x.is_finite() || (strict && x <= 0.0) || x < 0.0;
            if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| bad(**x)) {
                let need = if strict { "> 0" } else { ">= 0" };
                require(false, field, || {
                    format!("value {i} is {x}, must be finite and {need}")
                })?;
            }
        }
        if let Some(search) = &l.adapt_mu {
            search.check().map_err(|reason| SimError::Settings {
                field: "adapt_mu",
                reason,
            })?;
            require(self.law != Law::Spsm, "adapt_mu", || {
                "SPSM has no control updates whose cost a search of mu could weigh".into()
            })?;
        }
        let int = &self.integration;
        if !int.integrator.is_adaptive() {
            let h = int.step;
            require(h.is_finite() && h > 0.0, "step", || {
                format!("{h} must be finite and > 0")
            })?;
        }
        if let Some(tol) = int.tolerance {
            let ok = |v: f64| v.is_finite() && v >= 0.0;
            require(
                ok(tol.rtol) && ok(tol.atol) && tol.rtol + tol.atol > 0.0,
                "tolerance",
                || {
                    format!(
                        "rtol {} and atol {} must be finite, >= 0 and not both 0",
                        tol.rtol, tol.atol
                    )
                },
            )?;
        }
        require(int.max_step > 0.0, "max_step", || {
            format!("{} must be > 0", int.max_step)
        })?;
        let w = &self.window;
        let span = w.t_start.is_finite() && w.t_end.is_finite() && w.t_end > w.t_start;
        require(span, "t_end", || {
            format!(
                "[{}, {}] is not a finite, non-empty interval",
                w.t_start, w.t_end
            )
        })?;
        require(w.settle >= 0.0, "settle", || {
            format!("{} must be >= 0", w.settle)
        })?;
        require(w.reaching_limit > 0.0, "reaching_limit", || {
            format!("{} must be > 0", w.reaching_limit)
        })?;
        require(
            self.bound_tol >= 0.0 && self.bound_tol.is_finite(),
            "bound_tol",
            || format!("{} must be finite and >= 0", self.bound_tol),
        )?;
        self.validate_law()?;
        if let Some(init) = &self.initial {
            for (field, v, len, what) in [
                ("initial.x0", &init.x0, n, "states"),
                ("initial.z0", &init.z0, m, "constraints"),
            ] {
                require(v.len() == len, field, || {
                    format!("{} values for {len} {what}", v.len())
                })?;
                if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    require(false, field, || format!("value {i} is {x}, must be finite"))?;
                }
            }
        }
        Ok(())
    }

    /// The numbers inside the law, and SPSM's fixed step.
    fn validate_law(&self) -> Result<(), SimError> {
        let (update, raise) = match self.law {
            Law::Spsm => {
                return require(
                    !self.integration.integrator.is_adaptive(),
                    "integrator",
                    || "SPSM is integrated with a fixed step: choose Euler or RK4".into(),
                );
            }
            Law::StepEnd(d) => (d.update, d.raise),
            Law::Dbsmc(d) => {
                let tol = d.crossing_tol;
                require(tol > 0.0 && tol < 0.5, "crossing", || {
                    format!("tolerance {tol} must be in (0, 0.5)")
                })?;
                if let GainRule::FollowDrift { safety, graze, .. } = d.gains {
                    positive("follow_drift", "safety", safety)?;
                    if let Some(t) = graze {
                        positive("graze", "min_return", t)?;
                    }
                }
                (d.update, self.law.raise_margin())
            }
        };
        if let Update::Fixed { period } = update {
            positive("policy", "fixed period", period)?;
        }
        if let Update::Monitor {
            scope: Scope::Blocks { size },
            ..
        } = update
        {
            require(size >= 1, "scope", || {
                "blocks of 0 rows: the size must be >= 1".into()
            })?;
            // A block update solves its own rows only: the gains that follow the drift
            // and the ramp against it are global computations (of `s'` at the update
            // and of `J_s^{-1}` applied to the drift), the raise a global condition.
            let global_only = match self.law {
                Law::Dbsmc(d) if d.gains != GainRule::Fixed => Some("gains other than fixed"),
                Law::Dbsmc(d) if d.hold != Hold::Constant => Some("a ramp against the drift"),
                Law::StepEnd(d) if d.raise.is_some() => Some("raised gains"),
                _ => None,
            };
            if let Some(what) = global_only {
                require(false, "scope", || {
                    format!(
                        "block updates need fixed gains and v held; {what} need global updates (Scope::Global)"
                    )
                })?;
            }
        }
        match raise {
            Some(margin) => positive("raise_gains", "margin", margin),
            None => Ok(()),
        }
    }
}

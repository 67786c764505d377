//! Errors of the design and of the pilot runs in the words of the command line: the
//! flags the user gave and the constraints by their names, instead of the runtime's field
//! names (`t_end`, `gains`, `k_c`) and positions ("constraint 0").

use crate::Reported;
use dae_runtime::{
    Model, SimError, design::DesignError, design::PilotError, design::PilotRunError,
    error::Quantity,
};

/// What a failed simulation carries besides its message, as fields of the JSON object of
/// the failure: `kind` (`non_finite`, `singular_jacobian`, `solver_failed`,
/// `reaching_timeout`, `step_limit`, `step_underflow`, `deadline`, `settings`, ...), `t`
/// (when), and which variable or constraints.
pub(crate) fn sim_error_fields(e: &SimError) {
    use crate::failure::{field, names, number};
    use serde_json::json;
    let kind = match e {
        SimError::Settings { field: f, .. } => {
            field("setting", json!(f));
            "settings"
        }
        SimError::NonFinite {
            kind,
            index,
            name,
            value,
            t,
        } => {
            field("t", number(*t));
            field("quantity", json!(kind.to_string()));
            field("index", json!(index));
            field("value", number(*value));
            match kind {
                Quantity::Sliding | Quantity::Residual => field("constraint", json!(name)),
                _ => field("variable", json!(name)),
            }
            "non_finite"
        }
        SimError::SingularJacobian { t, names: n, .. } => {
            field("t", number(*t));
            names("constraints", n);
            "singular_jacobian"
        }
        SimError::SolverFailed { t, solver, .. } => {
            field("t", number(*t));
            field("solver", json!(solver));
            "solver_failed"
        }
        SimError::ReachingTimeout {
            limit, t, names: n, ..
        } => {
            field("t", number(*t));
            field("limit", number(*limit));
            names("constraints", n);
            "reaching_timeout"
        }
        SimError::StepLimit { limit, t } => {
            field("t", number(*t));
            field("limit", json!(limit));
            "step_limit"
        }
        SimError::StepUnderflow {
            t,
            h,
            near_singular,
        } => {
            field("t", number(*t));
            field("h", number(*h));
            field(
                "near_singular",
                near_singular.map_or(
                    json!(null),
                    |ns| json!({"t": number(ns.t), "ratio": number(ns.pivot_ratio)}),
                ),
            );
            "step_underflow"
        }
        SimError::Deadline { t } => {
            field("t", number(*t));
            "deadline"
        }
        SimError::Backwards { .. } => "backwards",
        SimError::Sink(_) => "trace",
    };
    field("kind", json!(kind));
}

/// A number as a person writes it: `1e300` rather than 301 digits, `0.5` as it is.
pub(crate) fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Checks that a flag's value is finite and `> 0`.
pub(crate) fn positive(flag: &str, value: f64) -> Result<(), Reported> {
    check(value.is_finite() && value > 0.0, || {
        format!("{flag} must be a finite number > 0, got {}", number(value))
    })
}

/// Checks that a flag's value is finite and `>= min`.
pub(crate) fn at_least(flag: &str, value: f64, min: f64) -> Result<(), Reported> {
    check(value.is_finite() && value >= min, || {
        format!(
            "{flag} must be a finite number >= {min}, got {}",
            number(value)
        )
    })
}

/// Checks that every value of a list flag is finite and `> 0`.
pub(crate) fn all_positive(flag: &str, values: &[f64]) -> Result<(), Reported> {
    match values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        Some(v) => check(false, || {
            format!("{flag} must be finite numbers > 0, got {}", number(*v))
        }),
        None => Ok(()),
    }
}

/// `Ok` if `ok`, else the message on stderr.
pub(crate) fn check(ok: bool, message: impl FnOnce() -> String) -> Result<(), Reported> {
    if ok {
        Ok(())
    } else {
        error!("{}", message());
        Err(Reported)
    }
}

/// The flag a quantity of a [`DesignError`] comes from, if the user gave it.
fn flag_of(name: &str) -> Option<&'static str> {
    match name {
        "eps" => Some("--eps"),
        "M" => Some("--m"),
        "|beta|" => Some("--beta"),
        _ => None,
    }
}

/// A design error of one constraint, `name` being how the constraint is called (`None`
/// without a model: the constraint of `--index`, `--beta`, `--m`).
pub(crate) fn design_error(e: &DesignError, name: Option<&str>) -> String {
    match e {
        DesignError::NotPositive { name: q, value } if flag_of(q).is_some() => {
            let flag = flag_of(q).unwrap_or_default();
            format!("{flag} must be a finite number > 0, got {value}")
        }
        DesignError::Negative { name: q, value } if flag_of(q).is_some() => {
            let flag = flag_of(q).unwrap_or_default();
            format!("{flag} must be a finite number >= 0, got {value}")
        }
        DesignError::BadIndex { r, max } => format!("--index must be in 1..={max}, got {r}"),
        DesignError::IndexNotSupported { formula, r } => match name {
            Some(c) => format!(
                "--bound index3 {formula} holds for index 3 only, and `{c}` has index {r}; \
                 use --bound general"
            ),
            None => format!(
                "--bound index3 {formula} holds for index 3 only, got --index {r}; use --bound \
                 general"
            ),
        },
        DesignError::Constraint { source, .. } => design_error(source, name),
        DesignError::NoInteriorMaximum { .. } => format!(
            "{e}\n  hint: the guaranteed period has no best mu for these pilot bounds (little or \
             no drift was measured); give --mu and let the gains be designed"
        ),
        other => other.to_string(),
    }
}

/// What a failed automatic design carries besides its message, as fields of the JSON
/// object of the failure: `stage` (`pilot` or `design`), and for a pilot that failed or
/// left its layers when and which constraint.
pub(crate) fn pilot_run_error_fields(model: &dyn Model, e: &PilotRunError) {
    use crate::failure::{field, number};
    use serde_json::json;
    let name = |i: usize| (i < model.n_constraints()).then(|| model.constraint_name(i).to_string());
    match e {
        PilotRunError::Sim(sim) => {
            field("stage", json!("pilot"));
            sim_error_fields(sim);
        }
        PilotRunError::LayerLost {
            constraint,
            t,
            ratio,
            ..
        } => {
            field("stage", json!("pilot"));
            field("kind", json!("layer_lost"));
            field("t", number(*t));
            field("constraint", json!(name(*constraint)));
            field("ratio", number(*ratio));
        }
        PilotRunError::Pilot(_) => field("stage", json!("pilot")),
        _ => field("stage", json!("design")),
    }
}

/// A failed automatic design (pilot runs, estimates, design) of `model`.
pub(crate) fn pilot_run_error(model: &dyn Model, e: &PilotRunError) -> String {
    let constraint = |i: usize| {
        if i < model.n_constraints() {
            model.constraint_name(i).to_string()
        } else {
            format!("#{}", i + 1)
        }
    };
    match e {
        PilotRunError::Sim(SimError::Settings { field, reason }) => {
            let flag = match *field {
                "t_end" => "--pilot",
                "eps" => "--eps",
                "mu" => "--pilot-mu",
                "gains" => "--pilot-gain",
                "step" => "--step",
                "settle" => "--settle",
                other => other,
            };
            format!("pilot run: {flag}: {reason}")
        }
        PilotRunError::OverBudget { budget, pass, t } => format!(
            "the pilot runs took more than {} s (--pilot-budget) and were stopped, pass {pass} at t = {t:.6} of its pilot\n  hint: --design online needs no pilot; or a longer --pilot-budget, a shorter --pilot",
            budget.as_secs_f64()
        ),
        PilotRunError::Sim(sim) => format!("pilot run failed: {sim}"),
        PilotRunError::Pilot(PilotError::NoDriftData { constraint: i }) => format!(
            "the pilot run gave no drift data for constraint `{}`: no control interval after \
             the reaching phase and --settle had two samples at distinct times (the pilot \
             did not reach its layers, or the system hardly moves); --design online needs \
             no pilot, or give --mu and --gain",
            constraint(*i)
        ),
        PilotRunError::Pilot(PilotError::NonFinite {
            what,
            t,
            constraint: Some(i),
        }) => format!(
            "the pilot run gave a non-finite {what} at t = {t} for constraint `{}`",
            constraint(*i)
        ),
        PilotRunError::Pilot(PilotError::BadSafety(s)) => {
            format!("--safety must be a finite number >= 1, got {s}")
        }
        PilotRunError::Pilot(p) => format!("pilot estimate failed: {p}"),
        PilotRunError::Design(DesignError::Constraint { index, source }) => {
            let c = constraint(*index);
            format!("constraint `{c}`: {}", design_error(source, Some(&c)))
        }
        PilotRunError::Design(d) => format!("design failed: {}", design_error(d, None)),
        PilotRunError::LayerLost {
            constraint: i,
            t,
            ratio,
            gain_max,
            near_singular_at,
            ..
        } => match near_singular_at {
            Some(ts) => format!(
                "every pilot left its layers (the last, with gains up to {gain_max:e}: \
                 constraint `{}` at t = {t}, |s|/eps = {ratio:.3}); J_s was nearly singular \
                 at t = {ts:.6}\n  hint: no gain keeps a layer where J_Omega is singular; \
                 check the model there, or give --mu and --gain to see the run",
                constraint(*i)
            ),
            None => format!(
                "every pilot left its layers (the last, with gains up to {gain_max:e}: \
                 constraint `{}` at t = {t}, |s|/eps = {ratio:.3})\n  hint: a larger \
                 --pilot-gain or --pilot-retries, or give --mu and --gain",
                constraint(*i)
            ),
        },
        other => other.to_string(),
    }
}

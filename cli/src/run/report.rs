//! The summary of `daec run`, printed as text or as JSON.

use super::args::Integration;
use super::{Args, DesignInfo, Outcome};
use dae_runtime::{
    Model, Settings, Summary, settings::Integrator, settings::Law, summary::NEAR_SINGULAR,
    summary::values_text,
};
use serde_json::json;

/// Everything the summary reports.
pub(super) struct Report<'a> {
    pub(super) args: &'a Args,
    pub(super) model: &'a dyn Model,
    pub(super) settings: &'a Settings,
    pub(super) summary: &'a Summary,
    pub(super) design: Option<&'a DesignInfo>,
    /// The consistent start, unless `--start given`.
    pub(super) start: Option<&'a super::Start>,
    pub(super) integration: &'a Integration,
    pub(super) outcome: Outcome,
}

impl Report<'_> {
    pub(super) fn print(&self) {
        if let Some(line) = self.loud_line() {
            // On stderr too, so that a script reading stdout (or a user reading only
            // the end) cannot miss it.
            eprintln!("error: {line}");
        }
        if self.args.json {
            let mut v = self.json();
            crate::bounded::summarise(&mut v, self.model);
            println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        } else {
            self.text();
        }
    }

    /// The line that says the run did not keep its promise.
    fn loud_line(&self) -> Option<String> {
        let s = self.summary;
        match self.outcome {
            Outcome::Held => None,
            Outcome::NotReached => Some(format!(
                "the layers were not reached by t = {}: the reaching phase did not finish (exit status 4)",
                s.t_end
            )),
            Outcome::BoundLost => {
                let l = s.bound_loss.as_ref()?;
                let mut line = format!(
                    "BOUND LOST: `{}` left its layer at t = {:.6} after reaching; max |s|/eps = {:.4} (`{}`, at t = {:.6}); {} step(s), {:.4e} s outside",
                    l.first_constraint,
                    l.first_time,
                    l.worst_ratio,
                    l.worst_constraint,
                    l.worst_time,
                    l.steps_outside,
                    l.time_outside
                );
                if let Some(ns) = &l.near_singular {
                    line.push_str(&format!(
                        "; J_s was nearly singular at t = {:.6} (its conditioning fell to {:.2e} of what it was earlier in the run, below {NEAR_SINGULAR:e})",
                        ns.t, ns.pivot_ratio
                    ));
                }
                line.push_str(" (exit status 3)");
                Some(line)
            }
        }
    }

    fn integrator_name(&self) -> String {
        let st = self.settings;
        match st.integration.integrator {
            Integrator::DormandPrince | Integrator::BogackiShampine => {
                let tol = st.effective_tolerance();
                let name = if st.integration.integrator == Integrator::DormandPrince {
                    "Dormand-Prince 5(4)"
                } else {
                    "Bogacki-Shampine 3(2)"
                };
                let how = if st.integration.tolerance.is_some() {
                    ""
                } else if st.layers.eps.is_empty() {
                    " (the default without constraints)"
                } else {
                    " (0.01 x the smallest eps)"
                };
                format!("{name}, tolerance {:e}{how}", tol.rtol)
            }
            Integrator::Rk4 => format!("RK4, fixed step {:e}", st.integration.step),
            Integrator::Euler => format!("Euler, fixed step {:e}", st.integration.step),
        }
    }

    fn crossing_name(&self) -> String {
        match self.settings.law {
            Law::Dbsmc(d) => format!("located in the step (to {:e} of eps)", d.crossing_tol),
            Law::StepEnd(_) => "at step ends (thesis rule)".into(),
            Law::Spsm => "none (SPSM recomputes v at every stage)".into(),
        }
    }

    fn start_json(&self) -> serde_json::Value {
        match self.start {
            None => json!({"z": "given"}),
            Some(st) => json!({
                "z": "consistent",
                "z0": st.found.z0,
                "newton_iterations": st.found.iterations,
                "residual_given": st.found.residual_before,
                "residual": st.found.residual_after,
                "worst_given": self.model.constraint_name(st.found.worst_before),
            }),
        }
    }

    fn json(&self) -> serde_json::Value {
        let (s, st, model) = (self.summary, self.settings, self.model);
        let tol = st.effective_tolerance();
        let given = |text: &str| {
            if text.trim() == "auto" {
                "designed"
            } else {
                "given"
            }
        };
        let mut v = json!({
            "model": s.model,
            "constraints": s.constraints,
            "status": match self.outcome {
                Outcome::Held => "held",
                Outcome::BoundLost => "bound lost",
                Outcome::NotReached => "not reached",
            },
            "exit_status": self.outcome.code(),
            "eps": st.layers.eps,
            "mu": st.layers.mu,
            "gain": st.layers.gains,
            "chosen": {
                "mu": if model.n_constraints() == 0 { "none" } else { given(&self.args.mu) },
                "gain": if model.n_constraints() == 0 { "none" } else { given(&self.args.gain) },
                "integrator": if self.integration.chosen { "chosen" } else { "given" },
            },
            "integrator": {
                "name": format!("{:?}", st.integration.integrator),
                "adaptive": st.integration.integrator.is_adaptive(),
                "step": (!st.integration.integrator.is_adaptive()).then_some(st.integration.step),
                "rtol": st.integration.integrator.is_adaptive().then_some(tol.rtol),
                "atol": st.integration.integrator.is_adaptive().then_some(tol.atol),
                "max_step": st.integration.max_step.is_finite().then_some(st.integration.max_step),
                "crossing": self.crossing_name(),
            },
            "design": self.design.map(|d| d.json.clone()),
            "t_end": s.t_end,
            "steps": s.steps,
            "rejected_steps": s.rejected_steps,
            "located_crossings": s.located_crossings,
            "unlocated_steps": s.unlocated_steps,
            "updates": s.updates,
            "f_evals": s.f_evals,
            "f_evals_per_update": s.f_evals as f64 / s.updates.max(1) as f64,
            "reaching_updates": s.reaching_updates,
            "update_scope": match s.blocks {
                None => json!({"name": "global"}),
                Some(b) => json!({
                    "name": "blocks",
                    "blocks": b.blocks,
                    "largest_block": b.largest,
                    "block_solves": b.block_solves,
                    "global_updates": b.global_updates,
                }),
            },
            "triggered_updates": s.triggered_updates,
            "reach_time": s.reaching_time,
            "stats_from": s.stats_from,
            "period_min": s.min_period,
            "period_avg": s.mean_period,
            "max_abs_s": s.max_abs_s,
            "max_abs_w": s.max_abs_w,
            "max_abs_s_seen": s.seen_max_abs_s,
            "max_abs_w_seen": s.seen_max_abs_w,
            "bound_loss": s.bound_loss,
            "min_pivot_ratio": s.min_pivot_ratio.map(|(r, t)| json!({"ratio": r, "t": t})),
            "robustness_violations": s.robustness_violations,
            "solver": {
                "name": s.solver.name,
                "choice": s.solver.choice.to_string(),
                "factorisations": s.solver.factorisations,
                "solves": s.solver.solves,
                "iterations": s.solver.iterations,
                "robustness_failures": s.solver.robustness_failures,
                "set_aside": s.solver.set_aside,
                "set_aside_max": s.solver.set_aside_max,
            },
            "states": (0..model.n_states()).map(|i| model.state_name(i)).collect::<Vec<_>>(),
            "x_final": s.x,
            "z_final": s.z,
            "z_eq_final": s.z_eq,
            "z_star_final": s.z_star,
            "s_final": s.s,
            "w_final": s.w,
            "wall_seconds": s.wall_time,
        });
        v["start"] = self.start_json();
        v["mu_search"] = serde_json::to_value(s.mu_search).unwrap_or_default();
        v
    }

    /// The loud line (if any), the summary's text, then the settings the run used.
    fn text(&self) {
        let (s, st) = (self.summary, self.settings);
        if let Some(line) = self.loud_line() {
            println!("{line}");
        }
        println!("{s}");
        if !s.constraints.is_empty() {
            let how = |text: &str| {
                if text.trim() == "auto" {
                    "designed"
                } else {
                    "given"
                }
            };
            println!(
                "  mu = {} ({}), gains = {} ({}), eps = {}",
                values_text(&st.layers.mu),
                how(&self.args.mu),
                values_text(&st.layers.gains),
                how(&self.args.gain),
                values_text(&st.layers.eps)
            );
        }
        println!(
            "  integrator {} ({}), crossings {}",
            self.integrator_name(),
            if self.integration.chosen {
                "chosen"
            } else {
                "given"
            },
            self.crossing_name()
        );
        if let Some(st) = self.start {
            println!("{}", start_line(self.model, &st.found));
        }
        if let Some(d) = self.design {
            println!("{}", d.line);
        }
    }
}

/// How far the model's own algebraic values were from consistent, and what was done.
fn start_line(model: &dyn Model, st: &dae_runtime::design::ConsistentStart) -> String {
    if st.iterations == 0 {
        return "  start z consistent as given".to_string();
    }
    format!(
        "  start z made consistent: max |w^(r-1)| {:.3e} (`{}`) at the given z, {:.3e} after {} Newton iteration{} (--start given keeps the given z)",
        st.residual_before,
        model.constraint_name(st.worst_before),
        st.residual_after,
        st.iterations,
        if st.iterations == 1 { "" } else { "s" }
    )
}

//! A model that gives `Omega`'s rate in one pass ([`Model::omega_rate`]): the simulator
//! reads `s'` from it at the end of every step and evaluates `J_Omega` only where an
//! update needs it. The pendulum with its rate written as `beta + J_Omega zdot` (summed
//! in the order the simulator sums them) must run to the bit as the pendulum without,
//! on every path that reads `s'` (fixed and error-controlled steps, cuts, updates, the
//! ramp against the drift, the gains that follow it), with fewer `J_Omega` evaluations.

mod common;

use std::cell::RefCell;

use common::pendulum::Pendulum;
use dae_runtime::{AlphaChoice, Integrator, Model, Settings, Simulator, Summary, Trace};

/// The pendulum with `omega_rate` composed from its own `beta` and `J_Omega`.
struct Rated {
    inner: Pendulum,
    jvals: RefCell<Vec<f64>>,
}

impl Model for Rated {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn n_states(&self) -> usize {
        self.inner.n_states()
    }
    fn n_constraints(&self) -> usize {
        self.inner.n_constraints()
    }
    fn n_params(&self) -> usize {
        self.inner.n_params()
    }
    fn state_name(&self, i: usize) -> &str {
        self.inner.state_name(i)
    }
    fn alg_name(&self, i: usize) -> &str {
        self.inner.alg_name(i)
    }
    fn constraint_name(&self, i: usize) -> &str {
        self.inner.constraint_name(i)
    }
    fn param_name(&self, i: usize) -> &str {
        self.inner.param_name(i)
    }
    fn indices(&self) -> &[usize] {
        self.inner.indices()
    }
    fn param(&self, i: usize) -> f64 {
        self.inner.param(i)
    }
    fn set_param(&mut self, i: usize, value: f64) {
        self.inner.set_param(i, value)
    }
    fn initial_state(&self, x: &mut [f64]) {
        self.inner.initial_state(x)
    }
    fn initial_alg(&self, z: &mut [f64]) {
        self.inner.initial_alg(z)
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.inner.rhs(t, x, z, dx)
    }
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        self.inner.sliding(t, x, z, mu, w, s, ah)
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        self.inner.jacobian_pattern()
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.inner.jacobian(t, x, z, values)
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.inner.beta(t, x, z, beta)
    }
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        let mut jvals = self.jvals.borrow_mut();
        self.inner.jacobian(t, x, z, &mut jvals);
        self.inner.beta(t, x, z, rate);
        for (&(i, j), a) in self.inner.jacobian_pattern().iter().zip(jvals.iter()) {
            rate[i] += a * zdot[j];
        }
        true
    }
}

fn rated() -> Rated {
    let inner = Pendulum::default();
    let n = inner.jacobian_pattern().len();
    Rated {
        inner,
        jvals: RefCell::new(vec![0.0; n]),
    }
}

fn run<M: Model>(model: M, settings: Settings) -> (Summary, Trace) {
    let mut trace = Trace::new();
    let summary = Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    (summary, trace)
}

fn pendulum(h: f64) -> Settings {
    let (mu, beta) = ([0.076, 0.066], [1.3e3, 2.3e3]);
    let gains = (0..2).map(|i| mu[i] * mu[i] * beta[i]).collect();
    Settings::new(vec![0.2; 2], mu.to_vec(), gains)
        .step(h)
        .t_end(2.0)
}

#[test]
fn a_model_that_gives_omegas_rate_runs_to_the_bit_with_fewer_jacobians() {
    let designs = [
        ("RK4", pendulum(0.02)),
        (
            "RK4 ramped, exact alpha",
            pendulum(0.02)
                .ramp_against_drift()
                .alpha(AlphaChoice::Exact),
        ),
        (
            "Dormand-Prince, ramped",
            pendulum(0.02)
                .integrator(Integrator::DormandPrince)
                .max_step(0.02)
                .ramp_against_drift(),
        ),
        (
            "Dormand-Prince, gains following the drift",
            pendulum(0.02)
                .integrator(Integrator::DormandPrince)
                .max_step(0.02)
                .follow_drift(1.0),
        ),
    ];
    for (label, settings) in designs {
        let (plain, plain_trace) = run(Pendulum::default(), settings.clone());
        let (fast, fast_trace) = run(rated(), settings);
        assert!(plain.updates > 20, "{label}: {} updates", plain.updates);
        assert!(plain.located_crossings > 0, "{label}: no cut");
        assert_eq!(plain.rate_evals, 0, "{label}");
        assert!(fast.rate_evals >= fast.steps, "{label}: {fast:?}");
        assert_eq!(
            (fast.steps, fast.updates, fast.located_crossings),
            (plain.steps, plain.updates, plain.located_crossings),
            "{label}"
        );
        assert_eq!(fast.x, plain.x, "{label}: final state");
        assert_eq!(fast.z, plain.z, "{label}: final tensions");
        assert_eq!(fast_trace.times(), plain_trace.times(), "{label}");
        // `J_Omega` only where an update or a sample's `z*` needs it, never at a step's
        // end for `s'` alone.
        assert!(
            fast.jacobian_evals < plain.jacobian_evals,
            "{label}: J_Omega {} with the rate, {} without",
            fast.jacobian_evals,
            plain.jacobian_evals
        );
        eprintln!(
            "{label}: {} steps, {} updates; J_Omega {} against {}, beta {} against {}, rate {}",
            fast.steps,
            fast.updates,
            fast.jacobian_evals,
            plain.jacobian_evals,
            fast.beta_evals,
            plain.beta_evals,
            fast.rate_evals
        );
    }
}

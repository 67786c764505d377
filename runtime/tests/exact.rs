//! Convergence of `x` and `z_eq` to exact solutions as the layer `eps` shrinks.

mod common;

use common::{Chain, Tracking};
use dae_runtime::{AlphaChoice, Model, Policy, Settings, Simulator, Trace};

/// Max errors of `x[0]` and `z_eq[0]` against the exact solution over `t >= 0.5`.
fn errors<M: Model>(
    model: &M,
    settings: Settings,
    exact_x: fn(f64) -> f64,
    exact_z: fn(f64) -> f64,
) -> (f64, f64) {
    let mut trace = Trace::new();
    Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    let (mut ex, mut ez) = (0.0f64, 0.0f64);
    for (i, &t) in trace.times().iter().enumerate() {
        if t >= 0.5 {
            ex = ex.max((trace.x(i)[0] - exact_x(t)).abs());
            ez = ez.max((trace.z_eq(i)[0] - exact_z(t)).abs());
        }
    }
    (ex, ez)
}

/// Asserts that each tenfold reduction of eps reduces the error by a factor in [4, 25]
/// (first order: 10) and returns the observed rates `log10(e_k / e_{k+1})`.
fn assert_first_order(label: &str, errs: &[f64]) -> Vec<f64> {
    let rates: Vec<f64> = errs.windows(2).map(|p| (p[0] / p[1]).log10()).collect();
    eprintln!("{label}: errors {errs:?}, rates per decade of eps {rates:?}");
    for (k, p) in errs.windows(2).enumerate() {
        let ratio = p[0] / p[1];
        assert!(
            (4.0..=25.0).contains(&ratio),
            "{label}: error ratio {ratio} at refinement {k}"
        );
    }
    rates
}

#[test]
fn index2_x_and_z_eq_converge_linearly_in_eps() {
    let mut ex = Vec::new();
    let mut ez = Vec::new();
    for eps in [1e-3, 1e-4, 1e-5] {
        // Gain proportional to eps keeps the update period (2 eps / k = 1 ms) and hence
        // its ratio to mu fixed, so the error scales with eps; the factor is large enough
        // that the drift of beta within a period (about mu |beta'| T) stays far below k.
        // Exact alpha, so that no |beta| has to be covered by the gain.
        let settings = Settings::new(vec![eps], vec![0.05], vec![2000.0 * eps])
            .step(1e-5)
            .alpha(AlphaChoice::Exact)
            .t_end(2.0);
        let (x, z) = errors(&Tracking::default(), settings, f64::sin, |t| {
            t.sin() + t.cos()
        });
        ex.push(x);
        ez.push(z);
    }
    assert_first_order("index 2, x", &ex);
    assert_first_order("index 2, z_eq", &ez);
    // |w| <= eps inside the layer (T 3.10).
    assert!(ex[2] <= 1e-5);
}

#[test]
fn index4_chain_x_and_z_eq_converge_linearly_in_eps() {
    let mut ex = Vec::new();
    let mut ez = Vec::new();
    for eps in [1e-5, 1e-6, 1e-7] {
        let settings = Settings::new(vec![eps], vec![0.2], vec![20.0 * eps])
            .step(1e-4)
            .alpha(AlphaChoice::Exact)
            .t_end(3.0);
        let (x, z) = errors(&Chain, settings, f64::sin, |t| -t.cos());
        ex.push(x);
        ez.push(z);
    }
    assert_first_order("index 4, x1", &ex);
    assert_first_order("index 4, z_eq", &ez);
}

#[test]
fn cheap_alpha_keeps_the_layer_bounds_on_the_chain() {
    // Cheap alpha: the gain must cover mu^(r-1) |beta| = mu^3 |sin t| <= mu^3.
    let (eps, mu) = (1e-6, 0.2);
    let settings = Settings::new(vec![eps], vec![mu], vec![1.5 * mu * mu * mu])
        .step(1e-5)
        .t_end(2.0);
    let (ex, ez) = errors(&Chain, settings, f64::sin, |t| -t.cos());
    eprintln!("index 4 cheap alpha: max |x1 - sin t| = {ex:e}, max |z_eq + cos t| = {ez:e}");
    // |w| <= eps (T 3.10), up to one step of overshoot.
    assert!(ex <= 1.05 * eps, "x error {ex}");
    // z_eq - z = -(3 mu^2 w'' + 3 mu w' + w) / mu^3 with |w^(j)| <= 2^j eps / mu^j.
    let bound = (3.0 * 4.0 + 3.0 * 2.0 + 1.0) * eps / mu.powi(3);
    assert!(ez <= bound, "z_eq error {ez} above {bound}");
}

#[test]
fn spsm_baseline_converges_linearly_in_eps() {
    let mut ex = Vec::new();
    let mut ez = Vec::new();
    for eps in [1e-2, 1e-3, 1e-4] {
        let settings = Settings::new(vec![eps], vec![0.05], vec![0.2])
            .step(1e-4)
            .policy(Policy::Spsm)
            .t_end(3.0);
        let (x, z) = errors(&Tracking::default(), settings, f64::sin, |t| {
            t.sin() + t.cos()
        });
        ex.push(x);
        ez.push(z);
    }
    assert_first_order("SPSM index 2, x", &ex);
    assert_first_order("SPSM index 2, z_eq", &ez);
}

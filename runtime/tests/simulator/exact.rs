//! Convergence of `x` and `z_eq` to exact solutions as the layer `eps` shrinks.

use crate::common;

use common::{Chain, Tracking};
use dae_runtime::settings::Law;
use dae_runtime::{Model, Settings, Simulator, Trace, settings::AlphaChoice, settings::Integrator};

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
            .law(Law::Spsm)
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

/// Max errors of `z`, `z_eq` and `z*` over `t >= 0.5` against the exact `z`.
fn algebraic_errors<M: Model>(model: &M, settings: Settings, exact_z: fn(f64) -> f64) -> [f64; 3] {
    let mut trace = Trace::new();
    let s = Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    assert!(s.bound_held(), "{:?}", s.bound_loss);
    let mut e = [0.0f64; 3];
    for (i, &t) in trace.times().iter().enumerate() {
        if t >= 0.5 {
            let z = exact_z(t);
            e[0] = e[0].max((trace.z(i)[0] - z).abs());
            e[1] = e[1].max((trace.z_eq(i)[0] - z).abs());
            e[2] = e[2].max((trace.z_star(i)[0] - z).abs());
        }
    }
    e
}

/// Which algebraic output to trust (the crate docs' table): `z*` solves `Omega = 0` at
/// the current state. Index 4 (`Omega = z + cos t`, independent of `x`): `z*` is exact.
/// Index 2 (`Omega = z - x - cos t`): `z* - z_exact = -(x - sin t) = -w`, bounded by
/// eps (T 3.10) and below `z_eq`'s error.
#[test]
fn z_star_is_exact_for_the_chain_and_within_the_layer_for_the_tracking_model() {
    let mut chain = Vec::new();
    let mut track = Vec::new();
    for eps in [1e-2, 1e-3, 1e-4] {
        // The setting for the chain: mu = 0.05; exact alpha, gain 20 eps.
        let s = Settings::new(vec![eps], vec![0.05], vec![20.0 * eps])
            .integrator(Integrator::DormandPrince)
            .alpha(AlphaChoice::Exact)
            .t_end(3.0);
        chain.push(algebraic_errors(&Chain, s, |t| -t.cos()));
        // A fixed gain: the update period 2 eps / k shrinks with the layer, so that the
        // ramp's own error (about z'' T^2) does not put a floor under the error.
        let s = Settings::new(vec![eps], vec![0.05], vec![2.0])
            .integrator(Integrator::DormandPrince)
            .alpha(AlphaChoice::Exact)
            .t_end(3.0);
        track.push(algebraic_errors(&Tracking::default(), s, |t| {
            t.sin() + t.cos()
        }));
    }
    for (label, rows) in [("index 4 chain", &chain), ("index 2 tracking", &track)] {
        for (eps, r) in [1e-2, 1e-3, 1e-4].iter().zip(rows.iter()) {
            eprintln!(
                "{label}, eps {eps:e}: max |z - z_exact| {:.3e}, |z_eq - z_exact| {:.3e}, |z* - z_exact| {:.3e}",
                r[0], r[1], r[2]
            );
        }
    }
    for r in &chain {
        assert!(r[2] < 1e-12, "chain z* {r:?}");
        assert!(r[1] > 1e6 * r[2], "chain z_eq {r:?}");
    }
    // z* - z_exact = -w, and |w| <= eps inside the layer (T 3.10); measured well below.
    for (eps, r) in [1e-2, 1e-3, 1e-4].iter().zip(&track) {
        assert!(r[2] <= 0.1 * eps, "tracking {r:?}");
        assert!(r[2] <= r[1] && r[2] <= r[0], "tracking {r:?}");
    }
    assert!(
        track.windows(2).all(|p| p[1][2] < 0.2 * p[0][2]),
        "{track:?}"
    );
}

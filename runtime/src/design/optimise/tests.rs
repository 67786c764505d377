use super::*;
use crate::design::LayerBound;

fn pendulum_link(beta_abs: f64, m: f64, layer: LayerBound) -> ConstraintSpec {
    ConstraintSpec {
        r: 3,
        eps: 0.2,
        m,
        beta_abs,
        layer,
    }
}

/// docs/method.md section 8 / thesis chapter 5: sufficient gains with (T 3.14).
#[test]
fn thesis_example_sufficient_gains_give_mu_0065_and_0060() {
    let links = [
        pendulum_link(1.3e3, 9e4, LayerBound::General),
        pendulum_link(2.3e3, 11e4, LayerBound::General),
    ];
    let d = design(&links, GainChoice::Sufficient, &MuSearch::default()).unwrap();
    eprintln!("sufficient / (T 3.14): {d:?}");
    let (mu1, mu2) = (d.constraints[0].mu, d.constraints[1].mu);
    assert!((mu1 - 0.065).abs() <= 0.002, "mu1 = {mu1}");
    assert!((mu2 - 0.060).abs() <= 0.002, "mu2 = {mu2}");
    assert_eq!(d.limiting, 1);
}

/// docs/method.md section 8 / thesis chapter 5: relaxed gains with (T 4.6).
#[test]
fn thesis_example_relaxed_gains_give_mu_0076_0066_and_periods_00062_00053() {
    let links = [
        pendulum_link(1.3e3, 9e4, LayerBound::TightIndex3),
        pendulum_link(2.3e3, 11e4, LayerBound::TightIndex3),
    ];
    let d = design(&links, GainChoice::Relaxed, &MuSearch::default()).unwrap();
    eprintln!("relaxed / (T 4.6): {d:?}");
    let [c1, c2] = [d.constraints[0], d.constraints[1]];
    assert!((c1.mu - 0.076).abs() <= 0.002, "mu1 = {}", c1.mu);
    assert!((c2.mu - 0.066).abs() <= 0.002, "mu2 = {}", c2.mu);
    assert!((c1.t_min / 0.0062 - 1.0).abs() <= 0.03, "T1 = {}", c1.t_min);
    assert!((c2.t_min / 0.0053 - 1.0).abs() <= 0.03, "T2 = {}", c2.t_min);
    assert_eq!(d.t_min, c2.t_min);
    // The gain reported is the relaxed one at the chosen mu.
    assert!((c1.k - c1.mu * c1.mu * 1.3e3).abs() < 1e-9);
}

/// At the published mu (0.076, 0.066), relaxed gains with (T 4.6) give the published
/// periods 0.0062 / 0.0053 (docs/method.md section 8), and each entry is `t_min` at its mu and
/// gain; a wrong number of mu is an error, not a panic.
#[test]
fn design_at_the_thesis_mu_gives_the_published_periods() {
    let links = [
        pendulum_link(1.3e3, 9e4, LayerBound::TightIndex3),
        pendulum_link(2.3e3, 11e4, LayerBound::TightIndex3),
    ];
    let mu = [0.076, 0.066];
    let d = design_at(&links, &mu, GainChoice::Relaxed).unwrap();
    for (i, c) in d.constraints.iter().enumerate() {
        assert_eq!(c.mu, mu[i]);
        assert_eq!(c.k, mu[i] * mu[i] * links[i].beta_abs);
        assert_eq!(c.t_min, t_min(&links[i], mu[i], c.k).unwrap());
    }
    assert!((d.constraints[0].t_min / 0.0062 - 1.0).abs() <= 0.03);
    assert!((d.constraints[1].t_min / 0.0053 - 1.0).abs() <= 0.03);
    assert_eq!((d.limiting, d.t_min), (1, d.constraints[1].t_min));
    assert!(matches!(
        design_at(&links, &[0.07], GainChoice::Relaxed),
        Err(DesignError::CountMismatch {
            what: "mu",
            got: 1,
            expected: 2
        })
    ));
    assert!(matches!(
        design_at(&links, &[0.07, -1.0], GainChoice::Relaxed),
        Err(DesignError::Constraint { index: 1, .. })
    ));
}

/// Oracle: with M = 0, T = eps / b and b = mu^(r-1) |beta| + c_r eps / mu is minimal at
/// mu* = (c_r eps / ((r-1) |beta|))^(1/r).
#[test]
fn relaxed_optimum_without_drift_matches_closed_form() {
    for (r, c) in [(2usize, 4.0), (3, 12.0), (4, 28.0)] {
        let spec = ConstraintSpec {
            r,
            eps: 0.05,
            m: 0.0,
            beta_abs: 300.0,
            layer: LayerBound::General,
        };
        let got = optimise_mu(&spec, GainChoice::Relaxed, &MuSearch::default()).unwrap();
        let mu_star = (c * 0.05 / ((r - 1) as f64 * 300.0)).powf(1.0 / r as f64);
        assert!(
            (got.mu / mu_star - 1.0).abs() < 1e-6,
            "r = {r}: {} vs {mu_star}",
            got.mu
        );
        let b = mu_star.powi(r as i32 - 1) * 300.0 + c * 0.05 / mu_star;
        assert!((got.t_min / (0.05 / b) - 1.0).abs() < 1e-12);
    }
}

/// Oracle: a dense brute-force grid, and a vanishing central difference at the optimum.
#[test]
fn optimum_beats_a_dense_grid_and_is_stationary() {
    let cases = [
        (
            2,
            0.01,
            5e3,
            40.0,
            LayerBound::General,
            GainChoice::Sufficient,
        ),
        (
            3,
            0.2,
            9e4,
            1.3e3,
            LayerBound::Spectrum { omega_m: 20.0 },
            GainChoice::Sufficient,
        ),
        (
            3,
            0.2,
            11e4,
            2.3e3,
            LayerBound::General,
            GainChoice::Relaxed,
        ),
        (
            4,
            1e-3,
            1e6,
            10.0,
            LayerBound::General,
            GainChoice::Fixed(3.0),
        ),
        (
            5,
            0.1,
            2.0,
            0.5,
            LayerBound::General,
            GainChoice::Sufficient,
        ),
    ];
    for (r, eps, m, beta_abs, layer, gain) in cases {
        let spec = ConstraintSpec {
            r,
            eps,
            m,
            beta_abs,
            layer,
        };
        let got = optimise_mu(&spec, gain, &MuSearch::default()).unwrap();
        let t = |mu: f64| t_min(&spec, mu, gain.gain(&spec, mu).unwrap()).unwrap();
        let n = 100_000;
        let (lo, hi) = (1e-6f64.ln(), 1e3f64.ln());
        let grid_best = (0..n)
            .map(|i| t((lo + (hi - lo) * i as f64 / (n - 1) as f64).exp()))
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(
            got.t_min >= grid_best * (1.0 - 1e-14),
            "r = {r}: {got:?} < {grid_best}"
        );
        let h = 1e-4;
        let slope = (t(got.mu * (1.0 + h)) - t(got.mu * (1.0 - h))) / (2.0 * h * got.t_min);
        assert!(slope.abs() < 1e-6, "r = {r}: relative slope {slope}");
        assert_eq!(got.k, gain.gain(&spec, got.mu).unwrap());
    }
}

#[test]
fn maximum_outside_the_range_is_reported() {
    let spec = pendulum_link(1.3e3, 9e4, LayerBound::General);
    let search = MuSearch {
        lo: 0.1,
        hi: 0.2,
        ..MuSearch::default()
    };
    match optimise_mu(&spec, GainChoice::Sufficient, &search) {
        Err(DesignError::NoInteriorMaximum { mu, .. }) => assert!((mu - 0.1).abs() < 1e-12),
        other => panic!("expected NoInteriorMaximum, got {other:?}"),
    }
}

#[test]
fn bad_search_ranges_are_errors() {
    let spec = pendulum_link(1.3e3, 9e4, LayerBound::General);
    for search in [
        MuSearch {
            lo: 0.0,
            ..MuSearch::default()
        },
        MuSearch {
            lo: 2.0,
            hi: 1.0,
            ..MuSearch::default()
        },
        MuSearch {
            hi: f64::NAN,
            ..MuSearch::default()
        },
        MuSearch {
            scan_points: 2,
            ..MuSearch::default()
        },
        MuSearch {
            ln_tol: 0.0,
            ..MuSearch::default()
        },
    ] {
        assert!(
            matches!(
                optimise_mu(&spec, GainChoice::Sufficient, &search),
                Err(DesignError::BadSearch { .. })
            ),
            "{search:?}"
        );
    }
}

#[test]
fn index_one_ignores_mu() {
    let spec = ConstraintSpec {
        r: 1,
        eps: 0.1,
        m: 50.0,
        beta_abs: 2.0,
        layer: LayerBound::General,
    };
    let got = optimise_mu(&spec, GainChoice::Sufficient, &MuSearch::default()).unwrap();
    assert_eq!(got.mu, 1.0);
    // k = 2 sqrt(M eps) + |beta|; T solves M T^2 + k T = eps.
    let k = 2.0 * 5f64.sqrt() + 2.0;
    assert!((got.k - k).abs() < 1e-14);
    assert!((50.0 * got.t_min * got.t_min + k * got.t_min - 0.1).abs() < 1e-15);
}

#[test]
fn design_takes_the_smallest_period_and_names_failing_constraints() {
    let a = pendulum_link(1.3e3, 9e4, LayerBound::General);
    let b = ConstraintSpec { m: 1e7, ..a };
    let d = design(&[a, b, a], GainChoice::Sufficient, &MuSearch::default()).unwrap();
    assert_eq!(d.limiting, 1);
    assert!(d.t_min < d.constraints[0].t_min);
    assert_eq!(d.constraints[0], d.constraints[2]);

    let bad = ConstraintSpec { eps: -1.0, ..a };
    match design(&[a, bad], GainChoice::Sufficient, &MuSearch::default()) {
        Err(DesignError::Constraint { index: 1, source }) => {
            assert!(matches!(
                *source,
                DesignError::NotPositive { name: "eps", .. }
            ))
        }
        other => panic!("expected a constraint error, got {other:?}"),
    }
    assert_eq!(
        design(&[], GainChoice::Sufficient, &MuSearch::default()),
        Err(DesignError::NoConstraints)
    );
}

/// A constraint without drift (`M = 0`, `beta = 0`) beside the thesis's links: with the
/// relaxed gain (`k = 0`) its period is `T(mu) = eps / (c_3 eps / mu) = mu / c_3`, which
/// grows without a maximum; it must get the closed-form smallest mu that keeps the
/// others' period, `mu = c_3 T_min` with `c_3 = 12` under (T 3.14), and not limit.
#[test]
fn a_quiet_constraint_takes_the_smallest_mu_that_keeps_the_period() {
    let links = [
        pendulum_link(1.3e3, 9e4, LayerBound::General),
        pendulum_link(0.0, 0.0, LayerBound::General),
        pendulum_link(2.3e3, 11e4, LayerBound::General),
    ];
    let d = design(&links, GainChoice::Relaxed, &MuSearch::default()).unwrap();
    let alone = design(
        &[links[0], links[2]],
        GainChoice::Relaxed,
        &MuSearch::default(),
    )
    .unwrap();
    assert_eq!(d.quiet, vec![1]);
    assert_eq!(
        d.t_min, alone.t_min,
        "the quiet link must not change the period"
    );
    assert_eq!(d.limiting, 2);
    let q = d.constraints[1];
    let closed_form = 12.0 * alone.t_min;
    assert!(
        (q.mu - closed_form).abs() <= 1e-8 * closed_form,
        "mu {} against 12 T_min = {closed_form}",
        q.mu
    );
    assert!(q.t_min >= d.t_min);
    assert_eq!(q.k, 0.0);
}

/// Only quiet constraints: there is no period to keep, so the design has no mu to give.
#[test]
fn only_quiet_constraints_are_an_error_naming_the_first() {
    let links = [
        pendulum_link(0.0, 0.0, LayerBound::General),
        pendulum_link(0.0, 0.0, LayerBound::General),
    ];
    match design(&links, GainChoice::Relaxed, &MuSearch::default()) {
        Err(DesignError::Constraint { index: 0, source }) => {
            assert!(
                matches!(*source, DesignError::NoInteriorMaximum { .. }),
                "{source:?}"
            )
        }
        other => panic!("expected the first constraint's NoInteriorMaximum, got {other:?}"),
    }
}

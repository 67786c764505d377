//! `design::Online`: the design without a pilot, from the layers and a time scale.

use crate::common::pendulum::Pendulum;
use dae_runtime::design::{DesignError, Online, OnlineError};
use dae_runtime::settings::{AlphaChoice, GainRule, InLayer, Integrator, Law};
use dae_runtime::{Simulator, Trace};

#[test]
fn the_settings_are_the_frame_tied_recipe() {
    let o = Online::frame(0.04);
    let s = o.settings(vec![1e-3, 4e-3]).unwrap();
    let mu = 0.25 * 0.04;
    assert_eq!(s.layers.mu, vec![mu; 2]);
    assert_eq!(s.layers.gains, vec![4.0 * 1e-3 / mu, 4.0 * 4e-3 / mu]);
    assert_eq!(s.integration.integrator, Integrator::DormandPrince);
    assert_eq!(s.integration.max_step, 0.5 * mu);
    let tol = s.integration.tolerance.unwrap();
    assert_eq!((tol.rtol, tol.atol), (1e-4, 1e-4));
    assert_eq!(s.alpha, AlphaChoice::Exact);
    let Law::Dbsmc(d) = s.law else {
        panic!("{:?}", s.law)
    };
    assert_eq!(
        d.gains,
        GainRule::FollowDrift {
            safety: 1.0,
            graze: Some(0.125 * mu),
            raise: None
        }
    );
    assert_eq!(d.in_layer, InLayer::Saturate);
}

#[test]
fn out_of_range_values_are_errors_naming_them() {
    let err = Online::frame(0.0).settings(vec![1e-3]).unwrap_err();
    assert!(
        matches!(err, DesignError::NotPositive { name: "frame", .. }),
        "{err}"
    );
    let low = Online {
        floor: 2.0,
        ..Online::default()
    };
    assert!(low.settings(vec![1e-3]).is_err());
    let err = Online::default().settings(vec![1e-3, -1.0]).unwrap_err();
    assert!(
        matches!(err, DesignError::Constraint { index: 1, .. }),
        "{err}"
    );
    let p = Pendulum::default();
    let err = Online::default().design(&p, &[1e-3; 3], 1.0).unwrap_err();
    assert!(
        matches!(
            err,
            OnlineError::Design(DesignError::CountMismatch { got: 3, .. })
        ),
        "{err}"
    );
}

#[test]
fn one_call_runs_the_thesis_pendulum_within_its_layers() {
    // The 3-D double pendulum of docs/method.md section 8, from its own start.
    let p = Pendulum::default();
    let settings = Online::default().design(&p, &[0.01], 2.0).unwrap();
    assert_eq!(settings.window.t_end, 2.0);
    let start = settings.initial.clone().expect("a consistent start");
    assert_eq!(start.x0.len(), 12);
    let summary = Simulator::new(&p, settings)
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    assert!(summary.bound_held(), "{:?}", summary.bound_loss);
    let worst = summary
        .max_abs_s
        .unwrap()
        .iter()
        .fold(0.0f64, |a, &b| a.max(b));
    assert!(worst <= 1.01 * 0.01, "{worst}");
}

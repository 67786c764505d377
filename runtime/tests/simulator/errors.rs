//! Typed run-time errors, and the trace kept up to the failure.

use crate::common;

use common::Tracking;
use dae_runtime::settings::StepEnd;
use dae_runtime::{Settings, SimError, Simulator, Trace, error::Quantity};

/// A fixed grid (the step-end rule), so that the failure's time is a grid point.
fn settings() -> Settings {
    Settings::new(vec![1e-3], vec![0.05], vec![0.2])
        .step(1e-3)
        .law(StepEnd::default())
        .t_end(2.0)
}

#[test]
fn nan_in_the_middle_of_a_run_names_the_state_and_time_and_keeps_the_trace() {
    let model = Tracking {
        nan_after: 0.7005,
        ..Tracking::default()
    };
    let mut trace = Trace::new();
    let err = Simulator::new(&model, settings())
        .unwrap()
        .run(&mut trace)
        .unwrap_err();
    match err {
        SimError::NonFinite {
            kind,
            index,
            ref name,
            value,
            t,
        } => {
            assert_eq!(kind, Quantity::State);
            assert_eq!((index, name.as_str()), (0, "x"));
            assert!(value.is_nan());
            // f is NaN from t = 0.7005 on: the RK4 step from 0.700 to 0.701 fails (its midpoint
            // stages) and is reported at its end.
            assert!((t - 0.701).abs() < 1e-9, "t = {t}");
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(
        err.to_string().contains("`x`") && err.to_string().contains("0.701"),
        "{err}"
    );
    // Every step before the failure was recorded, all finite and on the solution.
    assert_eq!(trace.len(), 701);
    let last = trace.len() - 1;
    assert!((trace.times()[last] - 0.7).abs() < 1e-12);
    assert!((trace.x(last)[0] - 0.7f64.sin()).abs() < 1e-3);
    assert!(!trace.update_times().is_empty());
    let mut csv = Vec::new();
    trace.write_csv(&mut csv).unwrap();
    let text = String::from_utf8(csv).unwrap();
    assert_eq!(text.lines().count(), 702);
    assert!(text.lines().all(|l| !l.contains("NaN")));
}

#[test]
fn singular_jacobian_names_the_constraint_and_time() {
    let model = Tracking {
        singular: true,
        ..Tracking::default()
    };
    let err = Simulator::new(&model, settings())
        .unwrap()
        .run(&mut Trace::new())
        .unwrap_err();
    // Named as written, not as a debug list (`["track"]`).
    let text = err.to_string();
    assert!(
        text.contains("constraints `track` have") && !text.contains('['),
        "{text}"
    );
    match err {
        SimError::SingularJacobian {
            t,
            constraints,
            names,
        } => {
            assert_eq!(t, 0.0);
            assert_eq!(constraints, vec![0]);
            assert_eq!(names, vec!["track".to_string()]);
        }
        other => panic!("unexpected error {other}"),
    }
}

#[test]
fn unfinished_reaching_phase_is_an_error_after_the_limit() {
    // Start 1.0 away from the constraint with a gain that needs ~20 s to get there.
    let model = Tracking {
        x0: 1.0,
        ..Tracking::default()
    };
    let s = Settings::new(vec![1e-3], vec![0.05], vec![0.05])
        .step(1e-3)
        .t_end(5.0)
        .reaching_limit(0.5);
    let mut trace = Trace::new();
    let err = Simulator::new(&model, s)
        .unwrap()
        .run(&mut trace)
        .unwrap_err();
    match err {
        SimError::ReachingTimeout { limit, t, names, s } => {
            assert_eq!(limit, 0.5);
            assert!(t > 0.5 && t < 0.5 + 2e-3, "t = {t}");
            assert_eq!(names, vec!["track".to_string()]);
            assert!(s[0].abs() > 1e-3);
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(trace.len() >= 500);
}

#[test]
fn settings_that_do_not_fit_the_model_are_rejected() {
    let model = Tracking::default();
    let wrong_len = Settings::new(vec![1e-3, 1e-3], vec![0.05, 0.05], vec![0.2, 0.2]);
    assert!(matches!(
        Simulator::new(&model, wrong_len),
        Err(SimError::Settings { field: "eps", .. })
    ));
    let zero_mu = Settings::new(vec![1e-3], vec![0.0], vec![0.2]);
    assert!(matches!(
        Simulator::new(&model, zero_mu),
        Err(SimError::Settings { field: "mu", .. })
    ));
    let bad_step = settings().step(-1.0);
    assert!(matches!(
        Simulator::new(&model, bad_step),
        Err(SimError::Settings { field: "step", .. })
    ));
    let empty = settings().t_end(0.0);
    assert!(matches!(
        Simulator::new(&model, empty),
        Err(SimError::Settings { field: "t_end", .. })
    ));
}

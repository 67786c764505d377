//! `Settings::initial`: starting from a given `(x0, z0)` instead of the model's own.

use crate::common;

use common::Tracking;
use dae_runtime::{Settings, SimError, Simulator, Trace};

fn settings() -> Settings {
    Settings::new(vec![1e-3], vec![0.05], vec![0.2])
        .step(1e-3)
        .t_end(0.5)
}

fn trace_of(model: &Tracking, settings: Settings) -> Trace {
    let mut trace = Trace::new();
    Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    trace
}

#[test]
fn given_start_replaces_the_models_initial_values_exactly() {
    // The oracle: the same model whose own initial values are the given ones.
    let own = Tracking {
        x0: 0.3,
        ..Tracking::default()
    };
    let given = Tracking::default();
    let a = trace_of(&own, settings());
    let b = trace_of(&given, settings().initial(vec![0.3], vec![1.0]));
    assert_eq!(b.x(0), &[0.3]);
    assert_eq!(a.len(), b.len());
    for k in 0..a.len() {
        assert_eq!(a.x(k), b.x(k), "sample {k}");
        assert_eq!(a.z(k), b.z(k), "sample {k}");
    }
    // And it differs from the model's own start (x0 = 0).
    let c = trace_of(&given, settings());
    assert_eq!(c.x(0), &[0.0]);
}

#[test]
fn given_algebraic_start_is_used() {
    let m = Tracking::default();
    let t = trace_of(&m, settings().initial(vec![0.0], vec![1.7]));
    // The first sample is taken after the first update, before any step: z is still z0.
    assert_eq!(t.z(0), &[1.7]);
}

fn settings_error(s: Settings) -> (&'static str, String) {
    match Simulator::new(&Tracking::default(), s) {
        Err(SimError::Settings { field, reason }) => (field, reason),
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted bad initial values"),
    }
}

#[test]
fn wrong_lengths_are_typed_errors_naming_the_vector() {
    let (field, reason) = settings_error(settings().initial(vec![0.0, 1.0], vec![1.0]));
    assert_eq!(field, "initial.x0");
    assert!(reason.contains("2 values for 1 states"), "{reason}");
    let (field, reason) = settings_error(settings().initial(vec![0.0], vec![]));
    assert_eq!(field, "initial.z0");
    assert!(reason.contains("0 values for 1 constraints"), "{reason}");
}

#[test]
fn non_finite_values_are_typed_errors_naming_the_entry() {
    let (field, reason) = settings_error(settings().initial(vec![f64::NAN], vec![1.0]));
    assert_eq!(field, "initial.x0");
    assert!(reason.contains("value 0 is NaN"), "{reason}");
    let (field, reason) = settings_error(settings().initial(vec![0.0], vec![f64::INFINITY]));
    assert_eq!(field, "initial.z0");
    assert!(reason.contains("value 0 is inf"), "{reason}");
}

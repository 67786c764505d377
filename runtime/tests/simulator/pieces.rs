//! A run in pieces (`start`, `advance_to`, `finish`), a model changed between pieces
//! with a forced update, and a model without constraints.

use crate::common;

use common::{Offset, Oscillator, Tracking};
use dae_runtime::{Settings, SimError, Simulator, Trace, settings::Integrator, trace::NoTrace};

fn settings() -> Settings {
    Settings::new(vec![1e-3], vec![0.05], vec![0.2])
        .integrator(Integrator::DormandPrince)
        .t_end(2.0)
}

#[test]
fn a_run_in_pieces_ends_where_the_whole_run_does() {
    let whole = Simulator::new(&Tracking::default(), settings())
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    let mut sim = Simulator::new(Tracking::default(), settings()).unwrap();
    let mut trace = Trace::new();
    sim.start(&mut trace).unwrap();
    for k in 1..=8 {
        sim.advance_to(0.25 * k as f64, &mut trace).unwrap();
        assert_eq!(sim.time(), 0.25 * k as f64);
    }
    let pieces = sim.finish(&mut trace).unwrap();
    assert_eq!(pieces.t_end, 2.0);
    // The pieces end steps at their boundaries, so the trajectories differ within the
    // layer, not beyond it.
    assert!((pieces.x[0] - whole.x[0]).abs() < 2e-3);
    assert!(pieces.bound_held() && whole.bound_held());
    // Every piece boundary is a sample, recorded once, in order.
    let t = trace.times();
    assert!(t.windows(2).all(|p| p[1] > p[0]), "{t:?}");
    for k in 1..=8 {
        let tk = 0.25 * k as f64;
        assert_eq!(t.iter().filter(|&&x| x == tk).count(), 1, "{tk}");
    }
    assert_eq!(*t.last().unwrap(), 2.0);
    // Going back is an error, and so is going on after finish.
    assert!(matches!(
        sim.advance_to(1.0, &mut trace),
        Err(SimError::Backwards { finished: true, .. })
    ));
}

#[test]
fn advancing_backwards_is_refused() {
    let mut sim = Simulator::new(Tracking::default(), settings()).unwrap();
    sim.advance_to(0.5, &mut NoTrace).unwrap();
    let err = sim.advance_to(0.4, &mut NoTrace).unwrap_err();
    assert!(matches!(
        err,
        SimError::Backwards {
            finished: false,
            ..
        }
    ));
    assert!(err.to_string().contains("t = 0.5"), "{err}");
}

#[test]
fn a_model_changed_between_pieces_is_followed_after_a_forced_update() {
    let mut sim = Simulator::new(Offset { c: 0.0, push: 0.0 }, settings().t_end(3.0)).unwrap();
    let mut trace = Trace::new();
    sim.start(&mut trace).unwrap();
    sim.advance_to(1.0, &mut trace).unwrap();
    // Move the tracked curve by 0.01 (ten layers): the state is now outside.
    sim.model_mut().c = 0.01;
    sim.request_update();
    sim.advance_to(3.0, &mut trace).unwrap();
    let s = sim.finish(&mut trace).unwrap();
    // The update was made at the change, with the new s.
    assert!(
        trace.update_times().contains(&1.0),
        "{:?}",
        trace.update_times()
    );
    let k = trace.times().iter().position(|&t| t == 1.0).unwrap();
    assert!(
        trace.s(k)[0] < -5e-3,
        "s after the change {}",
        trace.s(k)[0]
    );
    // The new curve is followed.
    assert!((s.x[0] - (3.0f64.sin() + 0.01)).abs() < 2e-3, "{:?}", s.x);
    // The jump of the layer is reported as leaving it, from the change on.
    let loss = s.bound_loss.expect("the change put the state outside");
    assert!((loss.first_time - 1.0).abs() < 1e-9, "{loss:?}");
    assert!(loss.worst_ratio > 5.0);
}

/// A push that the tension must balance, switched on between pieces: the state and `w`
/// are continuous, but `w'` (the part of `s` that depends on `z`) jumps by the push,
/// and `s` by `mu` times it (10 layers here). Through `model_mut` the layer is left;
/// through `change_model` `z` takes the jump (exactly `-push`: `w'` is affine in `z`)
/// and the bound holds.
#[test]
fn a_change_of_the_model_keeps_s_continuous_through_change_model() {
    let push = 0.2;
    let run = |carry: bool| {
        let mut sim = Simulator::new(Offset { c: 0.0, push: 0.0 }, settings().t_end(3.0)).unwrap();
        let mut trace = Trace::new();
        sim.start(&mut trace).unwrap();
        sim.advance_to(1.0, &mut trace).unwrap();
        let (z_before, s_before) = (sim.alg()[0], sim.sliding()[0]);
        if carry {
            let old = sim
                .change_model(|m| std::mem::replace(&mut m.push, push))
                .unwrap();
            assert_eq!(old, 0.0);
            // z moved by exactly -push, before any step.
            assert!((sim.alg()[0] - (z_before - push)).abs() < 1e-14);
        } else {
            sim.model_mut().push = push;
            sim.request_update();
        }
        sim.advance_to(3.0, &mut trace).unwrap();
        let summary = sim.finish(&mut trace).unwrap();
        let k = trace.times().iter().position(|&t| t == 1.0).unwrap();
        (summary, trace.s(k)[0], s_before)
    };
    let (lost, s_jumped, s0) = run(false);
    assert!(
        (s_jumped - s0 - 0.05 * push).abs() < 1e-12,
        "{s_jumped} vs {s0}"
    );
    let loss = lost.bound_loss.expect("the push put s outside its layer");
    assert!((loss.first_time - 1.0).abs() < 1e-9, "{loss:?}");
    let (held, s_after, s0) = run(true);
    assert!(
        (s_after - s0).abs() < 1e-12,
        "s jumped from {s0} to {s_after}"
    );
    assert!(held.bound_held(), "{:?}", held.bound_loss);
    // The new tension balances the push: z = sin t + cos t - push.
    assert!(
        (held.z[0] - (3.0f64.sin() + 3.0f64.cos() - push)).abs() < 0.05,
        "{:?}",
        held.z
    );
}

/// Before the run starts, `change_model` changes the model the run will start from.
#[test]
fn change_model_before_the_start_changes_the_initial_model() {
    let mut sim = Simulator::new(Offset { c: 0.0, push: 0.0 }, settings().t_end(0.5)).unwrap();
    sim.change_model(|m| m.c = 0.01).unwrap();
    let s = sim.run(&mut NoTrace).unwrap();
    assert!((s.x[0] - (0.5f64.sin() + 0.01)).abs() < 2e-3, "{:?}", s.x);
    assert!(s.bound_held());
}

/// A change that makes `J_Omega` singular is refused with the solver's located error.
#[test]
fn change_model_to_a_singular_j_omega_is_a_located_error() {
    let mut sim = Simulator::new(Tracking::default(), settings()).unwrap();
    sim.advance_to(0.5, &mut NoTrace).unwrap();
    let err = sim.change_model(|m| m.singular = true).unwrap_err();
    assert!(matches!(err, SimError::SingularJacobian { .. }), "{err}");
    assert!(err.to_string().contains("track"), "{err}");
}

#[test]
fn a_model_without_constraints_is_integrated_as_an_ode() {
    for integrator in [
        Integrator::DormandPrince,
        Integrator::BogackiShampine,
        Integrator::Rk4,
    ] {
        let settings = Settings::new(vec![], vec![], vec![])
            .integrator(integrator)
            .step(1e-3)
            .tolerance(1e-9, 1e-9)
            .t_end(10.0);
        let mut trace = Trace::new();
        let s = Simulator::new(&Oscillator, settings)
            .unwrap()
            .run(&mut trace)
            .unwrap();
        assert!(
            (s.x[0] - 10.0f64.cos()).abs() < 1e-6,
            "{integrator:?}: {:?}",
            s.x
        );
        assert_eq!(s.updates, 1);
        assert!(s.bound_held());
        assert_eq!(s.max_abs_s, Some(vec![]));
        assert_eq!(trace.layout().columns(), ["t", "x.x", "x.v"]);
    }
}

/// A passed wall-clock deadline stops `advance_to` after the step it is in, at a point
/// that the run goes on from as if it had not stopped: with Dormand-Prince, the run
/// stopped at every step ends where the whole run does, to the bit.
#[test]
fn a_passed_deadline_stops_a_piece_at_a_point_the_run_goes_on_from() {
    let whole = Simulator::new(&Tracking::default(), settings())
        .unwrap()
        .run(&mut NoTrace)
        .unwrap();
    let mut sim = Simulator::new(Tracking::default(), settings()).unwrap();
    sim.start(&mut NoTrace).unwrap();
    sim.set_deadline(Some(std::time::Instant::now()));
    let mut stops = 0;
    loop {
        match sim.advance_to(2.0, &mut NoTrace) {
            Ok(()) => break,
            Err(SimError::Deadline { t }) => {
                assert_eq!(t, sim.time());
                stops += 1;
            }
            Err(e) => panic!("{e}"),
        }
    }
    let stopped = sim.finish(&mut NoTrace).unwrap();
    assert_eq!(stops as u64, stopped.steps, "one stop after every step");
    assert_eq!(stopped.x, whole.x);
    assert_eq!(stopped.updates, whole.updates);
    assert!(stopped.bound_held());
    // Without a deadline nothing stops.
    let mut sim = Simulator::new(Tracking::default(), settings()).unwrap();
    sim.set_deadline(None);
    sim.advance_to(2.0, &mut NoTrace).unwrap();
}

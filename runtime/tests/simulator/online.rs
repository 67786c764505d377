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

/// The online design of the thesis pendulum at `eps` over `t_end`, with or without its
/// search for `mu`.
fn pendulum_online(eps: f64, t_end: f64, search: bool) -> dae_runtime::Summary {
    let p = Pendulum::default();
    let mut online = Online::default();
    if !search {
        online.search = None;
    }
    let settings = online.design(&p, &[eps], t_end).unwrap();
    assert_eq!(settings.layers.adapt_mu.is_some(), search);
    Simulator::new(&p, settings)
        .unwrap()
        .run(&mut Trace::new())
        .unwrap()
}

#[test]
fn the_search_moves_mu_up_on_a_slow_motion_at_a_loose_layer_and_keeps_the_layer() {
    // At eps = 0.2 the thesis's own design has mu = 0.065, 16 times the frame-tied
    // quarter frame: the search must find its way there, and pay less for it.
    let searched = pendulum_online(0.2, 4.0, true);
    let fixed = pendulum_online(0.2, 4.0, false);
    assert!(searched.bound_held(), "{:?}", searched.bound_loss);
    let a = searched.mu_search.expect("the search's summary");
    assert_eq!(a.frames, 240, "one look per frame of 1/60 s over 4 s");
    assert!(a.moves > 0 && a.scale >= 8.0, "{a:?}");
    assert!(fixed.mu_search.is_none());
    // The work the search weighs, counted: at most half of the frame-tied design's.
    let work = |s: &dae_runtime::Summary| s.f_evals + s.solver.factorisations;
    assert!(
        2 * work(&searched) <= work(&fixed),
        "searched {} against {}",
        work(&searched),
        work(&fixed)
    );
    // The summary's text says what the search did.
    let text = searched.to_string();
    assert!(text.contains("mu searched for over 240 frames"), "{text}");
}

#[test]
fn the_search_follows_the_settings_and_a_bad_search_is_refused_by_field() {
    let o = Online::frame(0.04);
    let s = o.settings(vec![1e-3]).unwrap();
    let a = s.layers.adapt_mu.expect("on by default");
    assert_eq!(a.frame, 0.04, "the search looks at the design's frames");
    assert_eq!((a.min_scale, a.max_scale), (1.0 / 16.0, 64.0));
    // Above `search_up_to` constraints mu is kept.
    let big = o.settings(vec![1e-3; o.search_up_to + 1]).unwrap();
    assert!(big.layers.adapt_mu.is_none());
    let bad = Online {
        search: Some(dae_runtime::settings::AdaptiveMu {
            step: 1.0,
            ..Default::default()
        }),
        ..Online::default()
    };
    let err = bad.settings(vec![1e-3]).unwrap_err();
    assert!(
        matches!(&err, DesignError::BadAdaptiveMu { reason } if reason.contains("step")),
        "{err}"
    );
    // The simulator checks the settings too.
    let p = Pendulum::default();
    let settings = Online::default()
        .design(&p, &[0.01], 1.0)
        .unwrap()
        .adapt_mu(Some(dae_runtime::settings::AdaptiveMu {
            window: 0,
            ..Default::default()
        }));
    let err = Simulator::new(&p, settings).err().expect("refused");
    assert!(err.to_string().contains("window"), "{err}");
}

#[test]
fn a_run_in_pieces_with_a_search_keeps_the_search_on_its_own_frames() {
    // The search's frames are the simulator's clock, not the caller's pieces: pieces
    // that end at frame ends give the run in one piece to the bit, and pieces that do
    // not still give one look per frame.
    let p = Pendulum::default();
    let settings = Online::default().design(&p, &[0.01], 1.0).unwrap();
    let whole = Simulator::new(&p, settings.clone())
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    let in_pieces = |ends: &[f64]| {
        let mut sim = Simulator::new(&p, settings.clone()).unwrap();
        let mut trace = Trace::new();
        sim.start(&mut trace).unwrap();
        for &t in ends {
            sim.advance_to(t, &mut trace).unwrap();
        }
        sim.finish(&mut trace).unwrap()
    };
    let frame_ends: Vec<f64> = (1..=12).map(|k| (5 * k) as f64 * (1.0 / 60.0)).collect();
    let aligned = in_pieces(&frame_ends);
    assert_eq!(aligned.mu_search, whole.mu_search);
    assert_eq!(aligned.updates, whole.updates);
    assert_eq!(aligned.x, whole.x);
    let sevenths: Vec<f64> = (1..=7).map(|k| k as f64 / 7.0).collect();
    let other = in_pieces(&sevenths);
    assert_eq!(other.mu_search.unwrap().frames, 60);
}

#[test]
fn cuts_that_drift_from_the_search_frames_by_rounding_step_no_sliver() {
    // An importer that sums its communication steps (t += 1/60) meets the search's frame
    // ends (origin + k/60) a few ulps away: those pieces must not be stepped (a step
    // of 1e-17 s underflows the error control).
    let p = Pendulum::default();
    let settings = Online::default().design(&p, &[1e-3], 2.0).unwrap();
    let mut sim = Simulator::new(&p, settings).unwrap();
    let mut trace = Trace::new();
    sim.start(&mut trace).unwrap();
    let (h, mut t) = (1.0 / 60.0, 0.0);
    let mut off_frame = 0;
    for k in 1..120 {
        t += h;
        off_frame += usize::from(t != k as f64 * h);
        sim.advance_to(t, &mut trace).unwrap();
        assert_eq!(sim.time(), t);
    }
    assert!(
        off_frame > 10,
        "the cuts drifted from the frames at {off_frame} points"
    );
    let summary = sim.finish(&mut trace).unwrap();
    assert!(summary.bound_held(), "{summary}");
}

//! A DBSMC particle run whose layer is left after reaching does not go on as if it
//! held: `advance_to` fails at the end of that frame, naming the constraint and the
//! time; with `keep_going_after_bound_loss` it goes on and the counters say when.

use dae_particles::{Backend, Dbsmc, FRAME, ParticleDae, ParticleModel, chain};
use dae_runtime::{Model, Settings, settings::AlphaChoice};

/// A heavy-end chain with gains far too small to hold layers of 0.1 % of a link.
fn weak(keep_going: bool) -> Dbsmc<ParticleModel> {
    let model = ParticleModel::new(&chain(10, 1e4).unwrap()).unwrap();
    let m = model.n_constraints();
    let eps: Vec<f64> = (0..m).map(|i| 1e-3 * model.rest_length(i)).collect();
    let settings = Settings::new(eps, vec![2e-3; m], vec![1e-9; m])
        .alpha(AlphaChoice::Exact)
        .step(FRAME / 100.0);
    let b = Dbsmc::new(model, settings, "weak").unwrap();
    if keep_going {
        b.keep_going_after_bound_loss()
    } else {
        b
    }
}

#[test]
fn a_lost_layer_stops_the_run_loudly() {
    let mut b = weak(false);
    let mut failure = None;
    for f in 1..=120 {
        if let Err(e) = b.advance_to(f as f64 * FRAME) {
            failure = Some((f, e));
            break;
        }
    }
    let (frame, e) = failure.expect("the layers cannot hold with these gains");
    assert!(e.reason.contains("bound lost"), "{e:?}");
    assert!(e.reason.contains("link"), "names the constraint: {e:?}");
    assert!(e.t <= frame as f64 * FRAME + 1e-12, "{e:?}");
    // And it stays failed.
    assert!(b.advance_to((frame + 1) as f64 * FRAME).is_err());
    assert_eq!(b.counters().layer_lost_at(), Some(e.t));
}

#[test]
fn keep_going_records_the_loss_and_goes_on() {
    let mut b = weak(true);
    for f in 1..=120 {
        b.advance_to(f as f64 * FRAME).expect("keeps going");
    }
    let lost = b.counters().layer_lost_at().expect("recorded");
    assert!(lost > 0.0 && lost <= 2.0, "{lost}");
    // How far: beyond the 1 % tolerance of the runtime's bound.
    let ratio = b
        .counters()
        .layer_worst_ratio()
        .expect("recorded with the time");
    assert!(ratio > 1.01, "{ratio}");
}

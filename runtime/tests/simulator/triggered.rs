//! `Summary::triggered_updates`, which constraints asked for the monitored updates,
//! against the recorded trace: at every update after reaching, the rows whose recorded
//! `s_i` sits on its layer boundary.

use crate::common;

use common::pendulum::Pendulum;
use dae_runtime::settings::{Dbsmc, Law, Update};
use dae_runtime::{Settings, Simulator, Summary, Trace, settings::CROSSING_TOL};

/// The double pendulum with the gains of `located.rs` (`mu^2 |beta|`), error-controlled
/// steps, every step recorded.
fn run(policy: Law) -> (Summary, Trace, Vec<f64>) {
    let (mu, beta) = ([0.076, 0.066], [1.3e3, 2.3e3]);
    let gains = (0..2).map(|i| mu[i] * mu[i] * beta[i]).collect();
    let eps = vec![0.2; 2];
    let settings = Settings::new(eps.clone(), mu.to_vec(), gains)
        .law(policy)
        .t_end(3.0);
    let mut trace = Trace::new();
    let summary = Simulator::new(Pendulum::default(), settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    (summary, trace, eps)
}

#[test]
fn each_update_is_counted_for_the_rows_on_their_boundary() {
    let (summary, trace, eps) = run(Law::default());
    let reached = summary.reaching_time.expect("reached");
    let counted = &summary.triggered_updates;
    assert_eq!(counted.len(), 2);
    // The oracle: the rows on their boundary in the sample recorded at each update's
    // time (an update happens at a step's end, which is recorded).
    let times = trace.times();
    let mut oracle = [0u64; 2];
    let mut steady = 0;
    for &t in trace.update_times().iter().filter(|&&t| t > reached) {
        let k = times.partition_point(|&x| x < t);
        assert_eq!(times[k], t, "the update at {t} has its sample");
        let s = trace.s(k);
        let on: Vec<usize> = (0..2)
            .filter(|&i| s[i].abs() >= eps[i] * (1.0 - 2.0 * CROSSING_TOL))
            .collect();
        assert!(
            !on.is_empty(),
            "update at {t}: no row on its boundary: {s:?}"
        );
        for i in on {
            oracle[i] += 1;
        }
        steady += 1;
    }
    eprintln!(
        "counted {counted:?}, on the boundary at the {steady} updates after reaching {oracle:?}, {} reaching updates",
        summary.reaching_updates
    );
    assert!(steady > 100, "{steady} updates after reaching");
    for i in 0..2 {
        assert!(oracle[i] > 0, "row {i} never asked");
        // Only the reaching phase's updates come on top (arrivals and outward motion
        // there are counted too).
        assert!(
            counted[i] >= oracle[i] && counted[i] <= oracle[i] + summary.reaching_updates,
            "row {i}: counted {}, oracle {}",
            counted[i],
            oracle[i]
        );
    }
}

#[test]
fn updates_of_a_fixed_period_are_asked_for_by_none() {
    let (summary, _, _) = run(Law::from(
        Dbsmc::default().update(Update::Fixed { period: 0.005 }),
    ));
    assert!(summary.updates > 100, "{} updates", summary.updates);
    assert_eq!(summary.triggered_updates, vec![0, 0]);
}

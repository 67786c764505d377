//! Sinks (decimation, CSV streaming, update times), the zero-order hold of `z`,
//! integrator costs and summary serialisation.

use crate::common;

use common::{Chain, Tracking};
use dae_runtime::settings::StepEnd;
use dae_runtime::{
    Settings, Simulator, Summary, Trace, settings::Integrator, trace::CsvSink, trace::Decimate,
    trace::Tee,
};

/// Fixed steps on a grid with the step-end rule: these tests are about the sinks and the
/// fixed-step integrators' costs (`located.rs` tests the located crossings).
fn settings() -> Settings {
    Settings::new(vec![1e-3], vec![0.05], vec![0.2])
        .step(1e-3)
        .law(StepEnd::default())
        .t_end(1.0)
}

#[test]
fn decimation_by_steps_keeps_every_kth_sample_and_all_updates() {
    let mut sink = Decimate::new(Trace::new()).every(10);
    let summary = Simulator::new(&Tracking::default(), settings())
        .unwrap()
        .run(&mut sink)
        .unwrap();
    let trace = sink.into_inner();
    assert_eq!(summary.steps, 1000);
    assert_eq!(trace.len(), 101);
    for (i, t) in trace.times().iter().enumerate() {
        assert!((t - i as f64 * 0.01).abs() < 1e-12, "sample {i} at {t}");
    }
    assert_eq!(trace.update_times().len() as u64, summary.updates);
    assert!(summary.updates > 2);
    assert!(trace.update_times().windows(2).all(|p| p[1] > p[0]));
}

/// A tee feeds each sink the samples it asks for: every 10th step to one, every 25th to
/// the other (each with the first and the last), all updates to both; the same samples
/// as two separate runs with one sink each. An absent (`None`) side records nothing.
#[test]
fn tee_feeds_each_sink_its_own_decimation() {
    let run = |sink: &mut dyn dae_runtime::trace::Sink| {
        Simulator::new(&Tracking::default(), settings().t_end(0.995))
            .unwrap()
            .run(sink)
            .unwrap()
    };
    let mut tee = Tee(
        Decimate::new(Trace::new()).every(10),
        Some(Decimate::new(Trace::new()).every(25)),
    );
    let summary = run(&mut tee);
    let (mut alone10, mut alone25) = (
        Decimate::new(Trace::new()).every(10),
        Decimate::new(Trace::new()).every(25),
    );
    run(&mut alone10);
    run(&mut alone25);
    let (ten, quarter) = (tee.0.into_inner(), tee.1.unwrap().into_inner());
    // 995 steps: steps 0, 10, ..., 990 and the last; 0, 25, ..., 975 and the last.
    assert_eq!(ten.len(), 101);
    assert_eq!(quarter.len(), 41);
    assert_eq!(ten.times(), alone10.inner().times());
    assert_eq!(quarter.times(), alone25.inner().times());
    for trace in [&ten, &quarter] {
        assert_eq!(trace.update_times().len() as u64, summary.updates);
    }
    let mut half = Tee(Decimate::new(Trace::new()).every(10), None::<Trace>);
    run(&mut half);
    assert_eq!(half.0.inner().times(), ten.times());
}

#[test]
fn decimation_by_time_spacing_keeps_samples_apart_and_the_last_one() {
    let mut sink = Decimate::new(Trace::new()).min_spacing(0.0499);
    Simulator::new(&Tracking::default(), settings().t_end(0.93))
        .unwrap()
        .run(&mut sink)
        .unwrap();
    let trace = sink.into_inner();
    let t = trace.times();
    assert_eq!(t.len(), 20, "{t:?}");
    assert!(t[..19].windows(2).all(|p| p[1] - p[0] >= 0.0499));
    assert!((t[19] - 0.93).abs() < 1e-12);
}

#[test]
fn csv_stream_matches_the_in_memory_trace() {
    let mut trace = Trace::new();
    Simulator::new(
        &Chain,
        Settings::new(vec![1e-4], vec![0.2], vec![0.01])
            .step(1e-3)
            .law(StepEnd::default())
            .t_end(0.2),
    )
    .unwrap()
    .run(&mut trace)
    .unwrap();
    let mut csv = CsvSink::new(Vec::new());
    Simulator::new(
        &Chain,
        Settings::new(vec![1e-4], vec![0.2], vec![0.01])
            .step(1e-3)
            .law(StepEnd::default())
            .t_end(0.2),
    )
    .unwrap()
    .run(&mut csv)
    .unwrap();
    assert_eq!(csv.update_times(), trace.update_times());
    let streamed = String::from_utf8(csv.into_inner()).unwrap();
    let mut stored = Vec::new();
    trace.write_csv(&mut stored).unwrap();
    assert_eq!(streamed, String::from_utf8(stored).unwrap());
    let mut lines = streamed.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,x.x1,x.x2,x.x3,z.z,z_eq.z,z_star.z,s.track,w.track"
    );
    // Row 100: the values parse back to exactly what the trace holds.
    let row: Vec<f64> = lines
        .nth(100)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(row[0], trace.times()[100]);
    assert_eq!(&row[1..4], trace.x(100));
    assert_eq!(row[4], trace.z(100)[0]);
    assert_eq!(row[5], trace.z_eq(100)[0]);
    assert_eq!(row[6], trace.z_star(100)[0]);
    assert_eq!(row[7], trace.s(100)[0]);
    assert_eq!(row[8], trace.w(100)[0]);
}

#[test]
fn z_is_an_exact_ramp_between_updates() {
    let mut trace = Trace::new();
    Simulator::new(
        &Chain,
        Settings::new(vec![1e-5], vec![0.2], vec![0.01])
            .step(1e-3)
            .t_end(1.0),
    )
    .unwrap()
    .run(&mut trace)
    .unwrap();
    let ups = trace.update_times();
    let mut checked = 0;
    for i in 0..trace.len() - 2 {
        let (t0, t2) = (trace.times()[i], trace.times()[i + 2]);
        if ups.iter().any(|&u| u > t0 && u <= t2) {
            continue;
        }
        // Samples are not evenly spaced (steps end at located crossings): the slopes
        // of consecutive chords agree.
        let z = |k: usize| trace.z(k)[0];
        let t = |k: usize| trace.times()[k];
        let slope = |k: usize| (z(k + 1) - z(k)) / (t(k + 1) - t(k));
        let (a, b) = (slope(i), slope(i + 1));
        assert!(
            (a - b).abs() <= 1e-9 * a.abs().max(1e-3),
            "at t = {t0}: slopes {a} and {b}"
        );
        checked += 1;
    }
    assert!(
        checked > 300 && ups.len() > 10,
        "checked {checked}, updates {}",
        ups.len()
    );
}

#[test]
fn euler_and_rk4_cost_one_and_four_rhs_evaluations_per_step() {
    for (integrator, per_step) in [(Integrator::Euler, 1), (Integrator::Rk4, 4)] {
        let s = Simulator::new(
            &Tracking::default(),
            settings().step(1e-4).integrator(integrator),
        )
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
        assert_eq!(s.f_evals, per_step * s.steps);
        assert_eq!(s.sliding_evals, s.steps + 1);
        // One per update, one for z* at each recorded sample between updates.
        assert_eq!(s.jacobian_evals, s.updates + (s.steps + 1 - s.updates));
        // Both keep the constraint within its layer (T 3.10).
        assert!(
            s.max_abs_w.as_ref().unwrap()[0] <= 1.05e-3,
            "{integrator:?}: |w| = {}",
            s.max_abs_w.as_ref().unwrap()[0]
        );
    }
}

#[test]
fn summary_round_trips_through_json() {
    let summary = Simulator::new(&Tracking::default(), settings())
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    let json = serde_json::to_string(&summary).unwrap();
    assert!(json.contains("\"z_eq\""));
    let back: Summary = serde_json::from_str(&json).unwrap();
    assert_eq!(back, summary);
}

//! The harness's measurements on cases with known answers.

use crate::common;

use common::Tracking;
use dae_bench::{
    harness::DbsmcStep, harness::Method, harness::Record, harness::Scene, harness::run_method,
    harness::write_csv, stability::Envelope, stability::StabilityRow, stability::Verdict,
    stability::judge, stability::write_table,
};

fn tracking_scene(model: &Tracking, offset: f64) -> Scene<'_, Tracking> {
    Scene {
        name: "tracking".into(),
        model,
        x0: vec![0.0],
        z0: vec![1.0],
        t_end: 1.5,
        compare: vec![0],
        truth: vec![1.5f64.sin() + offset],
        beta_bound: vec![2.0],
    }
}

#[test]
fn position_error_is_the_largest_absolute_difference() {
    let m = Tracking::default();
    let mut scene = tracking_scene(&m, 0.0);
    scene.compare = vec![0, 2];
    scene.truth = vec![1.0, -2.0];
    assert_eq!(scene.position_error(&[1.25, 9.0, -2.5]), 0.5);
}

#[test]
fn run_records_a_known_position_error_and_a_small_constraint_error() {
    // The exact solution is x = sin t; the "truth" is shifted by a known 0.125.
    let m = Tracking::default();
    let scene = tracking_scene(&m, 0.125);
    let r = run_method(
        &scene,
        &Method::IndexOne {
            mu: 0.1,
            step: 1e-3,
        },
        2,
    );
    assert!(r.ok, "{r:?}");
    assert!((r.pos_err - 0.125).abs() < 1e-11, "pos_err {}", r.pos_err);
    assert!(r.max_w < 1e-11, "max_w {}", r.max_w);
    assert_eq!(r.steps, 1500);
    assert_eq!(r.f_evals, 4 * 1500);
    assert!(r.wall > 0.0);
    // DBSMC keeps |w| within its layer (|w| <= eps once |s| <= eps, T 3.10).
    let d = run_method(
        &scene,
        &Method::Dbsmc {
            eps: 1e-3,
            mu: 0.1,
            step: DbsmcStep::Adaptive,
            gain_factor: 1.5,
        },
        1,
    );
    assert!(d.ok && d.max_w <= 1.2e-3, "{d:?}");
    assert!((d.pos_err - 0.125).abs() < 2e-3, "pos_err {}", d.pos_err);
}

#[test]
fn envelope_keeps_one_maximum_per_window_and_the_verdicts_follow_the_rule() {
    let mut env = Envelope::new(1.0);
    for k in 0..=1000 {
        let t = k as f64 * 0.01;
        env.push(t, &[1e-6 * (1.0 + t), -2e-6]);
    }
    env.finish_window(10.0);
    assert_eq!(env.max_w.len(), 10);
    assert_eq!(env.samples, 1001);
    assert!((env.max_w[9] - 1.1e-5).abs() < 1e-12, "{:?}", env.max_w);
    assert_eq!(env.max_w[0], 2e-6);
    let ok: Result<Vec<f64>, String> = Ok(vec![]);
    assert_eq!(judge(&env, &ok, 1e-4).0, Verdict::Holds);
    assert_eq!(judge(&env, &ok, 1e-6).0, Verdict::Drifts);
    assert_eq!(judge(&env, &Err("boom".into()), 1e-4).0, Verdict::Diverges);
    let mut growing = Envelope::new(1.0);
    for k in 0..=100 {
        growing.push(k as f64, &[1e-9 * 10f64.powf(k as f64 / 20.0)]);
    }
    assert_eq!(
        judge(&growing, &ok, 1e-3).0,
        Verdict::Drifts,
        "x1e5 growth under tol"
    );
}

#[test]
fn csv_has_the_header_and_one_line_per_record() {
    let r = Record {
        scene: "s".into(),
        line: "l".into(),
        knob: "h=1e-3".into(),
        ok: true,
        error: String::new(),
        max_w: 1e-3,
        max_s: 0.25,
        pos_err: 2e-4,
        wall: 0.5,
        j_solves: 3,
        f_evals: 4,
        steps: 5,
        updates: 6,
    };
    let mut out = Vec::new();
    write_csv(&[r.clone(), r], &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "scene,line,knob,ok,max_w,max_s,pos_err,wall_s,j_solves,f_evals,steps,updates,error"
    );
    assert_eq!(
        lines[1],
        "s,l,h=1e-3,true,1e-3,2.5e-1,2e-4,5e-1,3,4,5,6,\"\""
    );
    assert_eq!(lines.len(), 3);
}

#[test]
fn chart_draws_one_legend_entry_per_line_and_refuses_an_empty_set() {
    use dae_bench::{harness::CostAxis, harness::ErrorAxis, harness::chart};
    let rec = |line: &str, wall: f64, err: f64| Record {
        scene: "s".into(),
        line: line.into(),
        knob: String::new(),
        ok: true,
        error: String::new(),
        max_w: err,
        max_s: 0.0,
        pos_err: err,
        wall,
        j_solves: 10,
        f_evals: 20,
        steps: 5,
        updates: 3,
    };
    let records = [
        rec("alpha", 1e-3, 1e-4),
        rec("alpha", 1e-2, 1e-6),
        rec("beta", 2e-3, 1e-2),
    ];
    let path = std::env::temp_dir().join(format!("dae_bench_chart_{}.svg", std::process::id()));
    chart(
        &records,
        "test chart",
        ErrorAxis::Position,
        CostAxis::Wall,
        &path,
    )
    .unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(svg.starts_with("<svg"));
    for text in ["test chart", "alpha", "beta", "wall time"] {
        assert!(svg.contains(text), "missing {text}");
    }
    let failed = Record {
        ok: false,
        ..rec("gamma", 1.0, 1.0)
    };
    assert!(
        chart(
            &[failed],
            "empty",
            ErrorAxis::Position,
            CostAxis::Wall,
            &path
        )
        .is_err()
    );
}

#[test]
fn stability_table_escapes_bars_so_each_row_has_four_cells() {
    let row = StabilityRow {
        scene: "(i) long run".into(),
        method: "DBSMC".into(),
        verdict: Verdict::Holds,
        figure: "max|w| last 50%: 1e-4".into(),
        value: 1e-4,
    };
    let mut out = Vec::new();
    write_table(&[row], &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let line = text.lines().nth(2).unwrap();
    assert!(line.contains(r"max\|w\|"), "{line}");
    // Unescaped bars delimit the cells: 5 of them for 4 cells.
    let delimiters = line.replace(r"\|", "").matches('|').count();
    assert_eq!(delimiters, 5, "{line}");
}

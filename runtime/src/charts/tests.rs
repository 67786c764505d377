use super::*;

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dae-runtime-charts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// Every opened element is closed: a cheap well-formedness check of the SVG text.
fn assert_svg(svg: &str, names: &[&str]) {
    assert!(
        svg.trim_start().starts_with("<svg"),
        "{}",
        &svg[..svg.len().min(80)]
    );
    assert!(svg.trim_end().ends_with("</svg>"));
    let opened = svg.matches('<').count();
    let closed = svg.matches("/>").count() + svg.matches("</").count();
    assert_eq!(
        opened,
        2 * svg.matches("</").count() + svg.matches("/>").count()
    );
    assert!(closed > 0);
    for n in names {
        assert!(svg.contains(n), "missing {n}");
    }
}

fn trace(n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 4.0 / (n - 1) as f64).collect();
    let s1 = t
        .iter()
        .map(|t| -(-3.0 * t).exp() + 0.15 * (40.0 * t).sin())
        .collect();
    let s2 = t
        .iter()
        .map(|t| 2.0 * (-2.0 * t).exp() * (9.0 * t).cos())
        .collect();
    (t, s1, s2)
}

#[test]
fn sliding_chart_is_written_with_series_names_and_bands() {
    let (t, s1, s2) = trace(2001);
    let path = tmp("sliding.svg");
    plot_sliding(
        &path,
        "double pendulum",
        &t,
        &[
            SlidingSeries {
                name: "link_one",
                s: &s1,
                eps: 0.2,
            },
            SlidingSeries {
                name: "link_two",
                s: &s2,
                eps: 0.25,
            },
        ],
    )
    .unwrap();
    let svg = read(&path);
    assert_svg(
        &svg,
        &[
            "double pendulum",
            "link_one",
            "link_two",
            "eps = 0.2",
            "eps = 0.25",
        ],
    );
}

#[test]
fn periods_chart_shows_the_guaranteed_period() {
    let times: Vec<f64> = (0..200)
        .map(|k| 0.02 * k as f64 + 0.004 * (k as f64).sin())
        .collect();
    let path = tmp("periods.svg");
    plot_periods(&path, "update periods", &times, Some(0.0053)).unwrap();
    assert_svg(&read(&path), &["update periods", "T_min", "200 updates"]);
    plot_periods(&path, "no bound", &times, None).unwrap();
    let svg = read(&path);
    assert_svg(&svg, &["no bound"]);
    assert!(!svg.contains("T_min"));
}

#[test]
fn error_chart_linear_and_log_including_zeros() {
    let (t, s1, s2) = trace(301);
    let mut w1 = s1.clone();
    w1[0] = 0.0; // consistent start: |w| = 0 must not break the log axis
    for scale in [YScale::Linear, YScale::Log] {
        let path = tmp(&format!("errors-{scale:?}.svg"));
        plot_errors(
            &path,
            "constraint errors",
            &t,
            &[
                ErrorSeries {
                    name: "w_one",
                    w: &w1,
                },
                ErrorSeries {
                    name: "w_two",
                    w: &s2,
                },
            ],
            scale,
        )
        .unwrap();
        assert_svg(&read(&path), &["constraint errors", "w_one", "w_two"]);
    }
    let zeros = vec![0.0; t.len()];
    let path = tmp("errors-zero.svg");
    plot_errors(
        &path,
        "exact",
        &t,
        &[ErrorSeries {
            name: "w",
            w: &zeros,
        }],
        YScale::Log,
    )
    .unwrap();
    assert_svg(&read(&path), &["exact"]);
}

#[test]
fn bad_data_is_an_error_not_a_panic() {
    let path = tmp("bad.svg");
    let ok = [0.0, 1.0, 2.0];
    let s = |s: &'static [f64]| {
        [SlidingSeries {
            name: "s",
            s,
            eps: 0.1,
        }]
    };
    assert!(matches!(
        plot_sliding(&path, "x", &[], &s(&[])),
        Err(ChartError::Empty("t"))
    ));
    assert!(matches!(
        plot_sliding(&path, "x", &ok, &[]),
        Err(ChartError::Empty(_))
    ));
    assert!(matches!(
        plot_sliding(&path, "x", &ok, &s(&[0.0, f64::NAN, 1.0])),
        Err(ChartError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        plot_sliding(&path, "x", &[0.0, f64::INFINITY, 2.0], &s(&[0.0, 0.0, 1.0])),
        Err(ChartError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        plot_sliding(&path, "x", &ok, &s(&[0.0, 1.0])),
        Err(ChartError::LengthMismatch {
            got: 2,
            expected: 3,
            ..
        })
    ));
    assert!(matches!(
        plot_sliding(&path, "x", &[0.0, 2.0, 1.0], &s(&[0.0, 0.0, 1.0])),
        Err(ChartError::Decreasing { index: 2, .. })
    ));
    let zero_eps = [SlidingSeries {
        name: "s",
        s: &ok,
        eps: 0.0,
    }];
    assert!(matches!(
        plot_sliding(&path, "x", &ok, &zero_eps),
        Err(ChartError::NotPositive { what: "eps", .. })
    ));
    assert!(matches!(
        plot_periods(&path, "x", &[1.0], None),
        Err(ChartError::Empty(_))
    ));
    assert!(matches!(
        plot_periods(&path, "x", &ok, Some(f64::NAN)),
        Err(ChartError::NotPositive { what: "t_min", .. })
    ));
    assert!(matches!(
        plot_errors(
            &path,
            "x",
            &ok,
            &[ErrorSeries {
                name: "w",
                w: &[f64::NAN; 3]
            }],
            YScale::Log
        ),
        Err(ChartError::NonFinite { index: 0, .. })
    ));
    assert!(matches!(
        plot_errors(&path, "x", &ok, &[], YScale::Linear),
        Err(ChartError::Empty(_))
    ));
    assert!(!path.exists(), "nothing is written for bad data");
    let unwritable = tmp("no-such-dir").join("x.svg");
    assert!(matches!(
        plot_errors(
            &unwritable,
            "x",
            &ok,
            &[ErrorSeries { name: "w", w: &ok }],
            YScale::Linear
        ),
        Err(ChartError::Io { .. })
    ));
}

#[test]
fn single_sample_and_constant_data_still_draw() {
    let path = tmp("single.svg");
    plot_sliding(
        &path,
        "one",
        &[1.0],
        &[SlidingSeries {
            name: "s",
            s: &[0.0],
            eps: 0.1,
        }],
    )
    .unwrap();
    assert_svg(&read(&path), &["one"]);
    plot_periods(&path, "equal", &[0.5, 0.5, 0.5], Some(0.1)).unwrap();
    assert_svg(&read(&path), &["equal"]);
}

#[test]
fn thinning_keeps_the_envelope_and_order() {
    // Oracle: per time bin the extremes of the raw data.
    let n = 100_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-4).collect();
    let y = |i: usize| (i as f64 * 0.37).sin() * (1.0 + t[i]);
    let pts = thin(&t, y, 100);
    assert!(pts.len() <= 400 && pts.len() >= 200, "{}", pts.len());
    assert!(pts.windows(2).all(|w| w[0].0 <= w[1].0));
    assert_eq!(pts[0], (t[0], y(0)));
    assert_eq!(*pts.last().unwrap(), (t[n - 1], y(n - 1)));
    let raw_max = (0..n).map(y).fold(f64::NEG_INFINITY, f64::max);
    let raw_min = (0..n).map(y).fold(f64::INFINITY, f64::min);
    let kept_max = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let kept_min = pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    assert_eq!((kept_min, kept_max), (raw_min, raw_max));
    // Short series are untouched.
    assert_eq!(thin(&t[..10], y, 100).len(), 10);
}

/// A trace of two constraints fed by hand through the `Sink` calls the simulator makes,
/// with `updates` control updates.
fn run_trace(updates: usize) -> crate::Trace {
    use crate::trace::{Layout, Sample, Sink};
    let mut out = crate::Trace::new();
    let layout = Layout {
        states: vec!["x".into()],
        algs: vec!["z1".into(), "z2".into()],
        constraints: vec!["link_one".into(), "link_two".into()],
    };
    out.begin(&layout).unwrap();
    let (t, s1, s2) = trace(501);
    // Updates at equal spacing from the start.
    let every = t.len() / updates;
    for (k, &tk) in t.iter().enumerate() {
        if k % every == 0 && k / every < updates {
            out.update(tk).unwrap();
        }
        let s = [s1[k], s2[k]];
        out.record(&Sample {
            step: k as u64,
            t: tk,
            x: &[0.0],
            z: &[0.0, 0.0],
            z_eq: &[0.0, 0.0],
            z_star: &[0.0, 0.0],
            s: &s,
            w: &[0.5 * s[0], 0.5 * s[1]],
            last: k + 1 == t.len(),
        })
        .unwrap();
    }
    out
}

#[test]
fn run_charts_are_written_from_a_trace() {
    let dir = tmp("run");
    let charts = plot_run(&dir, "pendulum", &run_trace(8), &[0.2, 0.3], Some(0.05)).unwrap();
    assert_eq!(charts.sliding, dir.join("sliding.svg"));
    assert_eq!(charts.errors, dir.join("errors.svg"));
    assert_eq!(charts.periods, Some(dir.join("periods.svg")));
    assert_svg(
        &read(&charts.sliding),
        &["pendulum: sliding variables", "link_one", "link_two"],
    );
    assert_svg(&read(&charts.errors), &["pendulum: constraint errors"]);
    let periods = read(charts.periods.as_ref().unwrap());
    assert_svg(
        &periods,
        &["pendulum: update periods (line: guaranteed T_min)"],
    );

    // One update: no period, no periods chart.
    let one = tmp("run-one-update");
    let charts = plot_run(&one, "p", &run_trace(1), &[0.2, 0.3], None).unwrap();
    assert_eq!(charts.periods, None);
    assert!(!one.join("periods.svg").exists());

    // One eps per constraint, checked before anything is written.
    let bad = tmp("run-bad");
    let err = plot_run(&bad, "p", &run_trace(8), &[0.2], None).unwrap_err();
    assert!(
        matches!(err, ChartError::LengthMismatch { ref series, got: 1, expected: 2 } if series == "eps"),
        "{err}"
    );
    assert!(!bad.exists());
}

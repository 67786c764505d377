//! The text of a `Summary` (its `Display`), on a run of the hand-written pendulum.

use crate::common;

use common::pendulum::Pendulum;
use dae_runtime::summary::TEXT_LINES_MAX;
use dae_runtime::{Simulator, Summary, trace::NoTrace};

fn pendulum_summary() -> Summary {
    let settings = common::pendulum_settings(1e-4).t_end(0.5);
    Simulator::new(&Pendulum::default(), settings)
        .unwrap()
        .run(&mut NoTrace)
        .unwrap()
}

#[test]
fn the_text_of_a_summary_has_its_lines_in_order() {
    let s = pendulum_summary();
    assert_eq!(s.eps, vec![0.2; 2]);
    let text = s.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with(&format!(
            "model {} to t = {}: {} steps (",
            s.model, s.t_end, s.steps
        )),
        "{text}"
    );
    assert!(
        lines[0].contains(&format!("{} updates (", s.updates)),
        "{text}"
    );
    let reached = s.reaching_time.unwrap();
    assert_eq!(
        lines[1],
        format!(
            "  layers reached at {reached:.6}, statistics from {:.6}",
            s.stats_from.unwrap()
        )
    );
    assert!(lines[2].starts_with("  update period min "), "{text}");
    // One line per constraint, with its ratio to eps.
    for (i, c) in s.constraints.iter().enumerate() {
        let ms = s.max_abs_s.as_ref().unwrap()[i];
        let line = format!(
            "  {c}: max |s| = {ms:.6} ({:.4} eps), max |w| = {:.6}",
            ms / 0.2,
            s.max_abs_w.as_ref().unwrap()[i]
        );
        assert!(lines.contains(&line.as_str()), "{line}\n{text}");
    }
    assert!(
        text.contains(&format!("\n  solver {}: ", s.solver.name)),
        "{text}"
    );
    assert!(text.contains("\n  final z = ["), "{text}");
    assert_eq!(
        *lines.last().unwrap(),
        format!("  wall time {:.3} s", s.wall_time)
    );
    assert!(!text.ends_with('\n'));
}

#[test]
fn the_text_of_a_summary_of_ten_thousand_constraints_stays_short() {
    let mut s = pendulum_summary();
    let m = 10_000;
    s.constraints = (0..m).map(|i| format!("c{i}")).collect();
    s.eps = vec![0.1; m];
    // The largest ratio at c4321.
    let max_s: Vec<f64> = (0..m)
        .map(|i| if i == 4321 { 0.09 } else { 0.01 })
        .collect();
    s.max_abs_s = Some(max_s.clone());
    s.max_abs_w = Some(vec![0.001; m]);
    s.seen_max_abs_s = max_s;
    s.seen_max_abs_w = vec![0.001; m];
    s.triggered_updates = (0..m as u64).collect();
    s.z = vec![1.0; m];
    s.z_eq = (0..m).map(|i| i as f64).collect();
    s.z_star = vec![1.0; m];
    s.s = vec![0.0; m];
    s.w = vec![0.0; m];
    let text = s.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() <= TEXT_LINES_MAX + 10, "{} lines", lines.len());
    assert!(
        lines.contains(&"  10000 constraints; the 16 with the largest max |s| / eps:"),
        "{text}"
    );
    assert!(
        lines.contains(&"  c4321: max |s| = 0.090000 (0.9000 eps), max |w| = 0.001000"),
        "{text}"
    );
    assert!(
        text.contains("final z = 1 (all 10000), z_eq = 0 .. 9999 (10000 values)"),
        "{text}"
    );
    assert!(
        text.contains("updates asked for by 9999 of 10000 constraints, most by c9999 (9999)"),
        "{text}"
    );
    assert!(text.len() < 4000, "{} bytes", text.len());
}

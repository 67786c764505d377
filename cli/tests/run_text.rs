//! The text `daec run` prints is the runtime's `Summary` text followed by the settings
//! of the run: the same run through the runtime gives the same lines. Off a terminal
//! nothing else is written (no progress bar).

mod common;

use common::daec;
use dae_runtime::settings::Integrator;
use dae_runtime::solve::SolverChoice;
use dae_runtime::{Settings, Simulator, trace::NoTrace};
use std::path::Path;

/// Every line but the wall time (which differs from run to run).
fn without_wall_time(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| !l.starts_with("  wall time "))
        .map(str::to_string)
        .collect()
}

#[test]
fn daec_run_prints_the_summary_text_of_the_runtime() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/models/double_pendulum_3d.dae");
    let o = daec(&[
        "run",
        path.to_str().unwrap(),
        "--t-end",
        "0.5",
        "--eps",
        "0.2",
        "--mu",
        "0.076,0.066",
        "--gain",
        "7.5,10",
        "--step",
        "1e-4",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // stderr is not a terminal here: no progress bar, nothing at all on stderr.
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stdout = String::from_utf8(o.stdout).unwrap();

    // The same run through the runtime: what `daec run` sets up for these flags.
    let src = std::fs::read_to_string(&path).unwrap();
    let model = daec::interpret_source(&src).unwrap().remove(0);
    let settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .step(1e-4)
        .integrator(Integrator::Rk4)
        .max_steps(100_000_000)
        .t_end(0.5)
        .solver(SolverChoice::Auto);
    let summary = Simulator::new(&model, settings)
        .unwrap()
        .run(&mut NoTrace)
        .unwrap();
    let text = summary.to_string();
    let expected = without_wall_time(&text);
    let printed = without_wall_time(&stdout);
    assert!(expected.len() > 5, "{text}");
    assert_eq!(printed[..expected.len()], expected[..], "{stdout}");
    // Then the settings lines.
    assert!(
        printed[expected.len()].starts_with(
            "  mu = [0.076, 0.066] (given), gains = [7.5, 10.0] (given), eps = [0.2, 0.2]"
        ),
        "{stdout}"
    );
    assert!(
        printed[expected.len() + 1].starts_with("  integrator RK4, fixed step 1e-4 (given)"),
        "{stdout}"
    );
}

//! The cost of `fmi2DoStep` against the same span run by the simulator directly, as
//! `daec run` runs it (in process, the same design): the FMU's layers must add little.
//!
//! `cargo run --release -p dae-fmu --example step_cost [SECONDS]` prints, for the 3-D
//! double pendulum at eps 1e-3 over SECONDS (default 10) of model time in steps of
//! 1/60 s, the median wall time of 15 runs of each and their ratio.

use std::ffi::{CString, c_void};
use std::path::Path;
use std::time::Instant;

use dae_fmu::abi::{CallbackFunctions, fmi2DoStep, fmi2ExitInitializationMode};
use dae_fmu::abi::{fmi2FreeInstance, fmi2Instantiate, fmi2SetupExperiment};
use dae_fmu::{Config, unpack};
use dae_runtime::design::{Online, consistent_start};
use dae_runtime::family::Interpreted;
use dae_runtime::trace::NoTrace;
use dae_runtime::{Model, Simulator};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let span: f64 = std::env::args().nth(1).map_or(10.0, |s| s.parse().unwrap());
    let (eps, h) = (1e-3, 1.0 / 60.0);
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/models/double_pendulum_3d.dae");
    let src = std::fs::read_to_string(file).unwrap();
    let dir = std::env::temp_dir().join(format!("dae-fmu-step-cost-{}", std::process::id()));
    let e = unpack(&src, Config::new("DoublePendulum3D", eps, span), &dir).unwrap();
    let uri = CString::new(format!("file://{}", dir.join("resources").display())).unwrap();
    let guid = CString::new(e.guid).unwrap();
    let cb = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let steps = (span / h).round() as u64;
    // SAFETY: the arguments of the standard, from this function.
    let fmu_run = || unsafe {
        let c: *mut c_void =
            fmi2Instantiate(c"m".as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), &cb, 0, 0);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, span), 0);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        let start = Instant::now();
        let mut t = 0.0;
        for k in 1..=steps {
            let next = k as f64 * h;
            assert!(fmi2DoStep(c, t, next - t, 1) <= 1);
            t = next;
        }
        let wall = start.elapsed().as_secs_f64();
        fmi2FreeInstance(c);
        wall
    };
    let model = Interpreted::from_compiled(
        dae_lang::compile_source(&src).unwrap().remove(0),
        &Default::default(),
    )
    .expect("constructed at its sizes");
    let direct_run = || {
        let (mut x0, mut z0) = (vec![0.0; model.n_states()], vec![0.0; 2]);
        model.initial_state(&mut x0);
        model.initial_alg(&mut z0);
        let z0 = consistent_start(&model, 0.0, &x0, &z0).unwrap().z0;
        let settings = Online::frame(h)
            .settings(vec![eps; 2])
            .unwrap()
            .t_end(span)
            .initial(x0, z0);
        let mut sim = Simulator::new(&model, settings).unwrap();
        let start = Instant::now();
        sim.run(&mut NoTrace).unwrap();
        start.elapsed().as_secs_f64()
    };
    let (mut fmu, mut direct) = (Vec::new(), Vec::new());
    for _ in 0..15 {
        fmu.push(fmu_run());
        direct.push(direct_run());
    }
    let (f, d) = (median(fmu), median(direct));
    println!("| {span} s of the 3-D double pendulum, eps {eps} | median of 15 |");
    println!("| --- | --- |");
    println!("| fmi2DoStep every 1/60 s | {:.2} ms |", f * 1e3);
    println!("| Simulator::run (daec run's path) | {:.2} ms |", d * 1e3);
    println!("| ratio | {:.3} |", f / d);
    let _ = std::fs::remove_dir_all(&dir);
}

//! Fuzz target: whatever passes the checks is analysed and simulated, briefly, on the
//! interpreter, and nothing panics: parsing, checking and rendering diagnostics, the
//! index analysis and the tapes, the interpreter and the simulator (its settings, first
//! control update, and 50 ms of DBSMC: RK4 steps of 1 ms, Dormand-Prince,
//! Dormand-Prince with gains that follow the drift and graze, or RK4 with those gains
//! and `v` ramped against the drift, chosen by the input's length).
#![no_main]

use dae_runtime::settings::{Dbsmc, GainRule, Hold, Integrator};
use dae_runtime::trace::NoTrace;
use dae_runtime::{Model, Settings, Simulator};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(src) = std::str::from_utf8(data) else { return };
    let analysed = match dae_lang::analyze_source(src) {
        Ok(analysed) => analysed,
        Err(diags) => {
            let renderer = dae_lang::Renderer::new("fuzz.dae", src, false);
            for d in &diags {
                assert!(d.span.start <= d.span.end && d.span.end <= src.len());
                assert!(renderer.render(d).contains(&d.message));
            }
            return;
        }
    };
    for (_, analysis) in &analysed {
        assert!(analysis.condition_number.is_finite());
        // A version-1 model (the condition number is finite) has nothing that
        // construction can refuse.
        let compiled = dae_lang::compile(analysis);
        let model = dae_runtime::family::Interpreted::from_compiled(compiled, &Default::default())
            .expect("a version-1 model constructs");
        let m = model.n_constraints();
        // The settings of a first try from the command line: 50 steps of 1 ms.
        // A step limit bounds the work of a far-inconsistent start with a small gain
        // (every located crossing of a runaway variable is an update): a run that hits
        // it ends with `SimError::StepLimit`, an error, which is what is tested here.
        let settings = Settings::new(vec![0.1; m], vec![0.1; m], vec![1.0; m])
            .step(1e-3)
            .t_end(0.05)
            .max_steps(20_000);
        let grazing = Dbsmc::default().gains(GainRule::FollowDrift {
            safety: 1.0,
            graze: Some(1e-3),
            raise: None,
        });
        let settings = match data.len() % 4 {
            0 => settings,
            1 => settings.integrator(Integrator::DormandPrince),
            2 => settings.integrator(Integrator::DormandPrince).law(grazing),
            _ => settings.law(grazing.hold(Hold::RampAgainstDrift)),
        };
        if let Ok(mut sim) = Simulator::new(&model, settings) {
            // A run may fail (a value leaves its domain, the reaching phase does not
            // finish): with an error, not a panic.
            let _ = sim.run(&mut NoTrace);
        }
    }
});

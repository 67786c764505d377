//! Fuzz target: whatever passes the checks is analysed and simulated, briefly, on the
//! interpreter, and nothing panics: parsing, checking and rendering diagnostics, the
//! index analysis and the tapes, the interpreter and the simulator (its settings, first
//! control update, and 50 steps of DBSMC).
#![no_main]

use dae_runtime::{Model, NoTrace, Settings, Simulator};
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
        let model = daec::Interpreted::new(dae_lang::compile(analysis));
        let m = model.n_constraints();
        // The settings of a first try from the command line: 50 steps of 1 ms.
        let settings = Settings::new(vec![0.1; m], vec![0.1; m], vec![1.0; m])
            .step(1e-3)
            .t_end(0.05);
        if let Ok(mut sim) = Simulator::new(&model, settings) {
            // A run may fail (a value leaves its domain, the reaching phase does not
            // finish): with an error, not a panic.
            let _ = sim.run(&mut NoTrace);
        }
    }
});

//! Fuzz target: parsing, checking and rendering the diagnostics of arbitrary input
//! never panic, and every diagnostic points inside the input.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(src) = std::str::from_utf8(data) else { return };
    if let Err(diags) = dae_lang::check_source(src) {
        for d in &diags {
            assert!(d.span.start <= d.span.end && d.span.end <= src.len());
            let text = d.render("fuzz.dae", src, false);
            assert!(text.contains(&d.message));
        }
    }
});

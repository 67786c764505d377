//! Whole index analysis (lowering, derivatives, J_Omega, beta, s, alpha, the tapes, checks
//! and SVD at the initial point) of a planar chain of 100 links:
//! `cargo bench -p dae-lang --bench analysis`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use dae_lang::fixtures::planar_chain;
use dae_lang::{AnalysisOptions, analyze};

fn chain(c: &mut Criterion) {
    let model = planar_chain(100);
    let opts = AnalysisOptions::default();
    c.bench_function("analyze planar chain, 100 links", |b| {
        b.iter(|| analyze(black_box(&model), &opts).expect("the chain analyses"))
    });
    let text_of = analyze(&model, &opts).expect("the chain analyses");
    c.bench_function("derive text, planar chain, 100 links", |b| {
        b.iter(|| text_of.derive_text())
    });
}

criterion_group!(benches, chain);
criterion_main!(benches);

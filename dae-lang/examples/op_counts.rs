//! Operation counts of the derivatives the index analysis builds, with and without the
//! simplifying constructors: `cargo run -p dae-lang --example op_counts`.
//!
//! "shared" counts every distinct node once (straight-line code after common
//! sub-expression elimination); "tree" writes each expression out in full (what a naive
//! printer or code generator would emit). One operation is one `+ - * /`, power or call.

use dae_lang::fixtures::{double_pendulum_3d, planar_chain};
use dae_lang::model::Model;
use dae_lang::{AnalysisOptions, Id, analyze};

fn table(title: &str, model: &Model) {
    println!("{title}");
    println!(
        "| simplify | w^(r-1) = Omega shared / tree | J_Omega shared / tree | beta shared / tree | arena nodes |"
    );
    println!("|---|---|---|---|---|");
    for simplify in [false, true] {
        let opts = AnalysisOptions {
            simplify,
            ..AnalysisOptions::default()
        };
        let a = analyze(model, &opts).expect("the fixture analyses");
        let sym = a.symbolic();
        let omega: Vec<Id> = sym.constraints.iter().map(|c| c.omega).collect();
        let jac: Vec<Id> = sym
            .constraints
            .iter()
            .flat_map(|c| c.jacobian_row.iter().map(|e| e.1))
            .collect();
        let beta: Vec<Id> = sym.constraints.iter().map(|c| c.beta).collect();
        let count = |ids: &[Id]| {
            let arena = &sym.arena;
            format!("{} / {}", arena.op_count(ids), arena.tree_op_count(ids))
        };
        println!(
            "| {simplify} | {} | {} | {} | {} |",
            count(&omega),
            count(&jac),
            count(&beta),
            sym.arena.len()
        );
    }
    println!();
}

fn main() {
    table(
        "3-D double pendulum (docs/method.md section 8), both constraints:",
        &double_pendulum_3d(),
    );
    table(
        "Planar chain of 10 links, all constraints:",
        &planar_chain(10),
    );
}

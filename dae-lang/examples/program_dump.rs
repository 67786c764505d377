//! Prints the structure of a family model's programs (groups, arrays, sinks).
//! `cargo run -p dae-lang --example program_dump -- FILE.dae`
fn main() {
    let path = std::env::args().nth(1).expect("a .dae file");
    let src = std::fs::read_to_string(&path).unwrap();
    let m = dae_lang::check_source(&src).unwrap();
    let a = dae_lang::analyze(&m[0], &dae_lang::AnalysisOptions::default()).unwrap();
    let c = dae_lang::compile(&a);
    let f = &c.programs;
    for (name, p) in f.programs() {
        println!(
            "{name}: {} arrays {:?}",
            p.arrays.len(),
            p.arrays
                .iter()
                .map(|a| (a.over.map(|s| s.index()), a.accumulate))
                .collect::<Vec<_>>()
        );
        for g in &p.groups {
            println!(
                "  group over {:?}: {} instrs, sinks {:?}",
                g.over.map(|s| s.index()),
                g.tape.op_count(),
                g.sinks
            );
        }
        for e in &p.entries {
            println!("  entries coupling {}: {:?}", e.coupling, e.terms);
        }
    }
}

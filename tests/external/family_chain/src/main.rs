//! A user of the family chain: compiled once, run at any size.
//! `family-chain-user N`: builds the chain of N links, evaluates every function of the
//! model at its start and runs ten DBSMC steps; prints one line of figures.

use dae_runtime::settings::{ StepEnd,};
use dae_runtime::family::Spec;
use dae_runtime::{ Model, Settings, Simulator};

dae_runtime::dae_file!("../../../examples/models/chain.dae");

fn main() {
    let n: i64 = match std::env::args().nth(1).map(|a| a.parse()) {
        Some(Ok(n)) => n,
        _ => {
            eprintln!("usage: family-chain-user N (the number of links)");
            std::process::exit(2);
        }
    };
    let spec = Spec {
        sizes: vec![("N".into(), n)],
        ..Spec::default()
    };
    let chain = match Chain::new(&spec) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let (ns, m) = (chain.n_states(), chain.n_constraints());
    let mut x = vec![0.0; ns];
    let mut z = vec![0.0; m];
    chain.initial_state(&mut x);
    chain.initial_alg(&mut z);
    let mut dx = vec![0.0; ns];
    chain.rhs(0.0, &x, &z, &mut dx);
    let mut j = vec![0.0; chain.jacobian_pattern().len()];
    chain.jacobian(0.0, &x, &z, &mut j);
    // Ten steps of 1e-5 s (the settings of the runtime's 1000-link chain test).
    let settings = Settings::new(vec![1e-3; m], vec![0.05; m], vec![20.0; m])
        .step(1e-5)
        .law(StepEnd::default())
        .t_end(1e-4);
    let summary =
        match Simulator::new(&chain, settings).and_then(|mut s| s.run(&mut dae_runtime::trace::NoTrace)) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        };
    println!(
        "N = {n}: {ns} states, {m} constraints, {} entries of J_Omega, gravity on the last particle {:.3}, solver {}, {} steps",
        j.len(),
        dx[ns - 1],
        summary.solver.name,
        summary.steps,
    );
}

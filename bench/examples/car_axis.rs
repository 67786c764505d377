//! The car axis problem of the Test Set for IVP Solvers (`examples/models/car_axis.dae`,
//! generated code) to t = 3 against the test set's reference solution: DBSMC designed by
//! the runtime's toolkit per eps (error-controlled steps, located crossings) beside
//! diffsol's BDF on the index-1 form, by tolerance.
//!
//! ```text
//! cargo run --release -p dae-bench --features bdf --example car_axis
//! ```
//!
//! Prints one row per run: the method and its knob, whether it finished, the largest
//! absolute error of the four positions at t = 3, the largest constraint residual
//! `|w|`, `f` evaluations, `J` solves and the best wall time of three.

use dae_bench::{
    baseline::consistent_alg, generated::CarAxis, harness::DbsmcStep, harness::Method,
    harness::Scene, harness::designed_bounds, harness::pilot_beta_bound, harness::run_method,
};
use dae_runtime::Model;

/// The test set's reference positions `xl, yl, xr, yr` at t = 3.
const AT_3: [f64; 4] = [
    0.4934557842755629e-1,
    0.4969894602303324,
    1.0417425248854,
    0.3739110272652214,
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = CarAxis::default();
    let (n, m) = (model.n_states(), model.n_constraints());
    let mut x0 = vec![0.0; n];
    let mut z = vec![0.0; m];
    model.initial_state(&mut x0);
    model.initial_alg(&mut z);
    let z0 = consistent_alg(&model, 0.0, &x0, &vec![0.05; m], &z)?;
    let beta_bound = pilot_beta_bound(&model, &x0, &z0, 3.0, 0.05, 1e-4)?;
    let scene = Scene {
        name: "car_axis".into(),
        model: &model,
        x0,
        z0,
        t_end: 3.0,
        compare: vec![0, 1, 2, 3],
        truth: AT_3.to_vec(),
        beta_bound,
    };
    let mut methods = Vec::new();
    let bounds = designed_bounds(&scene, 1e-3, 1e-3)?;
    for eps in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
        methods.push(bounds.dbsmc(eps, Some(DbsmcStep::Adaptive), 1e-3)?);
    }
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        methods.push(Method::Bdf { mu: 0.05, tol });
    }
    println!(
        "| method | knob | finished | position error | max \\|w\\| | f evals | J solves | wall ms |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for method in &methods {
        let r = run_method(&scene, method, 3);
        println!(
            "| {} | {} | {} | {:.2e} | {:.2e} | {} | {} | {:.2} |",
            r.line,
            r.knob,
            if r.ok {
                "yes".to_string()
            } else {
                r.error.clone()
            },
            r.pos_err,
            r.max_w,
            r.f_evals,
            r.j_solves,
            r.wall * 1e3
        );
    }
    Ok(())
}

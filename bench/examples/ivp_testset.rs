//! Problems of the Test Set for IVP Solvers from their `.dae` files (generated code)
//! against the test set's reference solutions: DBSMC designed by the runtime's toolkit
//! per eps (error-controlled steps, located crossings) beside diffsol's BDF on the
//! index-1 form, by tolerance.
//!
//! ```text
//! cargo run --release -p dae-bench --features bdf --example ivp_testset [car_axis|andrews|slider_crank]
//! ```
//!
//! * the car axis (`examples/models/car_axis.dae`) to t = 3, its four positions;
//! * Andrews' squeezing mechanism (`examples/models/andrews.dae`, written with its mass
//!   matrix) to t = 0.03, its seven angles;
//! * the flexible slider crank (`examples/models/slider_crank.dae`, its mass matrix
//!   depending on the rod's deformation) to t = 0.1, its seven coordinates.
//!
//! Prints one table per problem, a row per run: the method and its knob, whether it
//! finished, the largest absolute error of the compared components at the end, the
//! largest constraint residual `|w|`, `f` evaluations, `J` solves and the best wall
//! time of three.

use dae_bench::{
    baseline::consistent_alg, generated::Andrews, generated::CarAxis, generated::SliderCrank,
    harness::DbsmcStep, harness::Method, harness::Scene, harness::designed_bounds,
    harness::pilot_beta_bound, harness::run_method,
};
use dae_runtime::{Model, Simulator, design::Online, trace::NoTrace};
use std::time::Instant;

include!("../../examples/models/ivp_references.rs");

/// One problem: its model, end time, reference, and the knobs of each method.
struct Problem<'a> {
    name: &'a str,
    model: &'a dyn Model,
    t_end: f64,
    truth: &'a [f64],
    /// `mu` of the pilot run and of the BDF's index-1 form.
    mu: f64,
    eps: &'a [f64],
    tols: &'a [f64],
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let only = std::env::args().nth(1);
    let (car, andrews) = (CarAxis::default(), Andrews::default());
    let crank = SliderCrank::default();
    let problems = [
        Problem {
            name: "car_axis",
            model: &car,
            t_end: 3.0,
            truth: &CAR_AXIS_AT_3,
            mu: 0.05,
            eps: &[1e-2, 1e-3, 1e-4, 1e-5, 1e-6],
            tols: &[1e-4, 1e-6, 1e-8, 1e-10],
        },
        Problem {
            name: "andrews",
            model: &andrews,
            t_end: 0.03,
            truth: &ANDREWS_AT_003,
            mu: 1e-4,
            eps: &[1e-4, 1e-5, 1e-6, 1e-7, 1e-8],
            tols: &[1e-4, 1e-6, 1e-8, 1e-10],
        },
        Problem {
            name: "slider_crank",
            model: &crank,
            t_end: 0.1,
            truth: &SLIDER_CRANK_AT_01,
            mu: 1e-4,
            eps: &[1e-4, 1e-5, 1e-6, 1e-7],
            tols: &[1e-4, 1e-6, 1e-8, 1e-10],
        },
    ];
    for p in problems
        .iter()
        .filter(|p| only.as_deref().is_none_or(|o| o == p.name))
    {
        run(p)?;
    }
    Ok(())
}

fn run(p: &Problem<'_>) -> Result<(), Box<dyn std::error::Error>> {
    let model = p.model;
    let (n, m) = (model.n_states(), model.n_constraints());
    let mut x0 = vec![0.0; n];
    let mut z = vec![0.0; m];
    model.initial_state(&mut x0);
    model.initial_alg(&mut z);
    let z0 = consistent_alg(model, 0.0, &x0, &vec![p.mu; m], &z)?;
    let beta_bound = pilot_beta_bound(model, &x0, &z0, p.t_end, p.mu, 1e-4)?;
    let scene = Scene {
        name: p.name.into(),
        model,
        x0,
        z0,
        t_end: p.t_end,
        compare: (0..p.truth.len()).collect(),
        truth: p.truth.to_vec(),
        beta_bound,
    };
    let mut methods = Vec::new();
    let bounds = designed_bounds(&scene, 1e-3, 1e-3)?;
    for &eps in p.eps {
        methods.push(bounds.dbsmc(eps, Some(DbsmcStep::Adaptive), 1e-3)?);
    }
    for &tol in p.tols {
        methods.push(Method::Bdf { mu: p.mu, tol });
    }
    println!("{} to t = {}\n", p.name, p.t_end);
    println!(
        "| method | knob | finished | error at the end | max \\|w\\| | f evals | J solves | wall ms |"
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
    for &eps in p.eps {
        online(&scene, eps);
    }
    println!();
    Ok(())
}

/// A row of DBSMC as `daec run FILE --t-end T --eps E` runs it (the runtime's online
/// design from eps and t_end alone), on the generated code: the best wall time of three,
/// design included.
fn online<M: Model + ?Sized>(scene: &Scene<'_, M>, eps: f64) {
    let (model, t_end) = (scene.model, scene.t_end);
    let eps_all = vec![eps; model.n_constraints()];
    let mut best = f64::INFINITY;
    let mut run = Err(String::new());
    for _ in 0..3 {
        let start = Instant::now();
        run = Online::default()
            .design(model, &eps_all, t_end)
            .map_err(|e| e.to_string())
            .and_then(|s| Simulator::new(model, s).map_err(|e| e.to_string()))
            .and_then(|mut sim| sim.run(&mut NoTrace).map_err(|e| e.to_string()));
        best = best.min(start.elapsed().as_secs_f64());
    }
    match run {
        Ok(s) => {
            let w = s.seen_max_abs_w.iter().fold(0.0_f64, |a, &b| a.max(b));
            println!(
                "| DBSMC online (daec run) | eps={eps:.1e} | yes | {:.2e} | {w:.2e} | {} | {} | {:.2} |",
                scene.position_error(&s.x),
                s.f_evals,
                s.solver.factorisations + s.solver.solves,
                best * 1e3
            );
        }
        Err(e) => {
            println!("| DBSMC online (daec run) | eps={eps:.1e} | {e} | NaN | NaN | 0 | 0 | NaN |")
        }
    }
}

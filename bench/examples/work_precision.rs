//! Regenerate every work-precision chart and the stability table
//! (`cargo run --release -p dae-bench --example work_precision [-- OUTPUT_DIR]`).
//!
//! Runs on the DEVELOPMENT STAND-IN chain models of `dae-bench`; switching to generated
//! models means building the same scenes with them (their state layout must be the
//! stand-in's: `[x_k, y_k, vx_k, vy_k]` per particle).

use std::f64::consts::FRAC_PI_2;
use std::fs::{self, File};
use std::io::BufWriter;
use std::path::PathBuf;
use std::time::Instant;

use dae_bench::{
    CostAxis, ErrorAxis, Method, PlanarChain, PlanarChainDae, Record, Scene, StabilityRow,
    chain_scene, chart, largest_step_row, run_method, stability_row, write_csv, write_table,
};
use dae_runtime::Model;

/// Target constraint error of the stability suite.
const TOL: f64 = 1e-3;
/// Repeats for the wall time (best of).
const REPEATS: usize = 3;

fn sweep<M: Model + ?Sized>(scene: &Scene<'_, M>) -> Vec<Method> {
    let mut out = Vec::new();
    for h in [1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4] {
        out.push(Method::IndexOne { mu: 0.05, step: h });
    }
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        out.push(Method::Bdf { mu: 0.05, tol });
    }
    for mu in [0.02, 0.05, 0.1] {
        for eps in [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5] {
            out.push(scene.dbsmc(eps, mu, 1.5, 1e-3));
        }
    }
    for h in [1e-3, 5e-4, 2e-4, 1e-4, 5e-5] {
        out.push(Method::Spsm {
            eps: 1e-3,
            mu: 0.05,
            step: h,
            gain_factor: 1.5,
        });
    }
    out
}

fn work_precision<M: Model + ?Sized>(
    scene: &Scene<'_, M>,
    dir: &std::path::Path,
    all: &mut Vec<Record>,
) {
    let clock = Instant::now();
    let records: Vec<Record> = sweep(scene)
        .iter()
        .map(|m| run_method(scene, m, REPEATS))
        .collect();
    for r in &records {
        println!(
            "  {:28} {:26} ok={:5} max|w|={:9.2e} pos_err={:9.2e} wall={:9.2e}s J={:8} f={:9}{}",
            r.line,
            r.knob,
            r.ok,
            r.max_w,
            r.pos_err,
            r.wall,
            r.j_solves,
            r.f_evals,
            if r.ok {
                String::new()
            } else {
                format!("  ({})", r.error)
            }
        );
    }
    for (axis, cost, tag, what) in [
        (
            ErrorAxis::Position,
            CostAxis::Wall,
            "position",
            "position error against wall time",
        ),
        (
            ErrorAxis::Constraint,
            CostAxis::Wall,
            "constraint",
            "constraint error against wall time",
        ),
        (
            ErrorAxis::Position,
            CostAxis::JSolves,
            "position_jsolves",
            "position error against J_s solves",
        ),
        (
            ErrorAxis::Position,
            CostAxis::FEvals,
            "position_fevals",
            "position error against f evaluations",
        ),
    ] {
        let path = dir.join(format!("{}_{tag}.svg", scene.name));
        if let Err(e) = chart(
            &records,
            &format!("{}: {what}", scene.name),
            axis,
            cost,
            &path,
        ) {
            eprintln!("chart: {e}");
        }
    }
    println!("  ({:.1} s)", clock.elapsed().as_secs_f64());
    all.extend(records);
}

fn nominal<M: Model + ?Sized>(scene: &Scene<'_, M>) -> Vec<Method> {
    vec![
        scene.dbsmc(TOL / 2.0, 0.05, 1.5, 1e-3),
        Method::Spsm {
            eps: TOL / 2.0,
            mu: 0.05,
            step: 2e-4,
            gain_factor: 1.5,
        },
        Method::IndexOne {
            mu: 0.05,
            step: 1e-3,
        },
        // Practically no stabilisation: poles at -1/mu = -1e-3, so s = 0 is w'' = 0.
        Method::IndexOne {
            mu: 1e3,
            step: 1e-3,
        },
        Method::Bdf {
            mu: 0.05,
            tol: 1e-8,
        },
    ]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/dae-bench".into()),
    );
    fs::create_dir_all(&dir)?;
    let total = Instant::now();

    // Work-precision scenes (consistent starts at rest, truth in minimal coordinates).
    let dp = PlanarChain::double_pendulum();
    let dp_dae = PlanarChainDae::new(&dp)?;
    let chain5 = PlanarChain::new(vec![0.1; 5], vec![0.5; 5], 9.8)?;
    let chain5_dae = PlanarChainDae::new(&chain5)?;
    let mut records = Vec::new();
    let s_dp = chain_scene(
        "double_pendulum",
        &dp_dae,
        &dp,
        &[-FRAC_PI_2, -FRAC_PI_2],
        2.0,
    )?;
    println!(
        "work-precision, {} (beta bound {:?})",
        s_dp.name, s_dp.beta_bound
    );
    work_precision(&s_dp, &dir, &mut records);
    let s_c5 = chain_scene(
        "chain5",
        &chain5_dae,
        &chain5,
        &[-1.2, -0.9, -0.6, -0.3, 0.0],
        2.0,
    )?;
    println!(
        "work-precision, {} (beta bound {:?})",
        s_c5.name, s_c5.beta_bound
    );
    work_precision(&s_c5, &dir, &mut records);
    write_csv(
        &records,
        BufWriter::new(File::create(dir.join("work_precision.csv"))?),
    )?;

    // Stability suite.
    let mut rows: Vec<StabilityRow> = Vec::new();
    let table = |rows: &mut Vec<StabilityRow>, row: StabilityRow| {
        println!(
            "  {:55} {:45} {:8} {}",
            row.scene,
            row.method,
            row.verdict.to_string(),
            row.figure
        );
        rows.push(row);
    };
    println!("stability (i): 10^6 steps of h = 1e-3 (1000 s), envelope windows of 1 s");
    let long = chain_scene(
        "double_pendulum 1000 s",
        &dp_dae,
        &dp,
        &[-FRAC_PI_2, -FRAC_PI_2],
        1000.0,
    )?;
    for m in nominal(&long) {
        table(
            &mut rows,
            stability_row("(i) long run", &long, &m, TOL, 1.0),
        );
    }
    println!("stability (ii): language.md initial state (|R1| = 1, L1 = 2: inconsistent)");
    let lang = PlanarChainDae::language_double_pendulum();
    let inconsistent = Scene {
        name: "double_pendulum language.md start".into(),
        model: &lang,
        x0: lang.x0.clone(),
        z0: vec![0.0; 2],
        t_end: 3.0,
        compare: Vec::new(),
        truth: Vec::new(),
        beta_bound: long.beta_bound.clone(),
    };
    for m in nominal(&inconsistent) {
        table(
            &mut rows,
            stability_row("(ii) inconsistent start", &inconsistent, &m, TOL, 0.05),
        );
    }
    println!("stability (iii): 3-link chain, end mass 1000 x the others");
    let heavy = PlanarChain::new(vec![0.1, 0.1, 100.0], vec![1.0; 3], 9.8)?;
    let heavy_dae = PlanarChainDae::new(&heavy)?;
    let s_heavy = chain_scene(
        "chain3 heavy end",
        &heavy_dae,
        &heavy,
        &[-1.0, -0.7, -0.4],
        3.0,
    )?;
    for m in nominal(&s_heavy) {
        table(
            &mut rows,
            stability_row("(iii) stiff", &s_heavy, &m, TOL, 0.05),
        );
    }
    println!("stability (iv): 4-link chain released almost straight (J_Omega worst conditioned)");
    let straight = PlanarChain::new(vec![0.1; 4], vec![0.5; 4], 9.8)?;
    let straight_dae = PlanarChainDae::new(&straight)?;
    let th: Vec<f64> = (0..4).map(|k| -FRAC_PI_2 + 1e-3 * k as f64).collect();
    let s_straight = chain_scene("chain4 straight", &straight_dae, &straight, &th, 2.0)?;
    for m in nominal(&s_straight) {
        table(
            &mut rows,
            stability_row("(iv) near-singular", &s_straight, &m, TOL, 0.05),
        );
    }
    println!("stability (v): largest step with max|w| <= {TOL:.0e} on the 2 s double pendulum");
    for m in nominal(&s_dp) {
        table(&mut rows, largest_step_row(&s_dp, &m, TOL, 1e-6, 0.1, 10));
    }
    write_table(
        &rows,
        BufWriter::new(File::create(dir.join("stability.md"))?),
    )?;
    println!(
        "wrote {} ({:.0} s)",
        dir.display(),
        total.elapsed().as_secs_f64()
    );
    Ok(())
}

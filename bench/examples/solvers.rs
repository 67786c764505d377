//! Cost of one control update's linear algebra (factor `J_s` + one solve) for every
//! solver of the runtime's seam on particle Jacobians (chains, cloth, random trees) at
//! about 10^2, 10^3 and 10^4 links, with fitted exponents:
//! `cargo run --release -p dae-bench --example solvers`.
//!
//! Columns: symbolic analysis (once per pattern), factor, solve, update = factor +
//! solve (best of several batches, one core), values kept by the solver per nonzero of
//! `J_Omega` (memory), and the relative residual `|J_s y - b| / |b|` of the solve (0 up to
//! rounding for exact solvers; the approximation's quality otherwise). The exponent is
//! the least-squares slope of log(update time) over log(m) across the sizes.

use std::hint::black_box;
use std::time::Instant;

use dae_bench::{particles::Lcg, particles::Particles, timing::best_time};
use dae_runtime::{
    solve::DENSE_MAX, solve::LinearSolver, solve::Solver, solve::SolverChoice, solve::mul_js,
};

struct Row {
    family: &'static str,
    m: usize,
    nnz: usize,
    solver: String,
    symbolic: f64,
    factor: f64,
    solve: f64,
    memory: f64,
    residual: f64,
}

fn measure(family: &'static str, p: &Particles, choice: SolverChoice) -> Option<Row> {
    let m = p.links.len();
    let (pattern, values) = p.jacobian();
    // Row scaling mu_i^(r-1) with mu differing per row (index 3: mu^2).
    let mut rng = Lcg(99);
    let scale: Vec<f64> = (0..m)
        .map(|_| (0.05 + 0.03 * rng.uniform()).powi(2))
        .collect();
    let b: Vec<f64> = (0..m).map(|_| 2.0 * rng.uniform() - 1.0).collect();
    let t = Instant::now();
    let mut solver = Solver::new(m, &pattern, choice).ok()?;
    let symbolic = t.elapsed().as_secs_f64();
    solver
        .factor(&values, &scale)
        .expect("particle J_Omega factors");
    let factor = best_time(|| solver.factor(black_box(&values), &scale).expect("factor"));
    let mut y = b.clone();
    let solve = best_time(|| {
        y.copy_from_slice(&b);
        solver.solve(black_box(&mut y));
    });
    y.copy_from_slice(&b);
    solver.solve(&mut y);
    let mut jy = vec![0.0; m];
    mul_js(&pattern, &values, &scale, &y, &mut jy);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let r: Vec<f64> = jy.iter().zip(&b).map(|(a, b)| a - b).collect();
    Some(Row {
        family,
        m,
        nnz: pattern.len(),
        solver: solver.name().to_string(),
        symbolic,
        factor,
        solve,
        memory: solver.stored_values() as f64 / pattern.len() as f64,
        residual: norm(&r) / norm(&b),
    })
}

/// `p` with its links in a random order.
fn shuffled(mut p: Particles, seed: u64) -> Particles {
    let mut rng = Lcg(seed);
    for i in (1..p.links.len()).rev() {
        let j = ((rng.uniform() * (i + 1) as f64) as usize).min(i);
        p.links.swap(i, j);
    }
    p
}

fn fmt_time(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else {
        format!("{:.2} ms", s * 1e3)
    }
}

fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    sxy / sxx
}

fn main() {
    let choices = [
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Tree,
        SolverChoice::Jacobi,
        SolverChoice::GaussSeidel(4),
        SolverChoice::Cg(4),
        SolverChoice::Ilu0,
    ];
    type Scene = (&'static str, Vec<Particles>);
    let scenes: Vec<Scene> = vec![
        (
            "chain",
            [100, 1000, 10_000]
                .iter()
                .map(|&n| Particles::chain(n, 0.3, 10.0))
                .collect(),
        ),
        (
            "random tree",
            [100, 1000, 10_000]
                .iter()
                .map(|&n| Particles::random_tree(n, 7))
                .collect(),
        ),
        (
            "cloth",
            [8, 23, 71]
                .iter()
                .map(|&w| Particles::cloth(w, 0.05, 3))
                .collect(),
        ),
        ("cloth 64x64", vec![Particles::cloth(64, 0.05, 3)]),
        // The same links numbered at random: the fill of a minimum degree order
        // depends on the numbering (its ties).
        (
            "cloth 64x64 shuffled",
            vec![shuffled(Particles::cloth(64, 0.05, 3), 1)],
        ),
    ];
    println!(
        "| scene | m | nnz | solver | symbolic | factor | solve | update | values/nnz | residual |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut fits = Vec::new();
    for (family, systems) in &scenes {
        for &choice in &choices {
            let mut points = Vec::new();
            for p in systems {
                // Dense LU beyond 2,000 rows: 32 MB and seconds per update; left out.
                if choice == SolverChoice::Dense && p.links.len() > 2000 {
                    continue;
                }
                let Some(r) = measure(family, p, choice) else {
                    continue;
                };
                println!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.1e} |",
                    r.family,
                    r.m,
                    r.nnz,
                    r.solver,
                    fmt_time(r.symbolic),
                    fmt_time(r.factor),
                    fmt_time(r.solve),
                    fmt_time(r.factor + r.solve),
                    r.memory,
                    r.residual
                );
                points.push((r.m as f64, r.factor + r.solve, r.solver));
            }
            if points.len() >= 2 {
                let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
                let last = xy.len() - 1;
                fits.push(format!(
                    "| {family} | {} | {:.2} | {:.1} |",
                    points[0].2,
                    slope(&xy),
                    xy[last].1 / xy[last - 1].1
                ));
            }
        }
    }
    // Where the exact sparse solvers overtake dense LU (the Auto threshold DENSE_MAX).
    println!("\nSmall systems: update time (factor + solve) of dense LU against the exact");
    println!("solver Auto picks above DENSE_MAX = {DENSE_MAX}:\n");
    println!("| scene | m | dense | sparse | tree |");
    println!("|---|---|---|---|---|");
    for m in [10, 20, 40, 80] {
        let w = ((m as f64 / 2.0).sqrt() + 1.0).round() as usize;
        for (family, p) in [
            ("chain", Particles::chain(m, 0.3, 10.0)),
            ("random tree", Particles::random_tree(m, 7)),
            ("cloth", Particles::cloth(w, 0.05, 3)),
        ] {
            let t = |c| measure(family, &p, c).map(|r| fmt_time(r.factor + r.solve));
            println!(
                "| {family} | {} | {} | {} | {} |",
                p.links.len(),
                t(SolverChoice::Dense).unwrap_or_default(),
                t(SolverChoice::Sparse).unwrap_or_default(),
                t(SolverChoice::Tree).unwrap_or_else(|| "-".into())
            );
        }
    }
    println!("\nFitted exponent of the update time in m (10^2 .. 10^4 links), and the time");
    println!("ratio between the two largest sizes (10x the links):\n");
    println!("| scene | solver | exponent | ratio |");
    println!("|---|---|---|---|");
    for f in fits {
        println!("{f}");
    }
}

//! The runtime's solvers of `J_s` against its dense LU on particle Jacobians (chains,
//! cloth, random trees) and on the generated example models; singular patterns; the
//! robustness condition (T 3.22) against a brute-force dense evaluation; and the
//! gain-raising policy on a straight chain solved with the inverse diagonal.

use dae_bench::{
    generated::Chain3, generated::Chain5, generated::DoublePendulum, generated::DoublePendulum3D,
    particles::Lcg, particles::Particles, scenes::chain_scene, truth::PlanarChain,
};
use dae_runtime::settings::{Dbsmc, GainRule, Update};
use dae_runtime::{
    Model, Settings, Simulator, Trace, solve::LinearSolver, solve::SolveError, solve::Solver,
    solve::SolverChoice, solve::mul_js,
};

const EXACT: [SolverChoice; 4] = [
    SolverChoice::Dense,
    SolverChoice::Sparse,
    SolverChoice::Tree,
    SolverChoice::Auto,
];

fn solve_with(
    choice: SolverChoice,
    m: usize,
    pat: &[(usize, usize)],
    vals: &[f64],
    d: &[f64],
    b: &[f64],
) -> Option<Vec<f64>> {
    let mut s = Solver::new(m, pat, choice).ok()?;
    s.factor(vals, d).expect("factors");
    let mut y = b.to_vec();
    s.solve(&mut y);
    Some(y)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300f64, |s, v| s.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()))
        / scale
}

/// Row scaling `mu_i^2` with `mu` differing per row, and a right-hand side.
fn scaling_and_rhs(m: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Lcg(seed);
    let d = (0..m)
        .map(|_| (0.03 + 0.05 * rng.uniform()).powi(2))
        .collect();
    let b = (0..m).map(|_| 2.0 * rng.uniform() - 1.0).collect();
    (d, b)
}

fn particle_scenes() -> Vec<(&'static str, Particles)> {
    vec![
        ("straight chain", Particles::chain(60, 0.0, 1.0)),
        ("bent chain, heavy end", Particles::chain(80, 0.4, 50.0)),
        ("cloth 9x9", Particles::cloth(9, 0.1, 2)),
        ("random tree", Particles::random_tree(150, 4)),
        ("random tree 2", Particles::random_tree(90, 12)),
    ]
}

#[test]
fn exact_solvers_agree_with_dense_lu_on_particle_jacobians() {
    for (name, p) in particle_scenes() {
        let m = p.links.len();
        let (pat, vals) = p.jacobian();
        let (d, b) = scaling_and_rhs(m, 1);
        let dense = solve_with(SolverChoice::Dense, m, &pat, &vals, &d, &b).unwrap();
        // Residual of the reference itself.
        let mut r = vec![0.0; m];
        mul_js(&pat, &vals, &d, &dense, &mut r);
        assert!(max_diff(&r, &b) < 1e-10, "{name}: dense residual");
        for choice in EXACT {
            let forest = Solver::new(m, &pat, SolverChoice::Tree).is_ok();
            match solve_with(choice, m, &pat, &vals, &d, &b) {
                Some(y) => {
                    let e = max_diff(&y, &dense);
                    assert!(e < 1e-10, "{name}, {choice}: relative difference {e}");
                }
                None => assert!(
                    choice == SolverChoice::Tree && !forest,
                    "{name}: {choice} refused"
                ),
            }
        }
    }
}

#[test]
fn approximate_solvers_are_what_they_claim_on_particle_jacobians() {
    for (name, p) in particle_scenes() {
        let m = p.links.len();
        let (pat, vals) = p.jacobian();
        let (d, b) = scaling_and_rhs(m, 2);
        let dense = solve_with(SolverChoice::Dense, m, &pat, &vals, &d, &b).unwrap();
        // Jacobi: exactly b_i / (J_s)_ii.
        let jac = solve_with(SolverChoice::Jacobi, m, &pat, &vals, &d, &b).unwrap();
        for (i, y) in jac.iter().enumerate() {
            let a = pat.iter().position(|&e| e == (i, i)).unwrap();
            assert!((y - b[i] / (d[i] * vals[a])).abs() <= 1e-14 * y.abs().max(1.0));
        }
        // K Gauss-Seidel sweeps from zero: exactly the dense sweeps.
        for sweeps in [1, 3, 10] {
            let y = solve_with(SolverChoice::GaussSeidel(sweeps), m, &pat, &vals, &d, &b).unwrap();
            let oracle = dense_gauss_seidel(m, &pat, &vals, &d, &b, sweeps);
            assert!(max_diff(&y, &oracle) < 1e-12, "{name}: {sweeps} sweeps");
        }
        // CG converges to the dense solution within a few times m iterations (-J_Omega is
        // positive definite).
        let y = solve_with(SolverChoice::Cg(4 * m as u32), m, &pat, &vals, &d, &b).unwrap();
        let e = max_diff(&y, &dense);
        assert!(e < 1e-8, "{name}, cg: relative difference {e}");
        // CG minimises the error in the norm of -J_Omega: more iterations, smaller error.
        let err = |iters: u32| {
            let y = solve_with(SolverChoice::Cg(iters), m, &pat, &vals, &d, &b).unwrap();
            let e: Vec<f64> = y.iter().zip(&dense).map(|(a, b)| a - b).collect();
            let mut je = vec![0.0; m];
            mul_js(&pat, &vals, &vec![1.0; m], &e, &mut je);
            -e.iter().zip(&je).map(|(a, b)| a * b).sum::<f64>()
        };
        assert!(
            err(6) < err(3),
            "{name}: cg errors {} vs {}",
            err(6),
            err(3)
        );
    }
}

/// Dense oracle of `sweeps` forward Gauss-Seidel sweeps on `J_s y = b` from zero.
fn dense_gauss_seidel(
    m: usize,
    pat: &[(usize, usize)],
    vals: &[f64],
    d: &[f64],
    b: &[f64],
    sweeps: u32,
) -> Vec<f64> {
    let mut a = vec![0.0; m * m];
    for (&(i, j), v) in pat.iter().zip(vals) {
        a[i * m + j] = d[i] * v;
    }
    let mut y = vec![0.0; m];
    for _ in 0..sweeps {
        for i in 0..m {
            let off: f64 = (0..m)
                .filter(|&j| j != i)
                .map(|j| a[i * m + j] * y[j])
                .sum();
            y[i] = (b[i] - off) / a[i * m + i];
        }
    }
    y
}

/// Dense oracle of ILU(0): Gaussian elimination without pivoting in which every update
/// outside the pattern is dropped.
fn dense_ilu0_solve(
    m: usize,
    pat: &[(usize, usize)],
    vals: &[f64],
    d: &[f64],
    b: &[f64],
) -> Vec<f64> {
    let mut a = vec![0.0; m * m];
    let mut inp = vec![false; m * m];
    for (&(i, j), v) in pat.iter().zip(vals) {
        a[i * m + j] = *v;
        inp[i * m + j] = true;
    }
    for i in 0..m {
        for k in 0..i {
            if !inp[i * m + k] {
                continue;
            }
            a[i * m + k] /= a[k * m + k];
            for j in k + 1..m {
                if inp[i * m + j] && inp[k * m + j] {
                    a[i * m + j] -= a[i * m + k] * a[k * m + j];
                }
            }
        }
    }
    let mut y: Vec<f64> = b.iter().zip(d).map(|(b, d)| b / d).collect();
    for i in 0..m {
        for k in 0..i {
            y[i] -= a[i * m + k] * y[k];
        }
    }
    for i in (0..m).rev() {
        for k in i + 1..m {
            y[i] -= a[i * m + k] * y[k];
        }
        y[i] /= a[i * m + i];
    }
    y
}

#[test]
fn ilu0_matches_a_dense_incomplete_elimination_and_is_exact_on_forests() {
    for (name, p) in particle_scenes() {
        let m = p.links.len();
        let (pat, vals) = p.jacobian();
        let (d, b) = scaling_and_rhs(m, 3);
        let y = solve_with(SolverChoice::Ilu0, m, &pat, &vals, &d, &b).unwrap();
        let oracle = dense_ilu0_solve(m, &pat, &vals, &d, &b);
        assert!(max_diff(&y, &oracle) < 1e-10, "{name}");
        if Solver::new(m, &pat, SolverChoice::Tree).is_ok() {
            let dense = solve_with(SolverChoice::Dense, m, &pat, &vals, &d, &b).unwrap();
            assert!(
                max_diff(&y, &dense) < 1e-10,
                "{name}: ILU(0) on a forest is exact"
            );
        }
    }
}

/// `J_Omega` of a generated model at its initial state and at a perturbed one.
fn model_jacobians(model: &dyn Model) -> Vec<Vec<f64>> {
    let (n, m) = (model.n_states(), model.n_constraints());
    let mut x = vec![0.0; n];
    let mut z = vec![0.0; m];
    model.initial_state(&mut x);
    model.initial_alg(&mut z);
    let mut out = Vec::new();
    let mut rng = Lcg(5);
    for _ in 0..2 {
        let mut j = vec![0.0; model.jacobian_pattern().len()];
        model.jacobian(0.3, &x, &z, &mut j);
        out.push(j);
        for v in x.iter_mut().chain(z.iter_mut()) {
            *v += 0.2 * (2.0 * rng.uniform() - 1.0);
        }
    }
    out
}

#[test]
fn every_solver_agrees_with_dense_lu_on_the_example_models() {
    let models: [&dyn Model; 4] = [
        &Chain5::default(),
        &Chain3::default(),
        &DoublePendulum::default(),
        &DoublePendulum3D::default(),
    ];
    for model in models {
        let m = model.n_constraints();
        let pat = model.jacobian_pattern();
        let (d, b) = scaling_and_rhs(m, 7);
        for vals in model_jacobians(model) {
            let dense = solve_with(SolverChoice::Dense, m, pat, &vals, &d, &b).unwrap();
            for choice in EXACT {
                if let Some(y) = solve_with(choice, m, pat, &vals, &d, &b) {
                    let e = max_diff(&y, &dense);
                    assert!(e < 1e-10, "{}, {choice}: {e}", model.name());
                }
            }
            for c in [SolverChoice::GaussSeidel(400), SolverChoice::Cg(50)] {
                let mut s = Solver::new(m, pat, c).unwrap();
                match s.factor(&vals, &d) {
                    Ok(()) => {
                        let mut y = b.clone();
                        s.solve(&mut y);
                        let e = max_diff(&y, &dense);
                        assert!(e < 1e-7, "{}, {c}: {e}", model.name());
                    }
                    // CG refuses an unsymmetric J_Omega, naming the entry.
                    Err(SolveError::NotSymmetric { .. }) => {
                        assert!(matches!(c, SolverChoice::Cg(_)))
                    }
                    Err(e) => panic!("{}, {c}: {e}", model.name()),
                }
            }
        }
    }
}

#[test]
fn a_redundant_link_is_reported_with_the_links_involved() {
    // Link 2 doubled (link 6 joins the same particles): rows 2 and 6 of J_Omega agree.
    let p = Particles::chain(6, 0.3, 1.0).with_duplicate_link(2);
    let (pat, vals) = p.jacobian();
    let (d, _) = scaling_and_rhs(7, 9);
    for c in [
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Auto,
    ] {
        let mut s = Solver::new(7, &pat, c).unwrap();
        assert_eq!(
            s.factor(&vals, &d).unwrap_err(),
            SolveError::Singular {
                constraints: vec![2, 6]
            },
            "{c}"
        );
    }
    // Above the size of the dense diagnosis the sparse solver names them through the
    // null vector of its failed pivot: a 30x30 cloth (1,740 links) with link 100 doubled.
    let cloth = Particles::cloth(30, 0.1, 4);
    let m = cloth.links.len() + 1;
    let (pat, vals) = cloth.with_duplicate_link(100).jacobian();
    let (d, _) = scaling_and_rhs(m, 9);
    let mut s = Solver::new(m, &pat, SolverChoice::Sparse).unwrap();
    assert_eq!(
        s.factor(&vals, &d).unwrap_err(),
        SolveError::Singular {
            constraints: vec![100, m - 1]
        }
    );
}

/// A chain scene of the generated 5-link chain hanging straight down at rest.
fn straight_chain() -> (Chain5, PlanarChain) {
    (
        Chain5::default(),
        PlanarChain::new(vec![0.1; 5], vec![1.0; 5], 9.8).unwrap(),
    )
}

/// Brute force (T 3.22) at one point: `E = J_s J_hat^{-1}` densely for the inverse
/// diagonal, `D = E K`, `gamma = alpha - E alpha_hat`; the rows that fail.
fn jacobi_failures(model: &dyn Model, t: f64, x: &[f64], z: &[f64], mu: f64, k: &[f64]) -> u64 {
    let m = model.n_constraints();
    let mut w = vec![0.0; model.indices().iter().sum()];
    let (mut s, mut ah, mut beta) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    model.sliding(t, x, z, &vec![mu; m], &mut w, &mut s, &mut ah);
    model.beta(t, x, z, &mut beta);
    let mut js = vec![0.0; m * m];
    let mut vals = vec![0.0; model.jacobian_pattern().len()];
    model.jacobian(t, x, z, &mut vals);
    for (&(i, j), v) in model.jacobian_pattern().iter().zip(&vals) {
        js[i * m + j] = mu * mu * v;
    }
    let mut fails = 0;
    for i in 0..m {
        let e = |j: usize| js[i * m + j] / js[j * m + j];
        let alpha_i = ah[i] + mu * mu * beta[i];
        let e_ah: f64 = (0..m).map(|j| e(j) * ah[j]).sum();
        let gamma = alpha_i - e_ah;
        let off: f64 = (0..m)
            .filter(|&j| j != i)
            .map(|j| (e(j) * k[j]).abs())
            .sum();
        let holds = e(i) * k[i] > gamma.abs() + off;
        if !holds {
            fails += 1;
        }
    }
    fails
}

fn jacobi_settings(
    scene_x0: &[f64],
    scene_z0: &[f64],
    gains: Vec<f64>,
    eps: f64,
    mu: f64,
) -> Settings {
    Settings::new(vec![eps; 5], vec![mu; 5], gains)
        .step(2e-5)
        .t_end(0.3)
        .settle(0.1)
        .solver(SolverChoice::Jacobi)
        .initial(scene_x0.to_vec(), scene_z0.to_vec())
}

#[test]
fn robustness_count_with_jacobi_matches_a_brute_force_dense_evaluation() {
    let (model, chain) = straight_chain();
    // Slightly bent, so that J_Omega is not exactly the straight chain's.
    let scene = chain_scene("bent", &model, &chain, &[0.1, -0.1, 0.2, 0.0, -0.2], 0.3).unwrap();
    let (eps, mu) = (1e-3, 0.05);
    let gains = scene.gains(mu, 1.5);
    let settings = jacobi_settings(&scene.x0, &scene.z0, gains.clone(), eps, mu)
        .law(Dbsmc::default().update(Update::Fixed { period: 1e-3 }));
    let mut trace = Trace::new();
    let summary = Simulator::new(&model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    let from = summary.stats_from.unwrap();
    let mut expected = 0;
    let mut updates = 0;
    for &tu in trace.update_times().iter().filter(|&&t| t >= from) {
        let k = trace.times().iter().position(|&t| t == tu).unwrap();
        expected += jacobi_failures(&model, tu, trace.x(k), trace.z(k), mu, &gains);
        updates += 1;
    }
    assert!(updates > 100);
    assert!(
        expected > 0,
        "the inverse diagonal of a chain violates (T 3.22)"
    );
    assert_eq!(summary.robustness_violations, Some(expected));
    assert_eq!(summary.solver.robustness_failures, expected);
    assert_eq!(summary.solver.name, "jacobi");
}

#[test]
fn raised_gains_restore_the_condition_on_a_straight_chain_with_jacobi() {
    let (model, chain) = straight_chain();
    // Straight, released at 0.6 rad from the vertical: it swings and stays nearly
    // straight over the run.
    let scene = chain_scene("straight", &model, &chain, &[0.6; 5], 0.3).unwrap();
    let (eps, mu) = (1e-3, 0.05);
    // Uniform gains: every interior row of the straight chain then fails by equality
    // (|E_i,i-1| + |E_i,i+1| = 1), the row next to the pinned link by more.
    let k = scene.gains(mu, 1.5).into_iter().fold(0.0, f64::max);
    let gains = vec![k; 5];
    let base = jacobi_settings(&scene.x0, &scene.z0, gains.clone(), eps, mu);
    let kept = Simulator::new(&model, base.clone())
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    let kept_fails = kept.robustness_violations.unwrap();
    assert!(
        kept_fails > 0,
        "the straight chain's inverse diagonal violates (T 3.22)"
    );
    let mut trace = Trace::new();
    let mut raise = base.clone();
    raise.dbsmc_mut().expect("a DBSMC law").gains = GainRule::Raise { margin: 0.05 };
    let raised = Simulator::new(&model, raise)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    // Most raises happen before the window; in it, a row fails only when its gamma grew
    // past the margin since its last raise (and is raised again at once): a thousandth
    // of the failures with the kept gains. The brute-force evaluation at the last update
    // with the final gains finds every row satisfied.
    assert!(raised.solver.gain_raises > 0);
    let raised_fails = raised.robustness_violations.unwrap();
    assert!(
        raised_fails * 1000 <= kept_fails,
        "raised {raised_fails}, kept {kept_fails}"
    );
    assert!(raised.gains.iter().zip(&gains).all(|(r, k)| r >= k));
    assert!(raised.gains.iter().zip(&gains).any(|(r, k)| *r > 1.5 * k));
    let last = *trace.update_times().last().unwrap();
    let k = trace.times().iter().position(|&t| t == last).unwrap();
    assert_eq!(
        jacobi_failures(&model, last, trace.x(k), trace.z(k), mu, &raised.gains),
        0
    );
    // And the motion stays in its layers.
    for (i, s) in raised.max_abs_s.as_ref().unwrap().iter().enumerate() {
        assert!(*s <= 1.1 * eps, "|s{}| = {s}", i + 1);
    }
}

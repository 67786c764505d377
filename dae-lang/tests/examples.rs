//! The example models in `examples/models/` check, and encode the equations their
//! comments (and docs/method.md) state: evaluated at chosen points, their right-hand sides
//! and residuals match values computed by hand from the physics.

use dae_lang::ast::BinOp;
use dae_lang::model::{Model, RExpr};
use dae_lang::{Func, VarRef};
use std::path::PathBuf;

fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/models")
}

fn load(name: &str) -> Model {
    let path = models_dir().join(name);
    let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match dae_lang::check_source(&src) {
        Ok(mut ms) if ms.len() == 1 => ms.remove(0),
        Ok(ms) => panic!("{name}: expected one model, got {}", ms.len()),
        Err(d) => {
            panic!(
                "{name}: {}",
                d.iter()
                    .map(|x| x.render(name, &src, false))
                    .collect::<String>()
            )
        }
    }
}

/// A point of evaluation: values of states, algebraics and time.
struct Point<'a> {
    m: &'a Model,
    x: Vec<f64>,
    z: Vec<f64>,
    t: f64,
    lets: Vec<f64>,
}

/// A direct tree-walking evaluator, written for these tests only.
fn eval(e: &RExpr, p: &Point<'_>) -> f64 {
    match e {
        RExpr::Num(v) => *v,
        RExpr::Var(VarRef::Param(i)) => p.m.params[i.index()].default,
        RExpr::Var(VarRef::State(i)) => p.x[i.index()],
        RExpr::Var(VarRef::Alg(i)) => p.z[i.index()],
        RExpr::Var(VarRef::Time) => p.t,
        RExpr::Var(VarRef::Mu(_)) => panic!("a checked model has no realization parameter"),
        RExpr::Var(v) => panic!("{v:?}: the version-1 examples have no family variables"),
        RExpr::Let(i) => p.lets[i.index()],
        RExpr::Neg(a) => -eval(a, p),
        RExpr::Binary(op, a, b) => {
            let (a, b) = (eval(a, p), eval(b, p));
            match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
                BinOp::Pow => a.powf(b),
            }
        }
        RExpr::Call(f, args) => {
            let a: Vec<f64> = args.iter().map(|x| eval(x, p)).collect();
            match f {
                Func::Sin => a[0].sin(),
                Func::Cos => a[0].cos(),
                Func::Sqrt => a[0].sqrt(),
                other => panic!("function {other:?} not used by the examples"),
            }
        }
        other => panic!("{other:?}: the version-1 examples have no family forms"),
    }
}

fn point<'a>(m: &'a Model, x: Vec<f64>, z: Vec<f64>, t: f64) -> Point<'a> {
    let mut p = Point {
        m,
        x,
        z,
        t,
        lets: Vec::new(),
    };
    // `Model::lets` is ordered so that each uses only earlier ones.
    for l in &m.lets {
        let v = eval(&l.expr, &p);
        p.lets.push(v);
    }
    p
}

/// States and algebraics at their initial values.
fn initial(m: &Model) -> (Vec<f64>, Vec<f64>) {
    // Initial values use only numbers and parameters: no state, let or time is needed.
    let empty = Point {
        m,
        x: vec![],
        z: vec![],
        t: f64::NAN,
        lets: vec![],
    };
    (
        m.states.iter().map(|s| eval(&s.init, &empty)).collect(),
        m.algs.iter().map(|a| eval(&a.init, &empty)).collect(),
    )
}

fn names(list: impl Iterator<Item = String>) -> Vec<String> {
    list.collect()
}

fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{a:?} vs {b:?}");
    }
}

#[test]
fn every_example_model_checks() {
    let mut count = 0;
    for entry in std::fs::read_dir(models_dir()).expect("examples/models exists") {
        let path = entry.expect("readable directory").path();
        if path.extension().is_some_and(|e| e == "dae") {
            let src = std::fs::read_to_string(&path).expect("readable model");
            let models = dae_lang::check_source(&src)
                .unwrap_or_else(|d| panic!("{}: {d:#?}", path.display()));
            assert!(!models.is_empty());
            count += 1;
        }
    }
    assert!(count >= 5, "found {count} example models");
}

#[test]
fn double_pendulum_3d_has_the_thesis_equations() {
    let m = load("double_pendulum_3d.dae");
    let states = names(m.states.iter().map(|s| s.name.clone()));
    assert_eq!(
        states,
        [
            "p1x", "p1y", "p1z", "p2x", "p2y", "p2z", "v1x", "v1y", "v1z", "v2x", "v2y", "v2z"
        ]
    );
    assert_eq!(names(m.algs.iter().map(|a| a.name.clone())), ["z1", "z2"]);
    let params: Vec<(&str, f64)> = m
        .params
        .iter()
        .map(|p| (p.name.as_str(), p.default))
        .collect();
    assert_eq!(
        params,
        [
            ("m1", 0.1),
            ("m2", 0.1),
            ("L1", 2.0),
            ("L2", 2.0),
            ("g", 9.8)
        ]
    );
    let (x0, z0) = initial(&m);
    close(
        &x0,
        &[-1.0, 0.0, 0.0, -5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    );
    close(&z0, &[0.0, 0.0]);
    // docs/method.md section 8: w1(0) = |R1| - L1 = -1, w2(0) = |R2 - R1| - L2 = 2.
    let p = point(&m, x0.clone(), z0, 0.0);
    close(
        &m.constraints
            .iter()
            .map(|c| eval(&c.residual, &p))
            .collect::<Vec<_>>(),
        &[-1.0, 2.0],
    );

    // A general point, accelerations from m1 R1'' = -z1 r01 + z2 r12 - m1 g k and
    // m2 R2'' = -z2 r12 - m2 g k computed here by hand.
    let r1 = [0.3, -1.2, 0.7];
    let r2 = [1.1, 0.4, -0.9];
    let v = [0.5, -0.25, 1.5, -2.0, 0.75, 0.1];
    let (z1, z2) = (3.0, -1.5);
    let x: Vec<f64> = r1.iter().chain(&r2).chain(&v).copied().collect();
    let p = point(&m, x, vec![z1, z2], 0.0);
    let f: Vec<f64> = m.ders.iter().map(|d| eval(&d.expr, &p)).collect();
    let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let l1 = norm(r1);
    let d = [r2[0] - r1[0], r2[1] - r1[1], r2[2] - r1[2]];
    let l2 = norm(d);
    let (m1, m2, g) = (0.1, 0.1, 9.8);
    let mut expected = v.to_vec();
    let gravity = [0.0, 0.0, g];
    for k in 0..3 {
        expected.push((-z1 * r1[k] / l1 + z2 * d[k] / l2) / m1 - gravity[k]);
    }
    for (dk, gk) in d.iter().zip(gravity) {
        expected.push(-z2 * dk / l2 / m2 - gk);
    }
    close(&f, &expected);
    close(
        &m.constraints
            .iter()
            .map(|c| eval(&c.residual, &p))
            .collect::<Vec<_>>(),
        &[l1 - 2.0, l2 - 2.0],
    );
}

#[test]
fn planar_double_pendulum_is_the_language_reference_example() {
    let m = load("double_pendulum_planar.dae");
    assert_eq!(m.name, "DoublePendulum");
    assert_eq!(m.states.len(), 8);
    let (x0, z0) = initial(&m);
    let p = point(&m, x0, z0, 0.0);
    close(
        &m.constraints
            .iter()
            .map(|c| eval(&c.residual, &p))
            .collect::<Vec<_>>(),
        &[-1.0, 2.0],
    );
    // With z = 0 the masses fall freely.
    let f: Vec<f64> = m.ders.iter().map(|d| eval(&d.expr, &p)).collect();
    close(&f, &[0.0, 0.0, 0.0, -9.8, 0.0, 0.0, 0.0, -9.8]);
}

#[test]
fn integrator_chain_starts_on_its_exact_solution() {
    let m = load("integrator_chain_index4.dae");
    // Exact solution x1 = sin t, x2 = cos t, x3 = -sin t, z = -cos t, at t = 0.7.
    let t: f64 = 0.7;
    let p = point(&m, vec![t.sin(), t.cos(), -t.sin()], vec![-t.cos()], t);
    let f: Vec<f64> = m.ders.iter().map(|d| eval(&d.expr, &p)).collect();
    close(&f, &[t.cos(), -t.sin(), -t.cos()]);
    assert!(eval(&m.constraints[0].residual, &p).abs() < 1e-15);
    let (x0, z0) = initial(&m);
    close(&x0, &[0.0, 1.0, 0.0]);
    close(&z0, &[-1.0]);
    assert_eq!(m.constraints[0].name, "c1");
}

#[test]
fn tank_level_initial_inflow_is_consistent() {
    let m = load("tank_level_index2.dae");
    let (x0, z0) = initial(&m);
    let p = point(&m, x0, z0, 0.0);
    // On the schedule, and h'(0) equals href'(0) = a w = 0.02.
    assert!(eval(&m.constraints[0].residual, &p).abs() < 1e-15);
    close(&[eval(&m.ders[0].expr, &p)], &[0.2 * 0.1]);
}

#[test]
fn circuit_satisfies_kirchhoff_at_a_hand_computed_point() {
    let m = load("circuit_index1.dae");
    let (x0, z0) = initial(&m);
    let p = point(&m, x0, z0, 0.0);
    assert!(eval(&m.constraints[0].residual, &p).abs() < 1e-15);
    // At t = 1/200 s (source at its peak, 5 V), v = 1 V, u = 2 V:
    // in through R1: (5 - 2)/100 = 0.03 A; load: 2/1000 + 1e-3 * 8 = 0.01 A;
    // through R3: (2 - 1)/220 A. Residual: 0.03 - 0.01 - 1/220. der(v) = (1/220)/1e-4.
    let p = point(&m, vec![1.0], vec![2.0], 1.0 / 200.0);
    close(
        &[eval(&m.constraints[0].residual, &p)],
        &[0.03 - 0.01 - 1.0 / 220.0],
    );
    close(&[eval(&m.ders[0].expr, &p)], &[1.0 / 220.0 / 1e-4]);
}

/// `x` with `a x = b` (`a` row-major), by elimination with partial pivoting: written here,
/// apart from the compiler's elimination in the written order.
fn solve_pivoting(mut a: Vec<f64>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
            .expect("k < n");
        for j in 0..n {
            a.swap(k * n + j, p * n + j);
        }
        b.swap(k, p);
        for i in k + 1..n {
            let l = a[i * n + k] / a[k * n + k];
            for j in k..n {
                a[i * n + j] -= l * a[k * n + j];
            }
            b[i] -= l * b[k];
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let r: f64 = (k + 1..n).map(|j| a[k * n + j] * x[j]).sum();
        x[k] = (b[k] - r) / a[k * n + k];
    }
    x
}

/// A mechanism of the IVP test set at its start: `(states, algs)` counts, one mass
/// matrix, every constraint within `residual` and the accelerations of
/// `M a = f - G^T lambda` (solved here) within `tol` of the test set's `expected`.
fn check_start(file: &str, counts: (usize, usize), residual: f64, expected: &[f64], tol: f64) {
    let m = load(file);
    assert_eq!(
        (m.states.len(), m.algs.len(), m.mass.len()),
        (counts.0, counts.1, 1)
    );
    let (x0, z0) = initial(&m);
    let p = point(&m, x0, z0, 0.0);
    for c in &m.constraints {
        let r = eval(&c.residual, &p);
        assert!(r.abs() < residual, "{file}: {}: residual {r:e}", c.name);
    }
    let mass = &m.mass[0];
    let a: Vec<f64> = mass.entries.iter().map(|e| eval(e, &p)).collect();
    let b: Vec<f64> = mass
        .states
        .iter()
        .map(|s| eval(&m.ders[s.index()].expr, &p))
        .collect();
    let acc = solve_pivoting(a, b);
    for (k, (x, y)) in acc.iter().zip(expected).enumerate() {
        assert!(
            (x - y).abs() <= tol * (1.0 + y.abs()),
            "{file}: a[{k}] = {x}, test set {y}"
        );
    }
}

/// The mass matrix, the forces and `G` as written give the test set's consistent
/// initial accelerations `y(15..21)` (its file andrews.f); the constraints hold at its
/// 30-digit start.
#[test]
fn andrews_starts_at_the_test_sets_consistent_point() {
    let expected = [
        14_222.443_919_954_114,
        -10_666.832_939_965_585,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    check_start("andrews.dae", (14, 6), 1e-15, &expected, 1e-9);
}

/// As for Andrews, to what the test set's nine-digit start allows (4e-7 measured).
#[test]
fn slider_crank_starts_at_the_test_sets_consistent_point() {
    let expected = [
        0.0,
        -1.344_541_576_008_661e-3,
        -5.062_194_923_138_079e3,
        -6.833_142_732_779_555e-5,
        1.449_382_650_173_157e-8,
        -4.268_463_211_410_861,
        2.098_334_687_947_376e-1,
    ];
    check_start("slider_crank.dae", (14, 3), 1e-9, &expected, 1e-6);
}

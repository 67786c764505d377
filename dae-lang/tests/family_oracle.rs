//! The template analysis of family models against the oracle: the same model expanded
//! into scalars (`family::expand`) and analysed by the version-1 pipeline. Every
//! function (rhs, the sliding outputs w, s and alpha_hat, J_Omega as a sparse matrix,
//! beta) of the programs, run by `Program::eval`, agrees with the version-1 tapes of
//! the expanded model at random points, for sizes 1..6; and the rate program (`Omega'`
//! along a random `z'`) with the expanded model's `beta + J_Omega z'`.

use dae_lang::family::{Instance, Program, Scratch, Sink, Spec, Values, construct, expand};
use dae_lang::model::Model;
use dae_lang::{AnalysisOptions, CompiledModel, analyze, compile};

mod common;
use common::{Rng, close, models_dir};

/// All outputs of one model at one point: rhs, w, s, alpha_hat, J (dense), beta.
#[derive(Debug)]
struct Outputs {
    rhs: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    alpha_hat: Vec<f64>,
    jacobian: Vec<f64>,
    beta: Vec<f64>,
    /// `Omega'` with the algebraic unknowns moving at the point's `zdot`.
    rate: Vec<f64>,
}

struct Point {
    params: Vec<f64>,
    states: Vec<f64>,
    algs: Vec<f64>,
    /// The direction of the algebraic unknowns for `Omega'`.
    zdot: Vec<f64>,
    mu: Vec<f64>,
    inputs: Vec<f64>,
    t: f64,
}

fn family(src: &str) -> (Model, CompiledModel) {
    let mut models = dae_lang::check_source(src).unwrap_or_else(|e| panic!("{e:#?}"));
    let m = models.remove(0);
    let a = analyze(&m, &AnalysisOptions::default()).unwrap_or_else(|e| panic!("{e:#?}"));
    let c = compile(&a);
    assert!(c.is_family());
    (m, c)
}

fn eval_family(c: &CompiledModel, inst: &Instance, p: &Point) -> Outputs {
    let f = &c.programs;
    let l = &inst.layout;
    let x = Values {
        params: &p.params,
        states: &p.states,
        algs: &p.algs,
        alg_rates: &p.zdot,
        mu: &p.mu,
        inputs: &p.inputs,
        t: p.t,
    };
    let run = |prog: &dae_lang::family::Program, outs: &mut [&mut [f64]]| {
        let mut scratch = Scratch::new(prog, inst);
        prog.eval(inst, &x, &mut scratch, outs);
    };
    let mut rhs = vec![f64::NAN; l.n_states];
    run(&f.rhs, &mut [&mut rhs]);
    let (mut w, mut s, mut ah) = (
        vec![f64::NAN; l.n_w],
        vec![f64::NAN; l.n_rows],
        vec![f64::NAN; l.n_rows],
    );
    run(&f.sliding, &mut [&mut w, &mut s, &mut ah]);
    let mut values = vec![f64::NAN; inst.jacobian.entries.len()];
    run(&f.jacobian, &mut [&mut values]);
    let mut rate = vec![f64::NAN; l.n_rows];
    run(&f.rate, &mut [&mut rate]);
    // `beta` is the rate program with the unknowns held.
    let held = vec![0.0; l.n_algs];
    let mut beta = vec![f64::NAN; l.n_rows];
    let mut scratch = Scratch::new(&f.rate, inst);
    f.rate.eval(
        inst,
        &Values {
            alg_rates: &held,
            ..x
        },
        &mut scratch,
        &mut [&mut beta],
    );
    let n = l.n_rows;
    let mut jacobian = vec![0.0; n * l.n_algs];
    for (&(r, col), v) in inst.jacobian.entries.iter().zip(values) {
        jacobian[r * l.n_algs + col] = v;
    }
    Outputs {
        rhs,
        w,
        s,
        alpha_hat: ah,
        jacobian,
        beta,
        rate,
    }
}

/// The expanded (scalar) model's outputs: its own programs, scheduled without sets,
/// with `Omega'` from its `J_Omega` and `beta` (not from a rate program).
fn eval_scalar(c: &CompiledModel, params: &[f64], p: &Point) -> Outputs {
    let inst = construct(&c.programs.construction, &Spec::default()).expect("the expansion");
    let (n, m, nw) = (inst.layout.n_states, c.algs.len(), c.w_len());
    let zero = vec![0.0; m];
    let run = |prog: &Program, alg_rates: &[f64], outs: &mut [&mut [f64]]| {
        let v = Values {
            params,
            states: &p.states,
            algs: &p.algs,
            alg_rates,
            mu: &p.mu,
            inputs: &[],
            t: p.t,
        };
        prog.eval(&inst, &v, &mut Scratch::new(prog, &inst), outs);
    };
    let programs = &c.programs;
    let mut rhs = vec![0.0; n];
    run(&programs.rhs, &[], &mut [&mut rhs]);
    let (mut w, mut s, mut alpha_hat) = (vec![0.0; nw], vec![0.0; m], vec![0.0; m]);
    run(
        &programs.sliding,
        &[],
        &mut [&mut w, &mut s, &mut alpha_hat],
    );
    let mut values = vec![0.0; inst.jacobian.entries.len()];
    run(&programs.jacobian, &[], &mut [&mut values]);
    let mut jacobian = vec![0.0; m * m];
    for (&(r, col), v) in inst.jacobian.entries.iter().zip(values) {
        jacobian[r * m + col] = v;
    }
    let mut beta = vec![0.0; m];
    run(&programs.rate, &zero, &mut [&mut beta]);
    let rate = (0..m)
        .map(|r| beta[r] + (0..m).map(|k| jacobian[r * m + k] * p.zdot[k]).sum::<f64>())
        .collect();
    Outputs {
        rhs,
        w,
        s,
        alpha_hat,
        jacobian,
        beta,
        rate,
    }
}

fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    assert!(!a.is_empty(), "{what}: no values");
    assert!(a.iter().all(|x| x.is_finite()), "{what}: not finite: {a:?}");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            close(*x, *y, tol),
            "{what}[{i}]: family {x} vs scalar {y}\nfamily {a:?}\nscalar {b:?}"
        );
    }
}

/// Compares the template programs with the expanded model at `points` random points.
fn compare(src: &str, spec: &Spec, seed: u64, points: usize) {
    let (m, c) = family(src);
    let mut inst = construct(&c.programs.construction, spec).unwrap_or_else(|e| panic!("{e}"));
    let mut rng = Rng::new(seed);
    // Start away from the examples' symmetric starts (a flat cloth pinned at two corners
    // has a straight edge between them, where J_Omega is singular and the expanded
    // model's initial-point check fails).
    for x in &mut inst.states {
        *x += rng.uniform(-0.1, 0.1);
    }
    let expanded = expand(&m, &inst);
    let a1 =
        analyze(&expanded.model, &AnalysisOptions::default()).unwrap_or_else(|e| panic!("{e:#?}"));
    let c1 = compile(&a1);
    assert_eq!(c1.states.len(), inst.layout.n_states);
    assert_eq!(c1.algs.len(), inst.layout.n_algs);
    for _ in 0..points {
        let p = Point {
            params: inst.params.clone(),
            states: inst
                .states
                .iter()
                .map(|x| x + rng.uniform(-0.05, 0.05))
                .collect(),
            algs: inst.algs.iter().map(|_| rng.uniform(-2.0, 2.0)).collect(),
            zdot: inst.algs.iter().map(|_| rng.uniform(-3.0, 3.0)).collect(),
            mu: (0..inst.layout.n_rows)
                .map(|_| rng.uniform(0.01, 0.2))
                .collect(),
            inputs: inst
                .inputs
                .iter()
                .map(|x| x + rng.uniform(-0.05, 0.05))
                .collect(),
            t: rng.uniform(0.0, 2.0),
        };
        let fam = eval_family(&c, &inst, &p);
        let mut params = p.params.clone();
        params.extend(&p.inputs);
        params.push(p.t);
        let sca = eval_scalar(&c1, &params, &p);
        let tol = 1e-12;
        assert_close("rhs", &fam.rhs, &sca.rhs, tol);
        assert_close("w", &fam.w, &sca.w, tol);
        assert_close("s", &fam.s, &sca.s, tol);
        assert_close("alpha_hat", &fam.alpha_hat, &sca.alpha_hat, tol);
        assert_close("J_Omega", &fam.jacobian, &sca.jacobian, tol);
        assert_close("beta", &fam.beta, &sca.beta, tol);
        assert_close("Omega'", &fam.rate, &sca.rate, tol);
        // The points exercise the functions: the tensions act, J_Omega is not zero.
        assert!(fam.jacobian.iter().any(|v| *v != 0.0));
        assert!(fam.beta.iter().any(|v| *v != 0.0));
        // ... and `zdot` moves `Omega'` away from `beta`.
        assert!(
            fam.rate
                .iter()
                .zip(&fam.beta)
                .any(|(r, b)| !close(*r, *b, 1e-6))
        );
    }
}

fn example(name: &str) -> String {
    std::fs::read_to_string(models_dir().join(name)).expect("example model")
}

#[test]
fn chain_templates_agree_with_the_expanded_chain() {
    let src = example("chain.dae");
    for n in 1..=6 {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            ..Spec::default()
        };
        compare(&src, &spec, 17 + n as u64, 3);
    }
}

#[test]
fn cloth_templates_agree_with_the_expanded_cloth() {
    // From W = 3: at W = 2 the two pinned corners are the whole far edge, and the link
    // between them has a zero row in J_Omega (the expanded model's analysis rejects it).
    let src = example("cloth.dae");
    for w in 3..=6 {
        for k_shear in [0.0, 40.0] {
            let spec = Spec {
                sizes: vec![("W".into(), w)],
                params: vec![("k_shear".into(), k_shear)],
                ..Spec::default()
            };
            compare(&src, &spec, 100 + w as u64, 2);
        }
    }
}

#[test]
fn hair_templates_agree_with_the_expanded_hair() {
    // A forest of strands whose roots follow a scalar input (the head).
    let src = example("hair.dae");
    for n in 1..=6 {
        let spec = Spec {
            sizes: vec![("S".into(), 3), ("N".into(), n)],
            ..Spec::default()
        };
        compare(&src, &spec, 200 + n as u64, 2);
    }
}

#[test]
fn given_sets_and_maps_agree_with_the_expansion() {
    // A star of links around a centre particle, its edges given by the caller: the
    // incidence sums meet on the centre (four links at one particle).
    let src = "
        model Star {
            set P;
            set L;
            map a[l in L] -> P;
            map b[l in L] -> P;
            param g = 9.81, L0 = 1.0, mass = 0.2;
            param free[p in P] = if p == 0 then 0 else 1;
            input pin: vec3 with 3 derivatives = vec3(0, 0, 0);
            state x[p in P]: vec3 = vec3(if p == 0 then 0 else if p == 1 then 1 else 0,
                                         if p == 2 then 1 else if p == 3 then -1 else 0,
                                         if p == 4 then -1 else 0);
            state v[p in P]: vec3 = vec3(0, 0, 0);
            alg z[l in L] = 0;
            let X[p in P] = free[p] * x[p] + (1 - free[p]) * pin;
            let d[l in L] = X[b[l]] - X[a[l]];
            der(x[p]) = v[p];
            der(v[p]) = free[p] * ((sum(l in L where a[l] == p) z[l] * d[l] / norm(d[l])
                                  - sum(l in L where b[l] == p) z[l] * d[l] / norm(d[l])) / mass
                                  + vec3(0, 0, -g));
            constraint link[l in L]: dot(d[l], d[l]) = L0^2;
        }";
    let spec = Spec {
        sets: vec![("P".into(), 5), ("L".into(), 4)],
        maps: vec![
            ("a".into(), vec![0, 0, 0, 0]),
            ("b".into(), vec![1, 2, 3, 4]),
        ],
        ..Spec::default()
    };
    compare(src, &spec, 7, 4);
}

/// Incidence sums into one codomain share an accumulator where only one linear
/// combination reads them with equal or opposite coefficients (the tension sums of
/// `der(v)`, the `2 z` sums of `der(q)`), and keep their own where another expression
/// reads one of them too (the first sum's `x` component, read again by `der(q)`):
/// either way the programs agree with the expansion.
#[test]
fn sums_into_one_codomain_share_an_accumulator_and_agree_with_the_expansion() {
    let src = "model Sums {
        size N = 3;
        set P = N + 1;
        set L = N;
        map a[l in L] -> P = l;
        map b[l in L] -> P = l + 1;
        param g = 9.81;
        param free[p in P] = if p == 0 then 0 else 1;
        state x[p in P]: vec3 = vec3(p, 0, 0);
        state v[p in P]: vec3 = vec3(0, 0, 0);
        state q[p in P] = 0;
        alg z[l in L] = 0;
        let d[l in L] = x[b[l]] - x[a[l]];
        let u[l in L] = d[l] / norm(d[l]);
        let up[p in P] = sum(l in L where a[l] == p) z[l] * u[l];
        der(x[p]) = v[p];
        der(v[p]) = free[p] * (up[p] - sum(l in L where b[l] == p) z[l] * u[l] + vec3(0, 0, -g));
        der(q[p]) = up[p].x + 2 * sum(l in L where a[l] == p) z[l]
            + 2 * sum(l in L where b[l] == p) z[l];
        constraint link[l in L]: norm(d[l]) = 1;
    }";
    let (_, c) = family(src);
    let rhs = &c.programs.rhs;
    let sinks = || rhs.groups.iter().flat_map(|g| &g.sinks);
    let count = |f: fn(&Sink) -> bool| sinks().filter(|s| f(s)).count();
    // Eight sums: the x components of the tension sums stay apart (the first is read
    // twice), the y and z components merge (the second subtracted from the first's
    // array), and so do the two `z` sums (added): 5 accumulators for 8 sums.
    assert_eq!(count(|s| matches!(s, Sink::ScatterSub(..))), 2);
    assert_eq!(count(|s| matches!(s, Sink::ScatterAdd(..))), 6);
    assert_eq!(rhs.arrays.iter().filter(|a| a.accumulate).count(), 5);
    for n in 1..=5 {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            ..Spec::default()
        };
        compare(src, &spec, 300 + n as u64, 3);
    }
}

/// A 2 x 2 mass matrix per element: the templates eliminate it once, the expansion
/// gives one matrix per particle to the version-1 pipeline.
#[test]
fn per_element_mass_matrices_agree_with_the_expansion() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/models/beads_mass.dae");
    let src = std::fs::read_to_string(path).expect("the model");
    for n in 1..=4 {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            ..Spec::default()
        };
        compare(&src, &spec, 61 + n as u64, 3);
    }
}

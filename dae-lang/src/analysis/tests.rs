//! Index analysis tests on models built in code, checked against hand derivations,
//! closed forms (docs/method.md section 7) and finite differences of s along the realized flow.

use super::fixtures::*;
use super::*;
use crate::analyze;
use crate::sym::Point;

fn opts() -> AnalysisOptions {
    AnalysisOptions::default()
}

/// A tiny deterministic generator (xorshift) for random points without extra state.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

struct Values {
    params: Vec<f64>,
    states: Vec<f64>,
    algs: Vec<f64>,
    t: f64,
    mu: Vec<f64>,
}

impl Values {
    fn point(&self) -> Point<'_> {
        Point {
            params: &self.params,
            states: &self.states,
            algs: &self.algs,
            t: self.t,
            mu: &self.mu,
        }
    }
}

fn eval(a: &Analysis, id: crate::sym::Id, v: &Values) -> f64 {
    a.symbolic.arena.eval(id, &v.point())
}

/// The oracle test of the realization: along the extended flow `x' = f, z' = v, t' = 1`,
/// a central difference of `s_i` must equal `mu_i^(r_i-1) (J_Omega v)_i + alpha_i`
/// (docs/method.md section 2, (T 2.6)), and `alpha_hat_i = alpha_i - mu_i^(r_i-1) beta_i`.
fn check_sliding_dynamics(a: &Analysis, model: &crate::model::Model, rng: &mut Rng, spread: f64) {
    let m = a.constraints.len();
    let base = Values {
        params: model.params.iter().map(|p| p.default).collect(),
        states: a
            .initial
            .states
            .iter()
            .map(|x| x + rng.uniform(-spread, spread))
            .collect(),
        algs: (0..model.algs.len())
            .map(|_| rng.uniform(-2.0, 2.0))
            .collect(),
        t: rng.uniform(0.0, 1.0),
        mu: (0..m).map(|_| rng.uniform(0.1, 1.0)).collect(),
    };
    let v: Vec<f64> = (0..model.algs.len())
        .map(|_| rng.uniform(-1.0, 1.0))
        .collect();
    let fval: Vec<f64> = a.symbolic.f.iter().map(|&f| eval(a, f, &base)).collect();
    let moved = |h: f64| Values {
        params: base.params.clone(),
        states: base
            .states
            .iter()
            .zip(&fval)
            .map(|(x, f)| x + h * f)
            .collect(),
        algs: base.algs.iter().zip(&v).map(|(z, vz)| z + h * vz).collect(),
        t: base.t + h,
        mu: base.mu.clone(),
    };
    let h = 1e-5;
    let (plus, minus) = (moved(h), moved(-h));
    for (i, (c, e)) in a
        .constraints
        .iter()
        .zip(&a.symbolic.constraints)
        .enumerate()
    {
        let fd = (eval(a, e.s, &plus) - eval(a, e.s, &minus)) / (2.0 * h);
        let mur = base.mu[i].powi(c.index as i32 - 1);
        let jv: f64 = e
            .jacobian_row
            .iter()
            .map(|&(k, id)| eval(a, id, &base) * v[k.index()])
            .sum();
        let want = mur * jv + eval(a, e.alpha, &base);
        assert!(
            (fd - want).abs() <= 1e-5 * (1.0 + want.abs()),
            "{}: s' by differences {fd}, J_s v + alpha = {want}",
            c.name
        );
        let hat = eval(a, e.alpha, &base) - mur * eval(a, e.beta, &base);
        let got = eval(a, e.alpha_hat, &base);
        assert!(
            (got - hat).abs() <= 1e-9 * (1.0 + hat.abs()),
            "{}: alpha_hat {got} vs {hat}",
            c.name
        );
    }
}

/// x1' = x2, ..., x_r' = z, 0 = x1 - sin t: index r + 1... built for r states.
fn chain_of_integrators(r: usize) -> crate::model::Model {
    let mut b = ModelBuilder::new("Integrators");
    let xs: Vec<E> = (1..=r).map(|k| b.state(&format!("x{k}"), 0.0)).collect();
    let z = b.alg("z", 0.0);
    for k in 0..r {
        let rhs = if k + 1 < r {
            xs[k + 1].clone()
        } else {
            z.clone()
        };
        b.der(&xs[k], rhs);
    }
    b.constraint("c", xs[0].clone(), E::t().sin());
    b.build()
}

#[test]
fn index_one() {
    let mut b = ModelBuilder::new("Index1");
    let x = b.state("x", 1.0);
    let z = b.alg("z", 0.5);
    b.der(&x, -x.clone() + z.clone());
    b.constraint("c", z, x.clone() * x);
    let model = b.build();
    let a = analyze(&model, &opts()).unwrap();
    let c = &a.constraints[0];
    let e = &a.symbolic.constraints[0];
    assert_eq!((c.index, e.w.len(), e.omega), (1, 1, e.w[0]));
    assert_eq!(c.depends_on, vec!["z".to_string()]);
    // J = 1; beta = D[z - x^2] = -2 x (-x + z)
    let v = Values {
        params: vec![],
        states: vec![0.7],
        algs: vec![-0.3],
        t: 0.0,
        mu: vec![0.2],
    };
    assert_eq!(e.jacobian_row.len(), 1);
    assert_eq!(eval(&a, e.jacobian_row[0].1, &v), 1.0);
    let beta = -2.0 * 0.7 * (-0.7 - 0.3);
    assert!((eval(&a, e.beta, &v) - beta).abs() < 1e-14);
    // r = 1: s = w, alpha = beta, alpha_hat = 0.
    assert_eq!(e.s, e.w[0]);
    assert_eq!(e.alpha, e.beta);
    assert_eq!(a.symbolic.arena.as_const(e.alpha_hat), Some(0.0));
    check_sliding_dynamics(&a, &model, &mut Rng(7), 1.0);
}

#[test]
fn index_two_time_dependent() {
    let model = chain_of_integrators(1);
    let a = analyze(&model, &opts()).unwrap();
    let c = &a.constraints[0];
    let e = &a.symbolic.constraints[0];
    assert_eq!(c.index, 2);
    // w' = z - cos t, beta = D[z - cos t] = sin t: depends on time only.
    let v = Values {
        params: vec![],
        states: vec![0.3],
        algs: vec![1.5],
        t: 0.8,
        mu: vec![0.3],
    };
    assert!((eval(&a, e.w[1], &v) - (1.5 - 0.8f64.cos())).abs() < 1e-15);
    assert!((eval(&a, e.beta, &v) - 0.8f64.sin()).abs() < 1e-15);
    // s = mu w' + w; alpha = mu beta + w'
    let s = 0.3 * (1.5 - 0.8f64.cos()) + (0.3 - 0.8f64.sin());
    assert!((eval(&a, e.s, &v) - s).abs() < 1e-15);
    let alpha = 0.3 * 0.8f64.sin() + (1.5 - 0.8f64.cos());
    assert!((eval(&a, e.alpha, &v) - alpha).abs() < 1e-15);
    check_sliding_dynamics(&a, &model, &mut Rng(11), 1.0);
}

#[test]
fn index_three_and_four() {
    for (states, r) in [(2, 3), (3, 4)] {
        let model = chain_of_integrators(states);
        let a = analyze(&model, &opts()).unwrap();
        let c = &a.constraints[0];
        let e = &a.symbolic.constraints[0];
        assert_eq!(c.index, r);
        assert_eq!(a.indices(), vec![r]);
        assert_eq!(c.depends_on, vec!["z".to_string()]);
        let v = Values {
            params: vec![],
            states: vec![0.1, 0.2, 0.3],
            algs: vec![0.4],
            t: 0.5,
            mu: vec![0.25],
        };
        // w^(r-1) = z - d^(r-1) sin t; beta = -d^r sin t.
        let dsin = |n: usize, t: f64| [t.sin(), t.cos(), -t.sin(), -t.cos()][n % 4];
        assert!((eval(&a, e.omega, &v) - (0.4 - dsin(r - 1, 0.5))).abs() < 1e-15);
        assert!((eval(&a, e.beta, &v) + dsin(r, 0.5)).abs() < 1e-15);
        // s = sum C(r-1, j) mu^j w^(j) with w^(j) = x_{j+1} - sin^(j) t below Omega.
        let w: Vec<f64> = (0..r)
            .map(|j| if j + 1 < r { v.states[j] } else { 0.4 } - dsin(j, 0.5))
            .collect();
        let s: f64 = (0..r)
            .map(|j| binomial(r - 1, j) * 0.25f64.powi(j as i32) * w[j])
            .sum();
        assert!((eval(&a, e.s, &v) - s).abs() < 1e-14, "s for index {r}");
        check_sliding_dynamics(&a, &model, &mut Rng(13 + r as u64), 1.0);
    }
}

#[test]
fn mixed_indices_in_one_model() {
    let mut b = ModelBuilder::new("Mixed");
    let p = b.state("p", 0.0);
    let q = b.state("q", 0.0);
    let u = b.state("u", 0.0);
    let z1 = b.alg("z1", 0.0);
    let z2 = b.alg("z2", 0.0);
    let z3 = b.alg("z3", 0.0);
    b.der(&p, q.clone());
    b.der(&q, z1.clone() + 0.5 * z2.clone());
    b.der(&u, z2.clone());
    b.constraint("three", p.clone(), E::t() * E::t());
    b.constraint("two", u.clone(), E::t().cos());
    b.constraint("one", z3.clone() + z1.clone(), p.clone() * u.clone());
    let model = b.build();
    let a = analyze(&model, &opts()).unwrap();
    assert_eq!(a.indices(), vec![3, 2, 1]);
    assert_eq!(a.constraints[0].depends_on, vec!["z1", "z2"]);
    assert_eq!(a.constraints[1].depends_on, vec!["z2"]);
    assert_eq!(a.constraints[2].depends_on, vec!["z1", "z3"]);
    // J_Omega = [[1, 0.5, 0], [0, 1, 0], [1, 0, 1]]
    assert_eq!(
        a.jacobian_at_initial,
        vec![1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]
    );
    check_sliding_dynamics(&a, &model, &mut Rng(17), 1.0);
}

#[test]
fn no_index_is_an_error_naming_the_constraint_and_its_variables() {
    let mut b = ModelBuilder::new("NoIndex");
    let x = b.state("x", 1.0);
    let y = b.state("y", 0.0);
    let _z = b.alg("z", 0.0);
    b.der(&x, y.clone());
    b.der(&y, -x.clone());
    b.constraint("free", y.clone() + x.clone(), 1.0);
    let model = b.build();
    let errs = analyze(&model, &opts()).unwrap_err();
    assert_eq!(errs.len(), 1);
    let d = &errs[0];
    assert_eq!(d.span, model.constraints[0].span);
    assert!(d.message.contains("`free` has no index"), "{}", d.message);
    assert!(
        d.message.contains("after 8 time derivatives"),
        "{}",
        d.message
    );
    assert!(
        d.label.contains('x') && d.label.contains('y'),
        "{}",
        d.label
    );
    assert!(d.hint.is_some());

    // A constant constraint is caught before differentiating.
    let mut b = ModelBuilder::new("Constant");
    let x = b.state("x", 1.0);
    let z = b.alg("z", 0.0);
    let p = b.param("p", 2.0);
    b.der(&x, z);
    b.constraint("k", p, 1.0);
    let errs = analyze(&b.build(), &opts()).unwrap_err();
    assert!(
        errs[0].message.contains("does not depend on any state"),
        "{}",
        errs[0].message
    );
    assert!(errs[0].label.contains('p'));
}

#[test]
fn the_maximum_number_of_differentiations_is_configurable() {
    let model = chain_of_integrators(3); // index 4
    let few = AnalysisOptions {
        max_differentiations: 2,
        ..opts()
    };
    let errs = analyze(&model, &few).unwrap_err();
    assert!(
        errs[0].message.contains("after 2 time derivatives"),
        "{}",
        errs[0].message
    );
    let enough = AnalysisOptions {
        max_differentiations: 3,
        ..opts()
    };
    assert_eq!(analyze(&model, &enough).unwrap().indices(), vec![4]);
}

/// x1' = x2, x2' = z1 + z2, x3' = x4, x4' = z1 + (1 + eps) z2, constraints x1 = 0, x3 = 0:
/// J_Omega = [[1, 1], [1, 1 + eps]].
fn nearly_dependent(eps: f64) -> crate::model::Model {
    let mut b = ModelBuilder::new("Dependent");
    let xs: Vec<E> = (1..=4).map(|k| b.state(&format!("x{k}"), 0.0)).collect();
    let z1 = b.alg("z1", 0.0);
    let z2 = b.alg("z2", 0.0);
    b.der(&xs[0], xs[1].clone());
    b.der(&xs[1], z1.clone() + z2.clone());
    b.der(&xs[2], xs[3].clone());
    b.der(&xs[3], z1 + (1.0 + eps) * z2);
    b.constraint("first", xs[0].clone(), 0.0);
    b.constraint("second", xs[2].clone(), 0.0);
    b.build()
}

#[test]
fn singular_jacobian_is_an_error_naming_both_constraints() {
    let model = nearly_dependent(0.0);
    let errs = analyze(&model, &opts()).unwrap_err();
    assert_eq!(errs.len(), 1);
    let d = &errs[0];
    assert!(d.message.contains("singular"), "{}", d.message);
    assert!(
        d.message.contains("`first`") && d.message.contains("`second`"),
        "{}",
        d.message
    );
    assert_eq!(d.span, model.constraints[0].span);
    assert_eq!(d.related.len(), 1);
    assert_eq!(d.related[0].0, model.constraints[1].span);
}

#[test]
fn ill_conditioned_jacobian_reports_its_condition_number() {
    // cond([[1, 1], [1, 1 + e]]) ~ 4 / e for small e.
    let model = nearly_dependent(1e-13);
    let errs = analyze(&model, &opts()).unwrap_err();
    assert!(
        errs[0].message.contains("ill-conditioned"),
        "{}",
        errs[0].message
    );
    assert!(errs[0].message.contains("e13"), "{}", errs[0].message);
    let lenient = AnalysisOptions {
        condition_threshold: 1e15,
        ..opts()
    };
    let a = analyze(&model, &lenient).unwrap();
    assert!(
        (a.condition_number / 4e13 - 1.0).abs() < 0.01,
        "{}",
        a.condition_number
    );
}

#[test]
fn non_finite_values_at_the_initial_point_are_errors() {
    let mut b = ModelBuilder::new("Bad");
    let x = b.state("x", -1.0);
    let y = b.state("y", 0.0);
    let z = b.alg("z", 0.0);
    b.der(&x, z.clone());
    b.der(&y, 1.0 / y.clone());
    b.constraint("root", x.sqrt(), 1.0);
    let model = b.build();
    let errs = analyze(&model, &opts()).unwrap_err();
    assert_eq!(errs.len(), 2, "{errs:?}");
    assert!(
        errs[0].message.starts_with("der(y) is inf"),
        "{}",
        errs[0].message
    );
    assert_eq!(errs[0].span, model.ders[1].span);
    assert!(
        errs[1].message.starts_with("w_root is NaN"),
        "{}",
        errs[1].message
    );
    assert_eq!(errs[1].span, model.constraints[0].span);
}

/// The 3-D double pendulum's J_Omega against docs/method.md section 7 at random configurations:
/// J11 = -1/m1 (link 1 pinned), J22 = -(1/m1 + 1/m2), J12 = J21 = -(rhat_10 . rhat_12)/m1.
#[test]
fn double_pendulum_jacobian_matches_the_closed_form() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let (m1, m2) = (0.1, 0.1);
    for _ in 0..20 {
        let r1: [f64; 3] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let r2: [f64; 3] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let model = double_pendulum_3d_at(r1, r2);
        let a = analyze(&model, &opts()).unwrap();
        assert_eq!(a.indices(), vec![3, 3]);
        let n1 = (r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2]).sqrt();
        let d: Vec<f64> = (0..3).map(|k| r2[k] - r1[k]).collect();
        let n2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let r10: Vec<f64> = r1.iter().map(|x| -x / n1).collect();
        let r12: Vec<f64> = d.iter().map(|x| x / n2).collect();
        let dot: f64 = (0..3).map(|k| r10[k] * r12[k]).sum();
        let want = [-1.0 / m1, -dot / m1, -dot / m1, -(1.0 / m1 + 1.0 / m2)];
        for (got, want) in a.jacobian_at_initial.iter().zip(want) {
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{:?} vs {want}",
                a.jacobian_at_initial
            );
        }
        check_sliding_dynamics(&a, &model, &mut rng, 0.3);
    }
}

/// The initial point is checked on the compiled form, the code that runs: the initial
/// values are the model's formulas over the parameters (as the checker's evaluator of
/// constant expressions computes them, not the construction's) and `J_Omega` what the
/// jacobian program (run by the interpreter, printed by the code generator) computes,
/// bit for bit (dense `J_Omega` of the pendulum, sparse one of a 10-link chain).
#[test]
fn the_initial_point_is_what_the_compiled_form_computes() {
    use crate::check::eval::eval;
    use crate::family::{Scratch, Spec, Values, construct};
    let formula = |e: &crate::model::RExpr, params: &[f64]| {
        let params: Vec<Option<f64>> = params.iter().copied().map(Some).collect();
        eval(e, &params).expect("an initial value over the parameters")
    };
    for model in [double_pendulum_3d(), planar_chain(10)] {
        let a = analyze(&model, &opts()).unwrap();
        let c = crate::compile(&a);
        let m = a.constraints.len();
        let p = &a.initial;
        let states: Vec<f64> = model
            .states
            .iter()
            .map(|s| formula(&s.init, &p.params))
            .collect();
        let algs: Vec<f64> = model
            .algs
            .iter()
            .map(|z| formula(&z.init, &p.params))
            .collect();
        assert_eq!(states, p.states, "{}", model.name);
        assert_eq!(algs, p.algs, "{}", model.name);
        let inst = construct(&c.programs.construction, &Spec::default()).unwrap();
        let at = Values {
            params: &p.params,
            states: &p.states,
            algs: &p.algs,
            alg_rates: &[],
            mu: &vec![f64::NAN; m],
            inputs: &[],
            t: 0.0,
        };
        let jac = &c.programs.jacobian;
        let mut values = vec![0.0; inst.jacobian.entries.len()];
        jac.eval(
            &inst,
            &at,
            &mut Scratch::new(jac, &inst),
            &mut [&mut values],
        );
        let mut dense = vec![0.0; m * m];
        for (&(i, k), v) in inst.jacobian.entries.iter().zip(values) {
            dense[i * m + k] = v;
        }
        assert_eq!(dense, a.jacobian_at_initial, "{}", model.name);
    }
}

/// A hand-built model may break the checked-model contract (a variable that does not
/// exist, a realization parameter in an equation, an initial value that reads a state):
/// the reference lowers to NaN and is reported at the initial point, never read outside
/// the tapes' inputs; an initial value that reads a variable is refused by the
/// construction.
#[test]
fn references_outside_the_model_are_reported_not_read() {
    use crate::model::RExpr;
    use crate::{ConstraintId, ParamId, VarRef};
    let mut b = ModelBuilder::new("Outside");
    let x = b.state("x", 1.0);
    let z = b.alg("z", 0.0);
    b.der(&x, z.clone());
    b.constraint("c", x.clone(), 1.0);
    let good = b.build();
    // der(x) = z + <the reference>, so that the constraint keeps its index.
    let der_reads = |v: VarRef| {
        let mut m = good.clone();
        m.ders[0].expr = (z.clone() + E(RExpr::Var(v))).0;
        m
    };
    let cases = [
        ("der(x) is NaN", der_reads(VarRef::Param(ParamId::new(3)))),
        ("der(x) is NaN", der_reads(VarRef::Mu(ConstraintId::new(0)))),
        // An initial value is the construction's, which names the breach.
        (
            "internal error: a construction-time expression reads a variable",
            {
                let mut m = good.clone();
                m.states[0].init = x.0.clone();
                m
            },
        ),
    ];
    for (what, model) in cases {
        let errs = analyze(&model, &opts()).unwrap_err();
        assert!(
            errs.iter().any(|e| e.message.starts_with(what)),
            "{what}: {errs:?}"
        );
    }
    assert!(analyze(&good, &opts()).is_ok());
}

#[test]
fn double_pendulum_at_the_thesis_initial_state() {
    let model = double_pendulum_3d();
    let a = analyze(&model, &opts()).unwrap();
    assert_eq!(a.indices(), vec![3, 3]);
    for c in &a.constraints {
        assert_eq!(c.depends_on, vec!["z1", "z2"]);
    }
    // R1 = (-1,0,0), R2 = (-5,0,0): rhat_10 . rhat_12 = (1,0,0).(-1,0,0) = -1 -> J12 = 10.
    assert_eq!(a.jacobian_at_initial, vec![-10.0, 10.0, 10.0, -20.0]);
    // cond of [[-10, 10], [10, -20]]: eigenvalues -15 -+ 5 sqrt(5).
    let e = 5.0 * 5f64.sqrt();
    assert!((a.condition_number - (15.0 + e) / (15.0 - e)).abs() < 1e-12);
    // s(0) = w(0) at rest: -1 and 2 (docs/method.md section 8).
    let v = Values {
        params: a.initial.params.clone(),
        states: a.initial.states.clone(),
        algs: vec![0.0, 0.0],
        t: 0.0,
        mu: vec![0.065, 0.06],
    };
    assert!((eval(&a, a.symbolic.constraints[0].s, &v) + 1.0).abs() < 1e-15);
    assert!((eval(&a, a.symbolic.constraints[1].s, &v) - 2.0).abs() < 1e-15);
}

#[test]
fn planar_chain_jacobian_is_tridiagonal_with_the_closed_form_entries() {
    let n = 12;
    let model = planar_chain(n);
    let a = analyze(&model, &opts()).unwrap();
    assert_eq!(a.indices(), vec![3; n]);
    for (i, c) in a.symbolic.constraints.iter().enumerate() {
        let cols: Vec<usize> = c.jacobian_row.iter().map(|(k, _)| k.index()).collect();
        let want: Vec<usize> = (i.saturating_sub(1)..(i + 2).min(n)).collect();
        assert_eq!(cols, want, "row {i}");
    }
    // Straight chain: neighbouring links point opposite ways at their shared particle, so
    // the off-diagonal is -(-1)/m = 10; diagonal -1/m pinned, -2/m otherwise.
    for i in 0..n {
        for k in 0..n {
            let want = match (i, k) {
                (0, 0) => -10.0,
                _ if i == k => -20.0,
                _ if i.abs_diff(k) == 1 => 10.0,
                _ => 0.0,
            };
            assert!(
                (a.jacobian_at_initial[i * n + k] - want).abs() < 1e-12,
                "J({i}, {k})"
            );
        }
    }
    check_sliding_dynamics(&a, &model, &mut Rng(23), 0.2);
}

#[test]
fn derive_text_has_one_line_per_equation() {
    let a = analyze(&chain_of_integrators(2), &opts()).unwrap();
    let text = a.derive_text();
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
        .collect();
    let heads: Vec<&str> = lines
        .iter()
        .map(|l| l.split(" = ").next().unwrap())
        .collect();
    assert_eq!(
        heads,
        [
            "w_c",
            "w_c'",
            "Omega_c",
            "J(0, 0)",
            "beta_c",
            "s_c",
            "alpha_c",
            "alpha_hat_c"
        ]
    );
    assert_eq!(lines[0], "w_c = x1 - sin(t)");
    assert_eq!(lines[1], "w_c' = x2 - cos(t)");
    assert_eq!(lines[2], "Omega_c = z + sin(t)");
    assert_eq!(lines[3], "J(0, 0) = 1  // c / z");
    assert_eq!(lines[4], "beta_c = cos(t)");
    assert!(
        text.starts_with("// model Integrators: 1 constraint, indices (3)"),
        "{text}"
    );
}

/// Operation counts (shared, tree) of w'', J_Omega and beta of the 3-D double pendulum, with
/// and without simplification. Run with `--nocapture` to see the table.
#[test]
fn simplification_reduces_the_double_pendulum_operation_counts() {
    let model = double_pendulum_3d();
    let mut rows = Vec::new();
    for simplify in [false, true] {
        let a = analyze(&model, &AnalysisOptions { simplify, ..opts() }).unwrap();
        let sym = a.symbolic();
        let omega: Vec<_> = sym.constraints.iter().map(|c| c.omega).collect();
        let jac: Vec<_> = sym
            .constraints
            .iter()
            .flat_map(|c| c.jacobian_row.iter().map(|e| e.1))
            .collect();
        let beta: Vec<_> = sym.constraints.iter().map(|c| c.beta).collect();
        let count =
            |ids: &[crate::sym::Id]| (sym.arena.op_count(ids), sym.arena.tree_op_count(ids));
        rows.push((
            simplify,
            count(&omega),
            count(&jac),
            count(&beta),
            sym.arena.len(),
        ));
        // Both builds mean the same thing at the initial point.
        assert_eq!(a.jacobian_at_initial, vec![-10.0, 10.0, 10.0, -20.0]);
    }
    println!(
        "simplify | w'' (shared, tree) | J_Omega (shared, tree) | beta (shared, tree) | arena nodes"
    );
    for r in &rows {
        println!("{:>8} | {:?} | {:?} | {:?} | {}", r.0, r.1, r.2, r.3, r.4);
    }
    let (raw, simp) = (&rows[0], &rows[1]);
    assert!(simp.1.0 < raw.1.0 && simp.2.0 < raw.2.0 && simp.3.0 < raw.3.0);
    assert!(simp.1.1 < raw.1.1 && simp.2.1 < raw.2.1 && simp.3.1 < raw.3.1);
}

#[test]
fn derive_text_writes_lets_by_name() {
    let a = analyze(&double_pendulum_3d(), &opts()).unwrap();
    let text = a.derive_text();
    assert!(
        text.contains("\nlet l1 = sqrt(rx1^2 + ry1^2 + rz1^2)\n"),
        "{text}"
    );
    assert!(text.contains("\nlet dx = rx2 - rx1\n"), "{text}");
    assert!(
        text.contains("\nlet l2 = sqrt(dx^2 + dy^2 + dz^2)\n"),
        "{text}"
    );
    assert!(text.contains("\nw_link1 = l1 - L1\n"), "{text}");
    assert!(text.contains("\nw_link2 = l2 - L2\n"), "{text}");
}

#[test]
fn a_model_without_constraints_analyses_to_nothing() {
    let mut b = ModelBuilder::new("Decay");
    let x = b.state("x", 1.0);
    b.der(&x, -x.clone());
    let a = analyze(&b.build(), &opts()).unwrap();
    assert!(a.constraints.is_empty());
    assert_eq!(a.condition_number, 1.0);
    assert_eq!(a.initial.states, vec![1.0]);
}

/// Every right-hand side of the derive text reads back (language precedence, the model's
/// names and lets, `mu<i>`) to exactly the node it was printed from.
#[test]
fn derive_text_reads_back_to_the_same_expressions() {
    use std::collections::HashMap;
    for model in [
        double_pendulum_3d(),
        planar_chain(4),
        chain_of_integrators(3),
    ] {
        let a = analyze(&model, &opts()).unwrap();
        let sym = a.symbolic();
        let mut arena = sym.arena.clone();
        let mut table: HashMap<String, crate::sym::Id> = HashMap::new();
        for (i, p) in model.params.iter().enumerate() {
            table.insert(p.name.clone(), arena.param(crate::ParamId::new(i)));
        }
        for (i, s) in model.states.iter().enumerate() {
            table.insert(s.name.clone(), arena.state(crate::StateId::new(i)));
        }
        for (i, z) in model.algs.iter().enumerate() {
            table.insert(z.name.clone(), arena.alg(crate::AlgId::new(i)));
        }
        for (name, &id) in sym.let_names.iter().zip(&sym.lets) {
            table.insert(name.clone(), id);
        }
        for i in 0..a.constraints.len() {
            table.insert(
                format!("mu{}", i + 1),
                arena.mu(crate::ConstraintId::new(i)),
            );
        }
        table.insert("t".into(), arena.time());
        let mut expected: Vec<crate::sym::Id> = sym.lets.clone();
        for c in &sym.constraints {
            expected.extend(&c.w);
            expected.extend(c.jacobian_row.iter().map(|e| e.1));
            expected.extend([c.beta, c.s, c.alpha, c.alpha_hat]);
        }
        let text = a.derive_text();
        let rhs: Vec<&str> = text
            .lines()
            .filter(|l| !l.is_empty() && !l.starts_with("//"))
            .map(|l| l.split_once(" = ").expect("an equation").1)
            .map(|r| r.split_once("  //").map_or(r, |(e, _)| e))
            .collect();
        assert_eq!(rhs.len(), expected.len());
        for (text, want) in rhs.into_iter().zip(expected) {
            let got = crate::sym::reader::read(&mut arena, &table, text);
            assert_eq!(
                got, want,
                "{} reads back as something else: {text}",
                model.name
            );
        }
    }
}

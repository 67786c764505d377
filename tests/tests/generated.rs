//! The Rust code generated for every example model (compiled here through
//! `dae_runtime::dae_file!`) against two oracles:
//! * the interpreter (`dae_runtime::family::Interpreted`), which runs the model's programs
//!   (scheduled apart from the tapes the code is printed from, `beta` from the rate
//!   program) without generating code: every output of every `Model` function must
//!   agree to 1e-12 relative, also after parameter changes (the initial values too);
//! * finite differences, which know nothing of the symbolic pipeline: `J_Omega` is the
//!   derivative of `Omega` (the last w-derivative of each constraint) in `z`, and `beta`
//!   the derivative of `Omega` along `(t + d, x + d f)` with `z` fixed.

use dae_runtime::{Model, model::w_offsets};
use dae_tests::{Rng, close, scalar_example_sources};

mod generated {
    dae_runtime::dae_file!("../examples/models/andrews.dae");
    dae_runtime::dae_file!("../examples/models/car_axis.dae");
    dae_runtime::dae_file!("../examples/models/cart_pendulum.dae");
    dae_runtime::dae_file!("../examples/models/chain3_planar.dae");
    dae_runtime::dae_file!("../examples/models/chain5_planar.dae");
    dae_runtime::dae_file!("../examples/models/circuit_index1.dae");
    dae_runtime::dae_file!("../examples/models/double_pendulum_3d.dae");
    dae_runtime::dae_file!("../examples/models/double_pendulum_planar.dae");
    dae_runtime::dae_file!("../examples/models/integrator_chain_index4.dae");
    dae_runtime::dae_file!("../examples/models/slider_crank.dae");
    dae_runtime::dae_file!("../examples/models/tank_level_index2.dae");
}

/// The generated type of each example file, by file stem.
fn generated(stem: &str) -> Box<dyn Model> {
    match stem {
        "andrews" => Box::new(generated::Andrews::default()),
        "car_axis" => Box::new(generated::CarAxis::default()),
        "cart_pendulum" => Box::new(generated::CartPendulum::default()),
        "chain3_planar" => Box::new(generated::Chain3::default()),
        "chain5_planar" => Box::new(generated::Chain5::default()),
        "circuit_index1" => Box::new(generated::NonlinearRC::default()),
        "double_pendulum_3d" => Box::new(generated::DoublePendulum3D::default()),
        "double_pendulum_planar" => Box::new(generated::DoublePendulum::default()),
        "integrator_chain_index4" => Box::new(generated::IntegratorChain::default()),
        "slider_crank" => Box::new(generated::SliderCrank::default()),
        "tank_level_index2" => Box::new(generated::TankLevel::default()),
        other => panic!("example `{other}` is not compiled in this test: add it above"),
    }
}

/// Every example: (stem, generated, interpreted).
fn pairs() -> Vec<(String, Box<dyn Model>, dae_runtime::family::Interpreted)> {
    let sources = scalar_example_sources();
    assert_eq!(
        sources.len(),
        11,
        "a new example model: add it to this test"
    );
    sources
        .into_iter()
        .map(|(stem, text)| {
            let mut models =
                daec::interpret_source(&text).unwrap_or_else(|e| panic!("{stem}: {e:?}"));
            assert_eq!(models.len(), 1, "{stem}: one model per example file");
            let code = generated(&stem);
            (stem, code, models.remove(0))
        })
        .collect()
}

/// All outputs of every function of `m` at one point, in a fixed order.
fn evaluate(m: &dyn Model, t: f64, x: &[f64], z: &[f64], mu: &[f64]) -> Vec<f64> {
    let n = m.n_states();
    let k = m.n_constraints();
    let nw: usize = m.indices().iter().sum();
    let mut out = vec![0.0; n + k + n + nw + 2 * k + m.jacobian_pattern().len() + k];
    let (init_x, rest) = out.split_at_mut(n);
    let (init_z, rest) = rest.split_at_mut(k);
    let (dx, rest) = rest.split_at_mut(n);
    let (w, rest) = rest.split_at_mut(nw);
    let (s, rest) = rest.split_at_mut(k);
    let (ah, rest) = rest.split_at_mut(k);
    let (jac, beta) = rest.split_at_mut(m.jacobian_pattern().len());
    m.initial_state(init_x);
    m.initial_alg(init_z);
    m.rhs(t, x, z, dx);
    m.sliding(t, x, z, mu, w, s, ah);
    m.jacobian(t, x, z, jac);
    m.beta(t, x, z, beta);
    out
}

/// A random point near the model's initial point: `(t, x, z, mu)`.
fn random_point(m: &dyn Model, rng: &mut Rng) -> (f64, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; m.n_states()];
    let mut z = vec![0.0; m.n_constraints()];
    m.initial_state(&mut x);
    m.initial_alg(&mut z);
    for v in &mut x {
        *v += rng.uniform(-0.3, 0.3) * (1.0 + v.abs());
    }
    for v in &mut z {
        *v += rng.uniform(-2.0, 2.0) * (1.0 + v.abs());
    }
    let mu = (0..m.n_constraints())
        .map(|_| rng.uniform(0.05, 2.0))
        .collect();
    (rng.uniform(0.0, 5.0), x, z, mu)
}

fn assert_agree(stem: &str, what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            close(*x, *y, 1e-12),
            "{stem} ({what}): output {k}: generated {x:e}, interpreted {y:e}"
        );
    }
}

#[test]
fn generated_code_has_the_interpreters_structure() {
    for (stem, code, int) in pairs() {
        assert_eq!(code.name(), int.name(), "{stem}");
        assert_eq!(code.n_states(), int.n_states(), "{stem}");
        assert_eq!(code.n_constraints(), int.n_constraints(), "{stem}");
        assert_eq!(code.n_params(), int.n_params(), "{stem}");
        assert_eq!(code.indices(), int.indices(), "{stem}");
        assert_eq!(code.jacobian_pattern(), int.jacobian_pattern(), "{stem}");
        for i in 0..code.n_states() {
            assert_eq!(code.state_name(i), int.state_name(i), "{stem}");
        }
        for i in 0..code.n_constraints() {
            assert_eq!(code.alg_name(i), int.alg_name(i), "{stem}");
            assert_eq!(code.constraint_name(i), int.constraint_name(i), "{stem}");
        }
        for i in 0..code.n_params() {
            assert_eq!(code.param_name(i), int.param_name(i), "{stem}");
            assert_eq!(code.param(i), int.param(i), "{stem}");
        }
    }
}

#[test]
fn generated_code_agrees_with_the_interpreter_at_random_points() {
    let mut rng = Rng::new(0x5eed_0001);
    for (stem, code, int) in pairs() {
        for _ in 0..200 {
            let (t, x, z, mu) = random_point(code.as_ref(), &mut rng);
            let a = evaluate(code.as_ref(), t, &x, &z, &mu);
            let b = evaluate(&int, t, &x, &z, &mu);
            assert_agree(&stem, "default parameters", &a, &b);
        }
    }
}

#[test]
fn parameter_changes_are_honoured_by_generated_code_and_interpreter() {
    let mut rng = Rng::new(0x5eed_0002);
    for (stem, mut code, mut int) in pairs() {
        // A fixed point, so that the outputs before and after a change are comparable.
        let (t, x, z, mu) = random_point(code.as_ref(), &mut rng);
        for i in 0..code.n_params() {
            let before = evaluate(code.as_ref(), t, &x, &z, &mu);
            let old = code.param(i);
            let new = if old == 0.0 {
                rng.uniform(0.5, 1.5)
            } else {
                old * rng.uniform(1.1, 1.3)
            };
            code.set_param(i, new);
            int.set_param(i, new);
            assert_eq!(code.param(i), new, "{stem}: param {i} reads back");
            assert_eq!(int.param(i), new, "{stem}: param {i} reads back");
            let after = evaluate(code.as_ref(), t, &x, &z, &mu);
            assert_ne!(
                before,
                after,
                "{stem}: changing `{}` changed no output of the generated code",
                code.param_name(i)
            );
            assert_agree(
                &stem,
                &format!("after changing `{}`", code.param_name(i)),
                &after,
                &evaluate(&int, t, &x, &z, &mu),
            );
            for _ in 0..20 {
                let (t, x, z, mu) = random_point(code.as_ref(), &mut rng);
                assert_agree(
                    &stem,
                    "changed parameters",
                    &evaluate(code.as_ref(), t, &x, &z, &mu),
                    &evaluate(&int, t, &x, &z, &mu),
                );
            }
        }
    }
}

/// `Omega_i`, the last w-derivative of each constraint.
fn omega(m: &dyn Model, t: f64, x: &[f64], z: &[f64]) -> Vec<f64> {
    let k = m.n_constraints();
    let offsets = w_offsets(m.indices());
    let mut w = vec![0.0; offsets[k]];
    let (mut s, mut ah) = (vec![0.0; k], vec![0.0; k]);
    m.sliding(t, x, z, &vec![1.0; k], &mut w, &mut s, &mut ah);
    (0..k).map(|i| w[offsets[i + 1] - 1]).collect()
}

/// The derivative at 0 of `g` (a vector function of one variable) by central
/// differences with step `h` and `h / 2`, combined by Richardson extrapolation
/// (error O(h^4)).
fn derivative(g: impl Fn(f64) -> Vec<f64>, h: f64) -> Vec<f64> {
    let central = |h: f64| -> Vec<f64> {
        let (p, q) = (g(h), g(-h));
        p.iter().zip(&q).map(|(p, q)| (p - q) / (2.0 * h)).collect()
    };
    let (d1, d2) = (central(h), central(h / 2.0));
    d1.iter()
        .zip(&d2)
        .map(|(a, b)| (4.0 * b - a) / 3.0)
        .collect()
}

/// Finite differences agree with the exact value within `1e-6` relative to the size of
/// the quantities involved (`Omega` itself and the derivative).
fn assert_fd(stem: &str, what: &str, exact: f64, fd: f64, scale: f64) {
    let tol = 1e-6 * (1.0 + exact.abs() + scale);
    assert!(
        (exact - fd).abs() <= tol,
        "{stem}: {what}: generated {exact:e}, finite differences {fd:e}"
    );
}

#[test]
fn jacobian_is_the_derivative_of_omega_in_z() {
    let mut rng = Rng::new(0x5eed_0003);
    for (stem, code, _) in pairs() {
        let m = code.as_ref();
        let k = m.n_constraints();
        for _ in 0..50 {
            let (t, x, z, _) = random_point(m, &mut rng);
            let mut values = vec![0.0; m.jacobian_pattern().len()];
            m.jacobian(t, &x, &z, &mut values);
            let mut dense = vec![0.0; k * k];
            for (&(r, c), v) in m.jacobian_pattern().iter().zip(&values) {
                dense[r * k + c] = *v;
            }
            let scale = omega(m, t, &x, &z)
                .iter()
                .fold(0.0, |a: f64, b| a.max(b.abs()));
            for col in 0..k {
                let h = 1e-4 * (1.0 + z[col].abs());
                let fd = derivative(
                    |d| {
                        let mut zd = z.clone();
                        zd[col] += d;
                        omega(m, t, &x, &zd)
                    },
                    h,
                );
                for row in 0..k {
                    assert_fd(
                        &stem,
                        &format!("J_Omega[{row}][{col}]"),
                        dense[row * k + col],
                        fd[row],
                        scale,
                    );
                }
            }
        }
    }
}

#[test]
fn beta_is_the_derivative_of_omega_along_the_flow_with_z_fixed() {
    let mut rng = Rng::new(0x5eed_0004);
    for (stem, code, _) in pairs() {
        let m = code.as_ref();
        for _ in 0..50 {
            let (t, x, z, _) = random_point(m, &mut rng);
            let mut f = vec![0.0; m.n_states()];
            m.rhs(t, &x, &z, &mut f);
            let mut beta = vec![0.0; m.n_constraints()];
            m.beta(t, &x, &z, &mut beta);
            let speed = f.iter().fold(1.0, |a: f64, b| a.max(b.abs()));
            let h = 1e-4 / speed;
            let fd = derivative(
                |d| {
                    let xd: Vec<f64> = x.iter().zip(&f).map(|(x, f)| x + d * f).collect();
                    omega(m, t + d, &xd, &z)
                },
                h,
            );
            let scale = omega(m, t, &x, &z)
                .iter()
                .fold(0.0, |a: f64, b| a.max(b.abs()));
            for (i, (b, d)) in beta.iter().zip(&fd).enumerate() {
                assert_fd(&stem, &format!("beta[{i}]"), *b, *d, scale * speed);
            }
        }
    }
}

/// Both back ends give `Omega'` from the rate program (the simulator then skips
/// `J_Omega` at the steps without an update): it must be `beta + J_Omega z'`, from the
/// generated `J_Omega` and `beta`, in both.
#[test]
fn omega_rate_is_beta_plus_j_omega_zdot() {
    let mut rng = Rng::new(0x5eed_0004);
    for (stem, code, int) in pairs() {
        let k = code.n_constraints();
        let pattern = code.jacobian_pattern().to_vec();
        let (mut from_code, mut from_int) = (vec![0.0; k], vec![0.0; k]);
        for _ in 0..50 {
            let (t, x, z, _) = random_point(code.as_ref(), &mut rng);
            let zdot: Vec<f64> = (0..k).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let mut values = vec![0.0; pattern.len()];
            let mut expected = vec![0.0; k];
            code.jacobian(t, &x, &z, &mut values);
            code.beta(t, &x, &z, &mut expected);
            for (&(r, c), v) in pattern.iter().zip(&values) {
                expected[r] += v * zdot[c];
            }
            assert!(code.omega_rate(t, &x, &z, &zdot, &mut from_code), "{stem}");
            assert!(int.omega_rate(t, &x, &z, &zdot, &mut from_int), "{stem}");
            assert_agree(&stem, "Omega'", &from_code, &from_int);
            for (r, (a, b)) in from_code.iter().zip(&expected).enumerate() {
                let scale = values.iter().fold(b.abs(), |m, v| m.max(v.abs() * 3.0));
                assert!(
                    (a - b).abs() <= 1e-11 * (1.0 + scale),
                    "{stem}: Omega'[{r}] {a:e}, beta + J z' {b:e}"
                );
            }
        }
    }
}

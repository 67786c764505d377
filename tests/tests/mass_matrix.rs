//! A model with a mass matrix against the same model with its accelerations written out
//! by hand: `examples/models/cart_pendulum.dae` (`mass [v, om] = M(th)`) and
//! `tests/models/cart_pendulum_explicit.dae` (Cramer's rule on the same 2 x 2 matrix).
//! Every quantity the runtime evaluates, `f`, `w`, `s`, `alpha_hat`, `J_Omega` and
//! `beta` (the last two through `M^-1`), agrees at random points, interpreted and
//! generated. The same for a family with a 2 x 2 matrix per element
//! (`tests/models/beads_mass.dae` against `beads_explicit.dae`).

use dae_runtime::Model;
use dae_tests::{Rng, close, models_dir};

mod generated {
    dae_runtime::dae_file!("../examples/models/cart_pendulum.dae");
    dae_runtime::dae_file!("models/cart_pendulum_explicit.dae");
}

fn here(file: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models")
        .join(file)
}

fn interpreted(path: std::path::PathBuf) -> dae_runtime::family::Interpreted {
    let text = std::fs::read_to_string(&path).expect("read the model");
    daec::interpret_source(&text)
        .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()))
        .remove(0)
}

/// `f`, `w`, `s`, `alpha_hat`, `J_Omega` and `beta` at one point.
fn evaluate(m: &dyn Model, t: f64, x: &[f64], z: &[f64], mu: &[f64]) -> Vec<f64> {
    let (n, k) = (m.n_states(), m.n_constraints());
    let nw: usize = m.indices().iter().sum();
    let mut dx = vec![0.0; n];
    let (mut w, mut s, mut ah) = (vec![0.0; nw], vec![0.0; k], vec![0.0; k]);
    let mut jac = vec![0.0; m.jacobian_pattern().len()];
    let mut beta = vec![0.0; k];
    m.rhs(t, x, z, &mut dx);
    m.sliding(t, x, z, mu, &mut w, &mut s, &mut ah);
    m.jacobian(t, x, z, &mut jac);
    m.beta(t, x, z, &mut beta);
    [dx, w, s, ah, jac, beta].concat()
}

#[test]
fn a_mass_matrix_model_equals_its_explicit_form() {
    let mass = interpreted(models_dir().join("cart_pendulum.dae"));
    let explicit = interpreted(here("cart_pendulum_explicit.dae"));
    let code = generated::CartPendulum::default();
    assert_eq!(mass.indices(), explicit.indices());
    assert_eq!(mass.jacobian_pattern(), explicit.jacobian_pattern());
    let mut rng = Rng::new(51);
    for _ in 0..200 {
        let t = rng.uniform(0.0, 5.0);
        let x: Vec<f64> = (0..4).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let z = [rng.uniform(-20.0, 20.0)];
        let mu = [rng.uniform(0.01, 1.0)];
        let a = evaluate(&mass, t, &x, &z, &mu);
        let b = evaluate(&explicit, t, &x, &z, &mu);
        let c = evaluate(&code, t, &x, &z, &mu);
        for (i, ((a, b), c)) in a.iter().zip(&b).zip(&c).enumerate() {
            assert!(
                close(*a, *b, 1e-11),
                "output {i} at x = {x:?}: mass {a:e}, explicit {b:e}"
            );
            assert!(
                close(*a, *c, 1e-12),
                "output {i}: interpreted {a:e}, generated {c:e}"
            );
        }
    }
    // The generated explicit form is the same model too.
    let e = generated::CartPendulumExplicit::default();
    let (x, z, mu) = ([0.1, -0.7, 0.4, 1.3], [2.5], [0.3]);
    for (a, b) in evaluate(&e, 0.4, &x, &z, &mu)
        .iter()
        .zip(evaluate(&code, 0.4, &x, &z, &mu))
    {
        assert!(close(*a, b, 1e-11), "{a:e} vs {b:e}");
    }
}

#[test]
fn a_per_element_mass_matrix_equals_its_explicit_form() {
    let mass = interpreted(here("beads_mass.dae"));
    let explicit = interpreted(here("beads_explicit.dae"));
    assert_eq!(mass.indices(), explicit.indices());
    assert_eq!(mass.jacobian_pattern(), explicit.jacobian_pattern());
    let (n, k) = (mass.n_states(), mass.n_constraints());
    let mut x0 = vec![0.0; n];
    mass.initial_state(&mut x0);
    let mut rng = Rng::new(52);
    for _ in 0..200 {
        let t = rng.uniform(0.0, 5.0);
        let x: Vec<f64> = x0.iter().map(|v| v + rng.uniform(-0.3, 0.3)).collect();
        let z: Vec<f64> = (0..k).map(|_| rng.uniform(-20.0, 20.0)).collect();
        let mu: Vec<f64> = (0..k).map(|_| rng.uniform(0.01, 1.0)).collect();
        let a = evaluate(&mass, t, &x, &z, &mu);
        let b = evaluate(&explicit, t, &x, &z, &mu);
        for (i, (a, b)) in a.iter().zip(&b).enumerate() {
            assert!(
                close(*a, *b, 1e-11),
                "output {i} at x = {x:?}: mass {a:e}, explicit {b:e}"
            );
        }
    }
}

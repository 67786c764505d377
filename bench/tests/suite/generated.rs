//! The generated models against the hand-written, finite-difference-checked stand-in
//! `PlanarChainDae` (an independent oracle of the compiler's output) at random points.

use dae_bench::{
    generated::Chain3, generated::Chain5, generated::DoublePendulum, generated::DoublePendulum3D,
    scenes::vertical_plane_map, standin::PlanarChainDae, truth::PlanarChain,
};
use dae_runtime::Model;

/// A small deterministic generator of values in `[-1, 1)` (no extra dependency).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

struct Eval {
    f: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    ah: Vec<f64>,
    jac: Vec<f64>,
    beta: Vec<f64>,
}

fn eval<M: Model + ?Sized>(model: &M, x: &[f64], z: &[f64], mu: &[f64]) -> Eval {
    let (n, m) = (model.n_states(), model.n_constraints());
    let nw: usize = model.indices().iter().sum();
    let mut e = Eval {
        f: vec![0.0; n],
        w: vec![0.0; nw],
        s: vec![0.0; m],
        ah: vec![0.0; m],
        jac: vec![0.0; m * m],
        beta: vec![0.0; m],
    };
    model.rhs(0.3, x, z, &mut e.f);
    model.sliding(0.3, x, z, mu, &mut e.w, &mut e.s, &mut e.ah);
    let mut vals = vec![0.0; model.jacobian_pattern().len()];
    model.jacobian(0.3, x, z, &mut vals);
    for (&(i, j), v) in model.jacobian_pattern().iter().zip(&vals) {
        e.jac[i * m + j] += v;
    }
    model.beta(0.3, x, z, &mut e.beta);
    e
}

fn close(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (i, (p, q)) in a.iter().zip(b).enumerate() {
        assert!(
            (p - q).abs() <= 1e-10 * (1.0 + q.abs()),
            "{what}[{i}]: generated {p} vs stand-in {q}"
        );
    }
}

/// Random states off the manifold (particles spread, velocities nonzero), random `z`
/// and `mu`: every formula must agree everywhere, not only on the solution.
fn compare_planar<M: Model>(generated: &M, chain: &PlanarChain, seed: u64) {
    let oracle = PlanarChainDae::new(chain).unwrap();
    let n = chain.links();
    assert_eq!(generated.n_states(), 4 * n);
    assert_eq!(generated.indices(), oracle.indices());
    let mut r = Lcg(seed);
    for _ in 0..20 {
        let x: Vec<f64> = (0..4 * n).map(|_| 2.0 * r.next()).collect();
        let z: Vec<f64> = (0..n).map(|_| 5.0 * r.next()).collect();
        let mu: Vec<f64> = (0..n).map(|_| 0.01 + 0.2 * (r.next() + 1.0)).collect();
        let (g, o) = (eval(generated, &x, &z, &mu), eval(&oracle, &x, &z, &mu));
        close("f", &g.f, &o.f);
        close("w", &g.w, &o.w);
        close("s", &g.s, &o.s);
        close("alpha_hat", &g.ah, &o.ah);
        close("J_Omega", &g.jac, &o.jac);
        close("beta", &g.beta, &o.beta);
    }
}

#[test]
fn generated_double_pendulum_matches_the_stand_in_at_random_points() {
    compare_planar(
        &DoublePendulum::default(),
        &PlanarChain::double_pendulum(),
        1,
    );
}

#[test]
fn generated_chain5_matches_the_stand_in_at_random_points() {
    let chain = PlanarChain::new(vec![0.1; 5], vec![0.5; 5], 9.8).unwrap();
    let model = Chain5 {
        L: 0.5,
        ..Chain5::default()
    };
    compare_planar(&model, &chain, 2);
}

#[test]
fn generated_chain3_with_its_own_masses_and_lengths_matches_the_stand_in() {
    let chain = PlanarChain::new(vec![0.1, 0.3, 100.0], vec![1.0, 0.7, 1.3], 9.8).unwrap();
    let model = Chain3 {
        m2: 0.3,
        m3: 100.0,
        L2: 0.7,
        L3: 1.3,
        ..Chain3::default()
    };
    compare_planar(&model, &chain, 3);
}

#[test]
fn generated_3d_pendulum_in_a_vertical_plane_is_the_planar_one() {
    let planar = PlanarChainDae::new(&PlanarChain::double_pendulum()).unwrap();
    let spatial = DoublePendulum3D::default();
    let map = vertical_plane_map(2);
    let mut r = Lcg(4);
    for _ in 0..20 {
        let xp: Vec<f64> = (0..8).map(|_| 2.0 * r.next()).collect();
        let mut x3 = vec![0.0; 12];
        for (&i, v) in map.iter().zip(&xp) {
            x3[i] = *v;
        }
        let z = [5.0 * r.next(), 5.0 * r.next()];
        let mu = [0.05, 0.07];
        let (g, o) = (eval(&spatial, &x3, &z, &mu), eval(&planar, &xp, &z, &mu));
        let f_in_plane: Vec<f64> = map.iter().map(|&i| g.f[i]).collect();
        close("f in the plane", &f_in_plane, &o.f);
        let out_of_plane: Vec<f64> = (0..12)
            .filter(|i| !map.contains(i))
            .map(|i| g.f[i])
            .collect();
        assert!(out_of_plane.iter().all(|v| *v == 0.0), "{out_of_plane:?}");
        close("w", &g.w, &o.w);
        close("J_Omega", &g.jac, &o.jac);
        close("beta", &g.beta, &o.beta);
    }
}

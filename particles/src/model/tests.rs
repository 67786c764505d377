//! The particle model against finite differences: `J_Omega` as the derivative of `w''`
//! in `z`, `w'` and `w''` as derivatives of `w` and `w'` along the flow, `beta` as the
//! derivative of `w''` along the flow with `z` held, and the structure of the pattern.

use super::*;
use crate::builders::{GridPins, chain, grid};
use crate::motion::{GrabPath, Sway};

/// Deterministic values in `[-1, 1)`.
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

/// A 3 x 3 cloth (structural links, jittered out of its plane so that the links are
/// independent) with one corner driven by a sway, the other fixed, a free particle
/// grabbed on a path, and a heavy particle: every kind of particle a link can end at.
fn test_model() -> ParticleModel {
    let flat = grid(3, GridPins::Corners, false).unwrap();
    let mut rng = Lcg(42);
    let positions = flat
        .positions()
        .iter()
        .map(|p| {
            [
                p[0] + 0.1 * rng.next(),
                p[1] + 0.1 * rng.next(),
                0.2 * rng.next(),
            ]
        })
        .collect();
    let edges: Vec<(usize, usize)> = flat.links().iter().map(|l| (l.a, l.b)).collect();
    let sys = System::from_edges(positions, flat.masses().to_vec(), &edges)
        .unwrap()
        .with_fixed(8)
        .unwrap()
        .with_mass(4, 3.0)
        .unwrap()
        .with_pin(
            6,
            Pin::moving(Sway {
                base: flat.positions()[6],
                travel: [0.2, 0.1, -0.1],
                frequency: 1.3,
            }),
        )
        .unwrap();
    let mut model = ParticleModel::new(&sys).unwrap();
    model
        .set_pin(
            1,
            Some(Pin::moving(GrabPath {
                t0: 0.1,
                p0: [0.5, 0.0, 0.0],
                v0: [0.1, 0.2, 0.3],
                a0: [0.0, 0.0, -9.81],
                offset: [0.3, 0.0, 0.3],
                duration: 0.5,
            })),
        )
        .unwrap();
    model
}

/// A random state near the initial one and random tensions.
fn random_point(model: &ParticleModel, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Lcg(seed);
    let mut x = vec![0.0; model.n_states()];
    model.initial_state(&mut x);
    for v in x.iter_mut() {
        *v += 0.1 * rng.next();
    }
    let z = (0..model.n_constraints()).map(|_| rng.next()).collect();
    (x, z)
}

struct Eval {
    f: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    ah: Vec<f64>,
}

fn eval(model: &ParticleModel, t: f64, x: &[f64], z: &[f64], mu: &[f64]) -> Eval {
    let (n, m) = (model.n_states(), model.n_constraints());
    let mut e = Eval {
        f: vec![0.0; n],
        w: vec![0.0; 3 * m],
        s: vec![0.0; m],
        ah: vec![0.0; m],
    };
    model.rhs(t, x, z, &mut e.f);
    model.sliding(t, x, z, mu, &mut e.w, &mut e.s, &mut e.ah);
    e
}

fn dense_jacobian(model: &ParticleModel, t: f64, x: &[f64]) -> Vec<f64> {
    let m = model.n_constraints();
    let mut vals = vec![0.0; model.jacobian_pattern().len()];
    model.jacobian(t, x, &[], &mut vals);
    let mut j = vec![0.0; m * m];
    for (&(r, c), v) in model.jacobian_pattern().iter().zip(&vals) {
        j[r * m + c] += v;
    }
    j
}

#[test]
fn jacobian_is_the_derivative_of_w2_in_z() {
    let model = test_model();
    let m = model.n_constraints();
    let mu = vec![0.1; m];
    for seed in 1..4 {
        let (x, z) = random_point(&model, seed);
        let t = 0.3;
        let j = dense_jacobian(&model, t, &x);
        for k in 0..m {
            // w'' is affine in z: a unit central difference is exact up to rounding.
            let (mut zp, mut zm) = (z.clone(), z.clone());
            zp[k] += 1.0;
            zm[k] -= 1.0;
            let (ep, em) = (eval(&model, t, &x, &zp, &mu), eval(&model, t, &x, &zm, &mu));
            for l in 0..m {
                let fd = (ep.w[3 * l + 2] - em.w[3 * l + 2]) / 2.0;
                assert!(
                    (fd - j[l * m + k]).abs() < 1e-9 * (1.0 + fd.abs()),
                    "J[{l},{k}] = {} vs fd {fd}",
                    j[l * m + k]
                );
            }
        }
    }
}

#[test]
fn w_derivatives_and_beta_match_finite_differences_along_the_flow() {
    let model = test_model();
    let m = model.n_constraints();
    let mu: Vec<f64> = (0..m).map(|l| 0.05 + 0.01 * l as f64).collect();
    let h = 1e-6;
    for seed in 5..9 {
        let (x, z) = random_point(&model, seed);
        let t = 0.35;
        let e = eval(&model, t, &x, &z, &mu);
        let along = |tau: f64| -> Eval {
            let xs: Vec<f64> = x.iter().zip(&e.f).map(|(x, f)| x + tau * f).collect();
            eval(&model, t + tau, &xs, &z, &mu)
        };
        let (ep, em) = (along(h), along(-h));
        let mut beta = vec![0.0; m];
        model.beta(t, &x, &z, &mut beta);
        for l in 0..m {
            let fd = |j: usize| (ep.w[3 * l + j] - em.w[3 * l + j]) / (2.0 * h);
            for (what, d, exact) in [
                ("w'", fd(0), e.w[3 * l + 1]),
                ("w''", fd(1), e.w[3 * l + 2]),
                ("beta", fd(2), beta[l]),
            ] {
                assert!(
                    (d - exact).abs() < 1e-5 * (1.0 + exact.abs()),
                    "link {l} {what}: {exact} vs fd {d}"
                );
            }
            let (w0, w1, w2) = (e.w[3 * l], e.w[3 * l + 1], e.w[3 * l + 2]);
            assert!((e.s[l] - (mu[l] * mu[l] * w2 + 2.0 * mu[l] * w1 + w0)).abs() < 1e-14);
            assert!((e.ah[l] - (w1 + 2.0 * mu[l] * w2)).abs() < 1e-14);
        }
    }
}

#[test]
fn omega_rate_is_the_derivative_of_w2_along_the_flow_with_the_tensions_moving() {
    // Against two oracles: the central difference of w'' along (x' = f, z' = zdot),
    // and beta + J_Omega zdot from the model's own beta and Jacobian.
    let model = test_model();
    let m = model.n_constraints();
    let mu = vec![0.1; m];
    let h = 1e-6;
    for seed in 21..25 {
        let (x, z) = random_point(&model, seed);
        let zdot: Vec<f64> = {
            let mut rng = Lcg(seed + 100);
            (0..m).map(|_| 3.0 * rng.next()).collect()
        };
        let t = 0.27;
        let e = eval(&model, t, &x, &z, &mu);
        let along = |tau: f64| -> Eval {
            let xs: Vec<f64> = x.iter().zip(&e.f).map(|(x, f)| x + tau * f).collect();
            let zs: Vec<f64> = z.iter().zip(&zdot).map(|(z, d)| z + tau * d).collect();
            eval(&model, t + tau, &xs, &zs, &mu)
        };
        let (ep, em) = (along(h), along(-h));
        let mut rate = vec![f64::NAN; m];
        assert!(model.omega_rate(t, &x, &z, &zdot, &mut rate));
        let mut beta = vec![0.0; m];
        model.beta(t, &x, &z, &mut beta);
        let j = dense_jacobian(&model, t, &x);
        for l in 0..m {
            let fd = (ep.w[3 * l + 2] - em.w[3 * l + 2]) / (2.0 * h);
            assert!(
                (fd - rate[l]).abs() < 1e-5 * (1.0 + fd.abs()),
                "link {l}: omega_rate {} vs fd {fd}",
                rate[l]
            );
            let composed = beta[l] + (0..m).map(|k| j[l * m + k] * zdot[k]).sum::<f64>();
            assert!(
                (composed - rate[l]).abs() < 1e-12 * (1.0 + composed.abs()),
                "link {l}: omega_rate {} vs beta + J zdot {composed}",
                rate[l]
            );
        }
        // With the tensions held it is beta, to the bit.
        model.omega_rate(t, &x, &z, &vec![0.0; m], &mut rate);
        assert_eq!(rate, beta);
    }
}

#[test]
fn pinned_particles_follow_their_motion_and_feel_no_tension() {
    let model = test_model();
    let (x, z) = random_point(&model, 11);
    let t = 0.4;
    let e = eval(&model, t, &x, &z, &vec![0.1; model.n_constraints()]);
    for k in [1, 6] {
        let acc = model.pins[k].as_ref().unwrap().at(t).acc;
        assert_eq!(&e.f[6 * k + 3..6 * k + 6], &acc);
        assert_eq!(&e.f[6 * k..6 * k + 3], &x[6 * k + 3..6 * k + 6]);
    }
    // Fixed corner: at rest whatever the tensions.
    assert_eq!(&e.f[6 * 8 + 3..6 * 8 + 6], &[0.0; 3]);
}

#[test]
fn jacobian_entries_are_the_closed_forms_of_the_method() {
    // A bent 3-link chain: J[0,1] = -(rhat_10 . rhat_12) / m_1 through particle 1.
    let sys = System::from_edges(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0, -1.0, 0.0],
            [2.0, -1.0, 0.5],
        ],
        vec![1.0, 2.0, 4.0, 8.0],
        &[(0, 1), (1, 2), (2, 3)],
    )
    .unwrap()
    .with_fixed(0)
    .unwrap();
    let model = ParticleModel::new(&sys).unwrap();
    let mut x = vec![0.0; model.n_states()];
    model.initial_state(&mut x);
    let j = dense_jacobian(&model, 0.0, &x);
    let r10 = [-1.0, 0.0, 0.0];
    let r12 = [0.0, -1.0, 0.0];
    let r21 = [0.0, 1.0, 0.0];
    let d23 = [1.0, 0.0, 0.5];
    let n23 = dot(d23, d23).sqrt();
    let r23 = [d23[0] / n23, d23[1] / n23, d23[2] / n23];
    let expect = [
        [-0.5, -dot(r10, r12) / 2.0, 0.0],
        [-dot(r10, r12) / 2.0, -(0.5 + 0.25), -dot(r21, r23) / 4.0],
        [0.0, -dot(r21, r23) / 4.0, -(0.25 + 0.125)],
    ];
    for l in 0..3 {
        for k in 0..3 {
            assert!((j[3 * l + k] - expect[l][k]).abs() < 1e-15, "J[{l},{k}]");
        }
    }
}

#[test]
fn the_start_is_consistent_and_links_between_pins_are_dropped() {
    let sys = grid(4, GridPins::Edge, false).unwrap();
    let model = ParticleModel::new(&sys).unwrap();
    // 24 links, 3 of them along the pinned edge.
    assert_eq!(model.n_constraints(), 21);
    let dropped: Vec<usize> = (0..24)
        .filter(|&l| model.constraint_of_link(l).is_none())
        .collect();
    assert_eq!(dropped.len(), 3);
    for &l in &dropped {
        let link = sys.links()[l];
        assert!(sys.pins()[link.a].is_some() && sys.pins()[link.b].is_some());
    }
    let (mut x, mut z) = (vec![0.0; model.n_states()], vec![0.0; 21]);
    model.initial_state(&mut x);
    model.initial_alg(&mut z);
    let e = eval(&model, 0.0, &x, &z, &[0.1; 21]);
    for l in 0..21 {
        assert!(
            e.w[3 * l].abs() < 1e-15 && e.w[3 * l + 1] == 0.0 && e.w[3 * l + 2].abs() < 1e-9,
            "link {l}: {:?}",
            &e.w[3 * l..3 * l + 3]
        );
    }
}

#[test]
fn pin_changes_keep_the_pattern_and_refuse_doubly_pinned_links() {
    let sys = chain(3, 1.0).unwrap();
    let mut model = ParticleModel::new(&sys).unwrap();
    let pattern = model.jacobian_pattern().to_vec();
    let err = model
        .set_pin(1, Some(Pin::Fixed([1.0 / 3.0, 0.0, 0.0])))
        .unwrap_err();
    assert!(
        matches!(err, ModelError::PinnedLink { link: 0, .. }),
        "{err}"
    );
    model
        .set_pin(2, Some(Pin::Fixed([2.0 / 3.0, 0.0, 0.0])))
        .unwrap();
    assert_eq!(model.jacobian_pattern(), &pattern[..]);
    let mut x = vec![0.0; model.n_states()];
    model.initial_state(&mut x);
    // Particle 2 pinned: links 1 and 2 no longer couple through it, and their
    // diagonals lose 1/m_2.
    let j = dense_jacobian(&model, 0.0, &x);
    let inv = 30.0;
    assert_eq!(j[3 + 2], 0.0);
    assert!((j[4] + inv).abs() < 1e-12 && (j[8] + inv).abs() < 1e-12);
    model.set_pin(2, None).unwrap();
    let j = dense_jacobian(&model, 0.0, &x);
    assert!((j[4] + 2.0 * inv).abs() < 1e-12 && (j[3 + 2] - inv).abs() < 1e-12);
    assert!(matches!(
        model.set_pin(9, None),
        Err(ModelError::NoSuchParticle { .. })
    ));
}

#[test]
fn evaluation_is_linear_in_the_links() {
    // The pattern has O(links) entries: at most 1 + 2 (deg - 1) per row for a chain,
    // 1 + 6 for a structural cloth row.
    let c = ParticleModel::new(&chain(1000, 1.0).unwrap()).unwrap();
    assert_eq!(c.jacobian_pattern().len(), 1000 + 2 * 999);
    let g = ParticleModel::new(&grid(32, GridPins::Edge, false).unwrap()).unwrap();
    assert!(g.jacobian_pattern().len() <= 7 * g.n_constraints());
}

/// `sliding` and `Omega'` at one point share one computation of the accelerations (the
/// simulator asks for both at the end of every step): whatever was evaluated before, at
/// that point or another, with the unit vectors of `J_Omega` computed in between, or a
/// pin changed, each gives to the bit what a model that evaluated nothing before gives.
#[test]
fn sliding_and_omega_rate_give_the_same_bits_whatever_was_evaluated_before() {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let mut model = test_model();
    let m = model.n_constraints();
    let mu = vec![0.01; m];
    let zdot: Vec<f64> = (0..m).map(|l| 0.3 - 0.1 * l as f64).collect();
    let fresh = |model: &ParticleModel, t: f64, x: &[f64], z: &[f64]| {
        // A model that evaluated nothing before: the same system, pins and all.
        let (mut w, mut s, mut ah, mut r) =
            (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        model.scratch.borrow_mut().holding = false;
        model.sliding(t, x, z, &mu, &mut w, &mut s, &mut ah);
        model.scratch.borrow_mut().holding = false;
        assert!(model.omega_rate(t, x, z, &zdot, &mut r));
        (bits(&w), bits(&s), bits(&ah), bits(&r))
    };
    let seen = |model: &ParticleModel, t: f64, x: &[f64], z: &[f64]| {
        let (mut w, mut s, mut ah, mut r) =
            (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        model.sliding(t, x, z, &mu, &mut w, &mut s, &mut ah);
        assert!(model.omega_rate(t, x, z, &zdot, &mut r));
        (bits(&w), bits(&s), bits(&ah), bits(&r))
    };
    let (x, z) = random_point(&model, 5);
    let (x2, z2) = random_point(&model, 6);
    let want = fresh(&model, 0.2, &x, &z);
    // After another point, twice at this one, and after J_Omega at another.
    seen(&model, 0.2, &x2, &z2);
    assert_eq!(seen(&model, 0.2, &x, &z), want);
    assert_eq!(seen(&model, 0.2, &x, &z), want);
    model.jacobian(
        0.2,
        &x2,
        &z2,
        &mut vec![0.0; model.jacobian_pattern().len()],
    );
    let mut r = vec![0.0; m];
    assert!(model.omega_rate(0.2, &x, &z, &zdot, &mut r));
    assert_eq!(bits(&r), want.3);
    // Another time is another point (the pins move).
    assert_eq!(seen(&model, 0.3, &x, &z), fresh(&model, 0.3, &x, &z));
    // A pin changed (the grabbed particle released): the same point gives the new
    // pins' values.
    seen(&model, 0.2, &x, &z);
    assert!(model.is_pinned(1));
    model.set_pin(1, None).unwrap();
    let released = seen(&model, 0.2, &x, &z);
    assert_eq!(released, fresh(&model, 0.2, &x, &z));
    assert_ne!(released.3, want.3);
}

/// At an update the simulator evaluates `s`, then `J_Omega` and `beta` at one point:
/// `J_Omega` takes the remembered unit vectors there and `beta` the remembered
/// accelerations. Both give to the bit what a model that evaluated nothing before gives,
/// and `J_Omega` at other positions still gives its own.
#[test]
fn j_omega_and_beta_after_s_at_one_point_give_the_same_bits_as_fresh() {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let model = test_model();
    let m = model.n_constraints();
    let n_j = model.jacobian_pattern().len();
    let mu = vec![0.01; m];
    let (x, z) = random_point(&model, 7);
    let (x2, z2) = random_point(&model, 8);
    let j_and_beta = |model: &ParticleModel, x: &[f64], z: &[f64]| {
        let (mut j, mut beta) = (vec![0.0; n_j], vec![0.0; m]);
        model.jacobian(0.2, x, z, &mut j);
        model.beta(0.2, x, z, &mut beta);
        (bits(&j), bits(&beta))
    };
    model.scratch.borrow_mut().holding = false;
    let fresh = j_and_beta(&model, &x, &z);
    model.scratch.borrow_mut().holding = false;
    let fresh2 = j_and_beta(&model, &x2, &z2);
    let (mut w, mut s, mut ah) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
    model.sliding(0.2, &x, &z, &mu, &mut w, &mut s, &mut ah);
    assert_eq!(j_and_beta(&model, &x, &z), fresh);
    model.sliding(0.2, &x, &z, &mu, &mut w, &mut s, &mut ah);
    assert_eq!(j_and_beta(&model, &x2, &z2), fresh2);
    assert_eq!(j_and_beta(&model, &x, &z), fresh);
}

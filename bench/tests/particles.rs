//! The particle model against the generated scalar chain, and the particle baselines
//! (XPBD, index-1) against a reference on a tiny chain.

use std::time::Duration;

use dae_bench::{
    Chain5, IndexOneParticles, MethodSpec, Xpbd, c1, drive_scene, run_particle_method,
};
use dae_particles::{Backend, FRAME, ParticleModel, Scene, System, chain};
use dae_runtime::{Integrator, Model, SolverChoice};

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

/// The hand-written 3-D particle model of a planar 5-link chain (unit links, 0.1 kg,
/// gravity 9.8 along -y, pinned at the origin) is the generated `chain5_planar.dae`
/// where they coincide: in the plane z = 0, at random states off the manifold.
#[test]
fn particle_model_matches_the_generated_planar_chain_at_random_points() {
    let sys = System::from_edges(
        (0..6).map(|k| [k as f64, 0.0, 0.0]).collect(),
        vec![0.1; 6],
        &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)],
    )
    .unwrap()
    .with_fixed(0)
    .unwrap()
    .with_gravity([0.0, -9.8, 0.0]);
    let ours = ParticleModel::new(&sys).unwrap();
    let generated = Chain5::default();
    let mut r = Lcg(7);
    for _ in 0..20 {
        let xg: Vec<f64> = (0..20).map(|_| 2.0 * r.next()).collect();
        let z: Vec<f64> = (0..5).map(|_| 5.0 * r.next()).collect();
        let mu: Vec<f64> = (0..5).map(|_| 0.01 + 0.2 * (r.next() + 1.0)).collect();
        let mut xo = vec![0.0; 36];
        for k in 0..5 {
            let p = k + 1;
            xo[6 * p] = xg[4 * k];
            xo[6 * p + 1] = xg[4 * k + 1];
            xo[6 * p + 3] = xg[4 * k + 2];
            xo[6 * p + 4] = xg[4 * k + 3];
        }
        let (mut fg, mut fo) = (vec![0.0; 20], vec![0.0; 36]);
        generated.rhs(0.2, &xg, &z, &mut fg);
        ours.rhs(0.2, &xo, &z, &mut fo);
        let (mut wg, mut sg, mut ag) = (vec![0.0; 15], vec![0.0; 5], vec![0.0; 5]);
        let (mut wo, mut so, mut ao) = (vec![0.0; 15], vec![0.0; 5], vec![0.0; 5]);
        generated.sliding(0.2, &xg, &z, &mu, &mut wg, &mut sg, &mut ag);
        ours.sliding(0.2, &xo, &z, &mu, &mut wo, &mut so, &mut ao);
        let dense = |m: &dyn Model, x: &[f64]| {
            let mut v = vec![0.0; m.jacobian_pattern().len()];
            m.jacobian(0.2, x, &z, &mut v);
            let mut j = vec![0.0; 25];
            for (&(a, b), v) in m.jacobian_pattern().iter().zip(&v) {
                j[5 * a + b] += v;
            }
            j
        };
        let (jg, jo) = (dense(&generated, &xg), dense(&ours, &xo));
        let (mut bg, mut bo) = (vec![0.0; 5], vec![0.0; 5]);
        generated.beta(0.2, &xg, &z, &mut bg);
        ours.beta(0.2, &xo, &z, &mut bo);
        let close = |what: &str, a: &[f64], b: &[f64]| {
            for (i, (p, q)) in a.iter().zip(b).enumerate() {
                assert!(
                    (p - q).abs() <= 1e-10 * (1.0 + q.abs()),
                    "{what}[{i}]: particles {p} vs generated {q}"
                );
            }
        };
        for k in 0..5 {
            let p = k + 1;
            let mapped = [fo[6 * p], fo[6 * p + 1], fo[6 * p + 3], fo[6 * p + 4]];
            close("f", &mapped, &fg[4 * k..4 * k + 4]);
            assert_eq!(
                (fo[6 * p + 2], fo[6 * p + 5]),
                (0.0, 0.0),
                "out of the plane"
            );
        }
        close("w", &wo, &wg);
        close("s", &so, &sg);
        close("alpha_hat", &ao, &ag);
        close("J_Omega", &jo, &jg);
        close("beta", &bo, &bg);
    }
}

/// Position of the chain's end after `frames` frames with `backend`.
fn end_after<B: Backend>(sys: &System, backend: B, frames: u64) -> ([f64; 3], f64) {
    let mut scene = Scene::new(sys, backend).unwrap();
    for _ in 0..frames {
        scene.step().unwrap();
    }
    (
        scene.positions()[sys.n_particles() - 1],
        scene.worst_strain().strain,
    )
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    dae_particles::distance(a, b)
}

#[test]
fn index_one_converges_to_the_reference_on_a_tiny_chain() {
    let sys = chain(3, 1.0).unwrap();
    let model = || ParticleModel::new(&sys).unwrap();
    let frames = 12;
    let (reference, _) = end_after(
        &sys,
        IndexOneParticles::new(model(), 256, SolverChoice::Auto).unwrap(),
        frames,
    );
    let (check, _) = end_after(
        &sys,
        IndexOneParticles::new(model(), 512, SolverChoice::Auto).unwrap(),
        frames,
    );
    assert!(
        dist(reference, check) < 1e-7,
        "the reference itself: {}",
        dist(reference, check)
    );
    let errors: Vec<f64> = [4, 16, 64]
        .iter()
        .map(|&spf| {
            dist(
                end_after(
                    &sys,
                    IndexOneParticles::new(model(), spf, SolverChoice::Auto).unwrap(),
                    frames,
                )
                .0,
                reference,
            )
        })
        .collect();
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 1e-5, "{errors:?}");
}

#[test]
fn xpbd_stretch_decreases_with_substeps_and_positions_approach_the_reference() {
    let sys = chain(3, 1.0).unwrap();
    let frames = 12;
    let (reference, _) = end_after(
        &sys,
        IndexOneParticles::new(ParticleModel::new(&sys).unwrap(), 256, SolverChoice::Auto).unwrap(),
        frames,
    );
    let runs: Vec<([f64; 3], f64)> = [1, 4, 16, 64]
        .iter()
        .map(|&k| end_after(&sys, Xpbd::new(&sys, k, 1).unwrap(), frames))
        .collect();
    for w in runs.windows(2) {
        assert!(w[1].1 < w[0].1, "stretch must fall with substeps: {runs:?}");
    }
    let errors: Vec<f64> = runs.iter().map(|r| dist(r.0, reference)).collect();
    assert!(errors[3] < errors[0] && errors[3] < 5e-3, "{errors:?}");
    // One step of more iterations stretches less, too.
    let (_, s4) = end_after(&sys, Xpbd::new(&sys, 1, 4).unwrap(), frames);
    let (_, s64) = end_after(&sys, Xpbd::new(&sys, 1, 64).unwrap(), frames);
    assert!(s64 < s4, "{s4} vs {s64}");
}

#[test]
fn dbsmc_keeps_its_bound_on_a_tiny_chain_through_the_harness() {
    let scene = c1(3, 1.0).unwrap();
    let mut short = scene.clone();
    short.duration = 0.5;
    let (bounds, pilot) = dae_bench::particle_pilot(&short, 64, Duration::from_secs(60)).unwrap();
    assert!(pilot.complete());
    for integrator in [Integrator::Rk4, Integrator::Euler] {
        let spec = MethodSpec::Dbsmc {
            eps: 1e-3,
            solver: SolverChoice::Auto,
            integrator,
        };
        let r = run_particle_method(
            &short,
            &spec,
            Some(&bounds),
            Duration::from_secs(60),
            None,
            None,
        );
        assert!(r.complete(), "{}", r.status);
        assert!(
            r.worst_strain <= 1.05e-3,
            "{integrator:?}: {}",
            r.worst_strain
        );
        assert!(r.counters.updates > 0 && r.counters.f_evals > 0);
    }
    // The driver counts the frames of the scene.
    let r = drive_scene(
        &short,
        &MethodSpec::XpbdSubsteps(4),
        Xpbd::new(&short.system, 4, 1).unwrap(),
        Duration::from_secs(60),
        None,
        None,
    );
    assert_eq!((r.frames, r.frames_total), (30, 30));
    assert!((r.frames as f64 * FRAME - 0.5).abs() < 1e-12);
}

/// The chain generated from the family model `chain.dae` (sized at run time) is the
/// hand-written particle model of the same C1 chain: `f`, the w-derivatives, `s`,
/// `J_Omega` (as a dense matrix: the two patterns need not list entries alike) and
/// `beta` agree at random states off the manifold, pinned particle at the origin.
#[test]
fn the_generated_family_chain_is_the_hand_written_c1_chain() {
    use dae_bench::FamilyChain;
    use dae_particles::ParticleDae;
    let mut r = Lcg(11);
    for (n, ratio) in [(3, 1.0), (6, 1e2), (10, 1e4)] {
        let hand = ParticleModel::new(&chain(n, ratio).unwrap()).unwrap();
        let fam = FamilyChain::new(n, ratio).unwrap();
        let m = n;
        assert_eq!((hand.n_constraints(), fam.n_constraints()), (m, m));
        assert_eq!(hand.n_particles(), fam.n_particles());
        let (mut xh, mut xg) = (vec![0.0; hand.n_states()], vec![0.0; fam.n_states()]);
        hand.initial_state(&mut xh);
        fam.initial_state(&mut xg);
        for k in 1..=n {
            let (hp, hv) = hand.state_slots(k);
            let (gp, gv) = fam.state_slots(k);
            for c in 0..3 {
                let p = xh[hp + c] + 0.02 * r.next();
                let v = r.next();
                xh[hp + c] = p;
                xg[gp + c] = p;
                xh[hv + c] = v;
                xg[gv + c] = v;
            }
        }
        let z: Vec<f64> = (0..m).map(|_| 0.05 * r.next()).collect();
        let mu = vec![0.07; m];
        let t = 0.3;
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs())),
                "N={n} r={ratio}: {what}: hand {a} generated {b}"
            )
        };
        let (mut fh, mut fg) = (vec![0.0; xh.len()], vec![0.0; xg.len()]);
        hand.rhs(t, &xh, &z, &mut fh);
        fam.rhs(t, &xg, &z, &mut fg);
        for k in 0..=n {
            let (hp, hv) = hand.state_slots(k);
            let (gp, gv) = fam.state_slots(k);
            for c in 0..3 {
                close(fh[hp + c], fg[gp + c], &format!("x'[{k}]"));
                close(fh[hv + c], fg[gv + c], &format!("v'[{k}]"));
            }
        }
        let nw = 3 * m;
        let (mut wh, mut wg) = (vec![0.0; nw], vec![0.0; nw]);
        let (mut sh, mut sg, mut ah, mut ag) =
            (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        hand.sliding(t, &xh, &z, &mu, &mut wh, &mut sh, &mut ah);
        fam.sliding(t, &xg, &z, &mu, &mut wg, &mut sg, &mut ag);
        for i in 0..nw {
            close(wh[i], wg[i], &format!("w[{i}]"));
        }
        for i in 0..m {
            close(sh[i], sg[i], &format!("s[{i}]"));
            close(ah[i], ag[i], &format!("alpha_hat[{i}]"));
        }
        let dense = |model: &dyn Model, x: &[f64]| {
            let mut v = vec![0.0; model.jacobian_pattern().len()];
            model.jacobian(t, x, &z, &mut v);
            let mut d = vec![0.0; m * m];
            for (&(i, j), v) in model.jacobian_pattern().iter().zip(&v) {
                d[i * m + j] += v;
            }
            d
        };
        let (jh, jg) = (dense(&hand, &xh), dense(&fam, &xg));
        for i in 0..m * m {
            close(jh[i], jg[i], &format!("J[{}, {}]", i / m, i % m));
        }
        let (mut bh, mut bg) = (vec![0.0; m], vec![0.0; m]);
        hand.beta(t, &xh, &z, &mut bh);
        fam.beta(t, &xg, &z, &mut bg);
        for i in 0..m {
            close(bh[i], bg[i], &format!("beta[{i}]"));
        }
    }
}

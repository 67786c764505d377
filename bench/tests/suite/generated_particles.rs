//! The generated family models of the particle scenes against the hand-written particle
//! model: the same functions at random states, through grabs and releases, a model of
//! another scene refused, a short grab and release of C4 on the generated cloth, and the
//! frame-tied design (no pilot) on the generated models.

use std::time::Duration;

use dae_bench::{
    particle_bench::MethodSpec, particle_bench::c1, particle_bench::c4,
    particle_bench::particle_pilot, particle_bench::run_particle_method,
    particle_methods::generated_chain, particle_methods::generated_grid,
    particle_methods::generated_strands, particles::Lcg,
};
use dae_particles::{
    FAR_EDGE_SLACK, FRAME, GrabPath, GridPins, Kinematics, Motion, ParticleDae, ParticleModel, Pin,
    System, chain, grid, grid_with_slack, strands,
};
use dae_runtime::{Model, settings::Integrator, solve::SolverChoice};

/// Both models at one random state (pinned particles on their pins at `t`, the others
/// off the manifold, moving, with random tensions): `f`, the w-derivatives, `s`,
/// `alpha_hat`, `J_Omega` (dense, entry by entry of the links: the patterns need not
/// list entries alike) and `beta` agree, constraint by constraint of the system's links.
fn assert_same_functions<M: ParticleDae>(
    what: &str,
    sys: &System,
    pins: &[Option<Pin>],
    hand: &ParticleModel,
    fam: &M,
    t: f64,
    r: &mut Lcg,
) {
    let m = hand.n_constraints();
    assert_eq!(fam.n_constraints(), m, "{what}: constraints");
    assert_eq!(fam.n_particles(), hand.n_particles(), "{what}: particles");
    let pairs: Vec<(usize, usize)> = (0..sys.links().len())
        .filter_map(|l| {
            let (h, g) = (hand.constraint_of_link(l), fam.constraint_of_link(l));
            assert_eq!(h.is_some(), g.is_some(), "{what}: link {l} constrained");
            h.zip(g)
        })
        .collect();
    assert_eq!(pairs.len(), m);
    let scale = hand
        .rest_lengths()
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let (mut xh, mut xg) = (vec![0.0; hand.n_states()], vec![0.0; fam.n_states()]);
    for (k, pin) in pins.iter().enumerate() {
        let kin = match pin {
            Some(pin) => pin.at(t),
            None => Kinematics {
                pos: sys.positions()[k].map(|p| p + 0.2 * scale * r.signed()),
                vel: [r.signed(), r.signed(), r.signed()],
                ..Kinematics::default()
            },
        };
        for (x, (p, v)) in [
            (&mut xh, hand.state_slots(k)),
            (&mut xg, fam.state_slots(k)),
        ] {
            x[p..p + 3].copy_from_slice(&kin.pos);
            x[v..v + 3].copy_from_slice(&kin.vel);
        }
    }
    let z: Vec<f64> = (0..m).map(|_| 0.05 * r.signed()).collect();
    let zg = {
        let mut zg = vec![0.0; m];
        for &(h, g) in &pairs {
            zg[g] = z[h];
        }
        zg
    };
    let mu: Vec<f64> = (0..m).map(|_| 0.03 + 0.02 * r.signed()).collect();
    let mug = {
        let mut v = vec![0.0; m];
        for &(h, g) in &pairs {
            v[g] = mu[h];
        }
        v
    };
    let close = |a: f64, b: f64, name: &str| {
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs())),
            "{what} at t = {t}: {name}: hand-written {a}, generated {b}"
        )
    };
    let (mut fh, mut fg) = (vec![0.0; xh.len()], vec![0.0; xg.len()]);
    hand.rhs(t, &xh, &z, &mut fh);
    fam.rhs(t, &xg, &zg, &mut fg);
    for k in 0..sys.n_particles() {
        let ((hp, hv), (gp, gv)) = (hand.state_slots(k), fam.state_slots(k));
        for c in 0..3 {
            close(fh[hp + c], fg[gp + c], &format!("x'[{k}]"));
            close(fh[hv + c], fg[gv + c], &format!("v'[{k}]"));
        }
    }
    let (mut wh, mut sh, mut ah) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
    let (mut wg, mut sg, mut ag) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
    hand.sliding(t, &xh, &z, &mu, &mut wh, &mut sh, &mut ah);
    fam.sliding(t, &xg, &zg, &mug, &mut wg, &mut sg, &mut ag);
    let (mut bh, mut bg) = (vec![0.0; m], vec![0.0; m]);
    hand.beta(t, &xh, &z, &mut bh);
    fam.beta(t, &xg, &zg, &mut bg);
    for &(h, g) in &pairs {
        for d in 0..3 {
            close(wh[3 * h + d], wg[3 * g + d], &format!("w^({d})[{h}]"));
        }
        close(sh[h], sg[g], &format!("s[{h}]"));
        close(ah[h], ag[g], &format!("alpha_hat[{h}]"));
        close(bh[h], bg[g], &format!("beta[{h}]"));
    }
    let dense = |model: &dyn Model, x: &[f64], z: &[f64]| {
        let mut v = vec![0.0; model.jacobian_pattern().len()];
        model.jacobian(t, x, z, &mut v);
        let mut d = vec![0.0; m * m];
        for (&(i, j), v) in model.jacobian_pattern().iter().zip(&v) {
            d[i * m + j] += v;
        }
        d
    };
    let (jh, jg) = (dense(hand, &xh, &z), dense(fam, &xg, &zg));
    for &(hi, gi) in &pairs {
        for &(hj, gj) in &pairs {
            close(jh[hi * m + hj], jg[gi * m + gj], &format!("J[{hi}, {hj}]"));
        }
    }
}

/// A free particle whose neighbours are free too, not in `avoid` nor next to it (so
/// that pinning it leaves every link a free end).
fn lonely(sys: &System, pins: &[Option<Pin>], avoid: &[usize]) -> usize {
    let n = sys.n_particles();
    let neighbours = |k: usize| {
        sys.links()
            .iter()
            .filter_map(move |l| match (l.a == k, l.b == k) {
                (true, _) => Some(l.b),
                (_, true) => Some(l.a),
                _ => None,
            })
    };
    (0..n)
        .map(|i| (n / 2 + i) % n)
        .find(|&k| {
            pins[k].is_none()
                && !avoid.contains(&k)
                && neighbours(k).all(|j| pins[j].is_none() && !avoid.contains(&j))
        })
        .expect("a particle away from the pins")
}

/// The scene's pins as built, then a particle grabbed on a path (a moving pin: the
/// input's derivatives), another fixed where it starts, then the grabbed one
/// released: after each change both models agree at several times, and both refuse
/// the same impossible changes.
fn check_scene<M: ParticleDae>(what: &str, sys: &System, mut fam: M, r: &mut Lcg) {
    let mut hand = ParticleModel::new(sys).unwrap();
    let mut pins = sys.pins().to_vec();
    for t in [0.0, 0.3, 0.75] {
        assert_same_functions(what, sys, &pins, &hand, &fam, t, r);
    }
    let grabbed = lonely(sys, &pins, &[]);
    let path = Pin::moving(GrabPath {
        t0: 0.2,
        p0: sys.positions()[grabbed],
        v0: [0.1, -0.2, 0.3],
        a0: [1.0, 0.0, -9.81],
        offset: [0.3, 0.0, 0.3],
        duration: 0.5,
    });
    let fixed = lonely(sys, &pins, &[grabbed]);
    for (k, pin) in [(grabbed, path), (fixed, Pin::Fixed(sys.positions()[fixed]))] {
        hand.set_pin(k, Some(pin.clone())).unwrap();
        fam.set_pin(k, Some(pin.clone())).unwrap();
        pins[k] = Some(pin);
    }
    for t in [0.3, 0.45, 0.3] {
        assert_same_functions(&format!("{what}, grabbed"), sys, &pins, &hand, &fam, t, r);
    }
    // A neighbour of the fixed particle cannot be pinned (the link between them would
    // lose its free end); a particle out of range does not exist.
    let neighbour = sys
        .links()
        .iter()
        .find_map(|l| {
            (l.a == fixed)
                .then_some(l.b)
                .or((l.b == fixed).then_some(l.a))
        })
        .unwrap();
    let both = Some(Pin::Fixed([0.0; 3]));
    assert_eq!(
        hand.set_pin(neighbour, both.clone()),
        fam.set_pin(neighbour, both.clone())
    );
    assert!(fam.set_pin(neighbour, both.clone()).is_err());
    let n = sys.n_particles();
    assert_eq!(hand.set_pin(n, None), fam.set_pin(n, None));
    // A link left out because both its ends are pinned stays out.
    if let Some(l) = (0..sys.links().len()).find(|&l| fam.constraint_of_link(l).is_none()) {
        let a = sys.links()[l].a;
        assert!(fam.set_pin(a, None).is_err());
        assert_eq!(hand.set_pin(a, None), fam.set_pin(a, None));
    }
    hand.set_pin(grabbed, None).unwrap();
    fam.set_pin(grabbed, None).unwrap();
    pins[grabbed] = None;
    for t in [0.5, 1.1] {
        assert_same_functions(&format!("{what}, released"), sys, &pins, &hand, &fam, t, r);
    }
}

/// The scenes' models generated from the family models (`chain.dae`; `c2_hair.dae`,
/// whose roots follow their inputs driven by the head's sway; `c3_cloth.dae` pinned
/// three ways) are the hand-written particle models of the same scenes, as built and
/// with particles grabbed, fixed and released.
#[test]
fn the_generated_scene_models_are_the_hand_written_ones_through_grabs_and_releases() {
    let mut r = Lcg(11);
    for (n, ratio) in [(4, 1.0), (6, 1e2), (10, 1e4)] {
        let sys = chain(n, ratio).unwrap();
        let fam = generated_chain(&sys, n, ratio).unwrap();
        check_scene(&format!("C1 N={n} r={ratio}"), &sys, fam, &mut r);
    }
    let sys = strands(3, 4).unwrap();
    check_scene(
        "C2 3x4",
        &sys,
        generated_strands(&sys, 3, 4).unwrap(),
        &mut r,
    );
    for (w, pins, shear, slack) in [
        (5, GridPins::Corners, false, FAR_EDGE_SLACK),
        (5, GridPins::Edge, false, FAR_EDGE_SLACK),
        (5, GridPins::CornersHeavy, false, FAR_EDGE_SLACK),
        (5, GridPins::Corners, false, 1e-3),
    ] {
        let sys = grid_with_slack(w, pins, shear, slack).unwrap();
        let fam = generated_grid(&sys, w, pins, shear, slack).unwrap();
        check_scene(
            &format!("C3 W={w} {pins:?} shear={shear} slack={slack}"),
            &sys,
            fam,
            &mut r,
        );
    }
}

/// A motion that breaks down after one second.
#[derive(Debug)]
struct Breaks;
impl Motion for Breaks {
    fn at(&self, t: f64) -> Kinematics {
        let x = if t < 1.0 { 0.5 } else { f64::NAN };
        Kinematics {
            pos: [x, 0.0, 0.0],
            ..Kinematics::default()
        }
    }
}

/// A family model of another scene (other sizes, pins or masses) is refused with what
/// differs; a pin whose motion stops giving numbers makes the evaluations NaN (which
/// the simulator reports) instead of leaving the input where it was.
#[test]
fn a_generated_model_of_another_scene_is_refused_and_a_broken_pin_is_loud() {
    let corners = grid(5, GridPins::Corners, false).unwrap();
    let e = generated_grid(&corners, 5, GridPins::Edge, false, FAR_EDGE_SLACK).unwrap_err();
    assert!(e.contains("particle") && e.contains("starts at"), "{e}");
    let e = generated_grid(&corners, 5, GridPins::CornersHeavy, false, FAR_EDGE_SLACK).unwrap_err();
    assert!(e.contains("particle 0 accelerates"), "{e}");
    let e = generated_grid(&corners, 5, GridPins::Corners, true, FAR_EDGE_SLACK).unwrap_err();
    assert!(e.contains("constraints"), "{e}");
    // The same numbers of particles and links, other links: the first one that differs.
    let mut swapped = grid(5, GridPins::Corners, false).unwrap().links().to_vec();
    swapped.swap(0, 1);
    let edges: Vec<(usize, usize)> = swapped.iter().map(|l| (l.a, l.b)).collect();
    let other = System::from_edges(
        corners.positions().to_vec(),
        corners.masses().to_vec(),
        &edges,
    )
    .unwrap()
    .with_fixed(20)
    .unwrap()
    .with_fixed(24)
    .unwrap();
    let e = generated_grid(&other, 5, GridPins::Corners, false, FAR_EDGE_SLACK).unwrap_err();
    assert!(
        e.contains("constraint 0") && e.contains("is not link 0"),
        "{e}"
    );
    // Another slack: the far edge starts elsewhere.
    let e = generated_grid(&corners, 5, GridPins::Corners, false, 1e-3).unwrap_err();
    assert!(e.contains("particle") && e.contains("starts at"), "{e}");
    let e = generated_grid(&corners, 4, GridPins::Corners, false, FAR_EDGE_SLACK).unwrap_err();
    assert!(e.contains("states"), "{e}");
    let e = generated_strands(&strands(3, 4).unwrap(), 5, 2).unwrap_err();
    assert!(e.contains("starts at"), "{e}");

    let sys = chain(4, 1.0).unwrap();
    let mut fam = generated_chain(&sys, 4, 1.0).unwrap();
    fam.set_pin(2, Some(Pin::moving(Breaks))).unwrap();
    let mut x = vec![0.0; fam.n_states()];
    fam.initial_state(&mut x);
    let z = vec![0.0; 4];
    let mut f = vec![0.0; x.len()];
    fam.rhs(0.5, &x, &z, &mut f);
    assert!(f.iter().all(|v| v.is_finite()));
    fam.rhs(1.5, &x, &z, &mut f);
    assert!(f.iter().all(|v| v.is_nan()), "{f:?}");
}

/// C4's grab and release on the generated cloth, shortened: a 6 x 6 cloth, the middle
/// particle of the near edge grabbed during the fall (frame 6), moved 0.1 m along +x
/// and +z over 0.3 s on the scene's path, held, released at frame 30, 0.6 s in all.
///
/// At the grab and at the release the particle's acceleration jumps (to the hand's, then
/// to its link tensions over its own 14 g), so `w''` of its links would jump and `s`
/// with it; the backend moves the tensions so that `s` is continuous
/// (`Simulator::change_model`). Every link stays within 1.05 eps at every frame, no
/// s-layer is left, the particle is where its path ends when released and moves with the
/// cloth afterwards, on the hand-written and the generated model alike (the same worst
/// strain within 10 %). Without the carried tensions the release left the bound: 6.6e-2
/// at eps = 1e-3 for five frames.
#[test]
fn a_short_c4_grab_and_release_on_the_generated_cloth_holds_the_bound_as_the_hand_written_model() {
    // Frames of the grab, the release and the end.
    let (fa, fr, fe) = (6, 30, 36);
    let mut scene = c4(6).unwrap();
    scene.duration = fe as f64 * FRAME;
    let grab = scene.grab.as_mut().unwrap();
    (grab.at, grab.duration, grab.release) = (fa as f64 * FRAME, 0.3, fr as f64 * FRAME);
    grab.offset = [0.1, 0.0, 0.1];
    let grab = *grab;
    let (bounds, pilot) = particle_pilot(&scene, 64, Duration::from_secs(60)).unwrap();
    assert!(pilot.complete(), "{}", pilot.status);
    let eps = 1e-3;
    let mut worst = Vec::new();
    for spec in [
        MethodSpec::Dbsmc {
            eps,
            solver: SolverChoice::Auto,
            integrator: Integrator::Rk4,
        },
        MethodSpec::DbsmcGenerated {
            eps,
            integrator: Integrator::Rk4,
        },
    ] {
        let links = scene.system.links().to_vec();
        let mut frames = Vec::new();
        let mut obs = |_: u64, p: &[[f64; 3]]| {
            frames.push((p[grab.particle], dae_particles::worst_strain(&links, p).0))
        };
        let r = run_particle_method(
            &scene,
            &spec,
            Some(&bounds),
            Duration::from_secs(120),
            None,
            Some(&mut obs),
        );
        let what = spec.method();
        assert!(r.complete(), "{what}: {}", r.status);
        assert_eq!(frames.len(), fe + 1);
        for (f, &(_, strain)) in frames.iter().enumerate() {
            assert!(strain <= 1.05 * eps, "{what}: strain {strain} at frame {f}");
        }
        assert_eq!(r.counters.layer_lost_at(), None, "{what}");
        let (p0, at_release, end) = (frames[fa].0, frames[fr].0, frames[fe].0);
        for c in 0..3 {
            let target = p0[c] + grab.offset[c];
            assert!(
                (at_release[c] - target).abs() < 1e-9,
                "{what}: held at {at_release:?}, the path ends at {target}"
            );
        }
        assert!(
            dae_particles::distance(at_release, end) > 1e-2,
            "{what}: released, it moves with the cloth: {at_release:?} -> {end:?}"
        );
        worst.push(r.worst_strain);
    }
    let (hand, generated) = (worst[0], worst[1]);
    assert!(
        (generated - hand).abs() <= 0.1 * hand,
        "worst strain: hand-written {hand}, generated {generated}"
    );
}

/// The frame-tied design with `v` ramped (`dbsmc-ramp-generated`, no pilot) on the
/// generated heavy-ended chain and on a short grab and release of the generated cloth:
/// every link within 1.05 eps at every frame, no s-layer left, and the run follows the
/// hand-written model's (`dbsmc-ramp`): as many control updates within 10 %,
/// and the tracked particle (the chain's end, the grabbed particle) at the end within a
/// thousandth of the distance it moved (measured: the same updates, 218 and 141, and
/// 1e-8 and 7e-6 of it).
#[test]
fn the_frame_tied_design_on_the_generated_models_holds_and_follows_the_hand_written_model() {
    let mut cloth = c4(6).unwrap();
    let (fa, fr, fe) = (6, 24, 30);
    cloth.duration = fe as f64 * FRAME;
    let grab = cloth.grab.as_mut().unwrap();
    (grab.at, grab.duration, grab.release) = (fa as f64 * FRAME, 0.2, fr as f64 * FRAME);
    grab.offset = [0.1, 0.0, 0.1];
    let mut chain = c1(10, 1e2).unwrap();
    chain.duration = 60.0 * FRAME;
    for (scene, eps) in [(&chain, 1e-3), (&cloth, 1e-2)] {
        let links = scene.system.links().to_vec();
        let mut runs = Vec::new();
        for spec in [
            MethodSpec::DbsmcRamped { eps, gain: 4.0 },
            MethodSpec::DbsmcRampGenerated { eps, gain: 4.0 },
        ] {
            let what = format!("{} {}", scene.title(), spec.method());
            let mut tracked = Vec::new();
            let mut obs = |f: u64, p: &[[f64; 3]]| {
                let strain = dae_particles::worst_strain(&links, p).0;
                assert!(strain <= 1.05 * eps, "{what}: strain {strain} at frame {f}");
                tracked.push(p[scene.tracked]);
            };
            let r = run_particle_method(
                scene,
                &spec,
                None,
                Duration::from_secs(120),
                None,
                Some(&mut obs),
            );
            assert!(r.complete(), "{what}: {}", r.status);
            assert_eq!(r.eps, Some(eps), "{what}: the record carries its bound");
            assert_eq!(r.counters.layer_lost_at(), None, "{what}");
            runs.push((r.counters.updates(), tracked));
        }
        let (hand, generated) = (&runs[0], &runs[1]);
        let title = scene.title();
        let ratio = generated.0 as f64 / hand.0 as f64;
        assert!(
            (ratio - 1.0).abs() <= 0.1,
            "{title}: {} updates on the generated model, {} on the hand-written",
            generated.0,
            hand.0
        );
        let moved = dae_particles::distance(hand.1[0], *hand.1.last().unwrap());
        let apart = dae_particles::distance(*generated.1.last().unwrap(), *hand.1.last().unwrap());
        assert!(
            apart <= 1e-3 * moved,
            "{title}: the tracked particle ends {apart} m from the hand-written model's (moved {moved} m)"
        );
    }
}

//! The particle model against the generated scalar chain, and the particle baselines
//! (XPBD, index-1) against a reference on a tiny chain.

use dae_runtime::settings::{GainRule, InLayer};
use std::time::Duration;

use dae_bench::{
    generated::Chain5, particle_bench::MethodSpec, particle_bench::ParticleRecord,
    particle_bench::ParticleScene, particle_bench::RELAXED_DRIFT_SAFETY,
    particle_bench::RELAXED_GRAZE_PER_MU, particle_bench::RELAXED_MU_PER_FRAME,
    particle_bench::RELAXED_STEP_PER_MU, particle_bench::RELAXED_TOLERANCE_PER_EPS,
    particle_bench::c1, particle_bench::c3_with_slack, particle_bench::drive_scene,
    particle_bench::ramped, particle_bench::relaxed_settings, particle_bench::run_particle_method,
    particle_bench::run_relaxed_with, particle_methods::IndexOneParticles,
    particle_methods::SweepOrder, particle_methods::Xpbd, particles::Lcg,
};
use dae_particles::{
    Backend, Dbsmc, FAR_EDGE_SLACK, FRAME, GridPins, ParticleDae, ParticleModel, Scene, System,
    chain,
};
use dae_runtime::{Model, Settings, settings::Integrator, solve::SolverChoice};

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
        let xg: Vec<f64> = (0..20).map(|_| 2.0 * r.signed()).collect();
        let z: Vec<f64> = (0..5).map(|_| 5.0 * r.signed()).collect();
        let mu: Vec<f64> = (0..5).map(|_| 0.01 + 0.2 * (r.signed() + 1.0)).collect();
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
        .map(|&k| {
            end_after(
                &sys,
                Xpbd::new(&sys, k, 1, SweepOrder::System).unwrap(),
                frames,
            )
        })
        .collect();
    for w in runs.windows(2) {
        assert!(w[1].1 < w[0].1, "stretch must fall with substeps: {runs:?}");
    }
    let errors: Vec<f64> = runs.iter().map(|r| dist(r.0, reference)).collect();
    assert!(errors[3] < errors[0] && errors[3] < 5e-3, "{errors:?}");
    // One step of more iterations stretches less, too.
    let (_, s4) = end_after(
        &sys,
        Xpbd::new(&sys, 1, 4, SweepOrder::System).unwrap(),
        frames,
    );
    let (_, s64) = end_after(
        &sys,
        Xpbd::new(&sys, 1, 64, SweepOrder::System).unwrap(),
        frames,
    );
    assert!(s64 < s4, "{s4} vs {s64}");
}

#[test]
fn dbsmc_keeps_its_bound_on_a_tiny_chain_through_the_harness() {
    let scene = c1(3, 1.0).unwrap();
    let mut short = scene.clone();
    short.duration = 0.5;
    let (bounds, pilot) =
        dae_bench::particle_bench::particle_pilot(&short, 64, Duration::from_secs(60)).unwrap();
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
        assert!(r.counters.updates() > 0 && r.counters.f_evals > 0);
    }
    // The driver counts the frames of the scene.
    let r = drive_scene(
        &short,
        &MethodSpec::XpbdSubsteps(4),
        Xpbd::new(&short.system, 4, 1, SweepOrder::System).unwrap(),
        Duration::from_secs(60),
        None,
        None,
    );
    assert_eq!((r.frames, r.frames_total), (30, 30));
    assert!((r.frames as f64 * FRAME - 0.5).abs() < 1e-12);
}

/// The relaxed design is what `relaxed_settings` says (one `mu` a quarter of a frame,
/// gains from `k_i = gain eps_i / mu` up, following the drift as far as grazing returns
/// `mu / 8` apart need, exact alpha,
/// Dormand-Prince with steps of at most `mu / 2` at a tolerance of a tenth of the
/// smallest layer), and on a chain whose end is 10^4
/// times heavier than its particles it holds its layer and the strain for a second
/// without a pilot. (It is not cheaper there than a design from a pilot of that same
/// second: 7,831 against 3,364 updates, measured; over the whole 5 s scene, where the
/// pilot design leaves its layer, see docs/particles.md.)
#[test]
fn the_relaxed_design_holds_a_heavy_end_chain_without_a_pilot() {
    let mut scene = c1(10, 1e4).unwrap();
    scene.duration = 1.0;
    let eps = 1e-3;
    let model = ParticleModel::new(&scene.system).unwrap();
    let st = relaxed_settings(&model, eps, 8.0);
    let mu = RELAXED_MU_PER_FRAME * FRAME;
    for i in 0..model.n_constraints() {
        let e = eps * model.rest_length(i);
        assert_eq!((st.layers.eps[i], st.layers.mu[i]), (e, mu));
        assert!((st.layers.gains[i] - 8.0 * e / mu).abs() <= 1e-15 * st.layers.gains[i]);
    }
    assert_eq!(st.integration.integrator, Integrator::DormandPrince);
    assert_eq!(st.alpha, dae_runtime::settings::AlphaChoice::Exact);
    assert_eq!(st.integration.max_step, RELAXED_STEP_PER_MU * mu);
    let min_eps = st.layers.eps.iter().copied().fold(f64::INFINITY, f64::min);
    let tol = RELAXED_TOLERANCE_PER_EPS * min_eps;
    assert_eq!(
        st.integration.tolerance,
        Some(dae_runtime::settings::Tolerance {
            rtol: tol,
            atol: tol
        })
    );
    assert_eq!(
        st.law.follows_drift(),
        Some((RELAXED_DRIFT_SAFETY, Some(RELAXED_GRAZE_PER_MU * mu)))
    );
    assert!(st.law.saturates() && !st.law.ramps());

    let relaxed = run_particle_method(
        &scene,
        &MethodSpec::DbsmcRelaxed { eps, gain: 8.0 },
        None,
        Duration::from_secs(120),
        None,
        None,
    );
    assert!(relaxed.complete(), "{}", relaxed.status);
    assert!(
        relaxed.worst_strain <= 1.05 * eps,
        "{}",
        relaxed.worst_strain
    );
    assert_eq!(relaxed.counters.layer_lost_at(), None);
    assert!(
        relaxed.t_min.is_none(),
        "the relaxed design guarantees no period"
    );
}

/// A run of the frame-tied design (`what` names it in the failure) ran its whole scene,
/// kept its `s`-layer (the runtime's monitor) and held its strain within 1.05 `eps`.
fn assert_held(r: &ParticleRecord, eps: f64, what: &str) {
    assert!(r.complete(), "{what}: {}", r.status);
    assert_eq!(r.counters.layer_lost_at(), None, "{what}");
    assert!(r.worst_strain <= 1.05 * eps, "{what}: {}", r.worst_strain);
}

/// The heavy-ended 10-link chain (end mass 1e4) at eps = 1e-2, the frame-tied design
/// with its gains fixed at the floor `8 eps / mu` and with them following the drift (as
/// far as grazing needs, the design):
/// both keep the layer and the strain over the whole 5 s. The fixed gains graze the
/// layer, with located returns that come every few microseconds while the end whips;
/// they left it (0.330 s, 12 eps, and the strain with it) while a step was taken as
/// ending at its event when the event's variable came back to its level by the step's
/// end after a dip beyond it, and (0.511 s) when another variable crossed its level
/// later in the same step. The runtime's monitor is the judge of the layer; the strain
/// is measured on the positions, independently of `s`.
#[test]
fn fixed_and_followed_gains_keep_the_layer_on_the_heavy_end_chain() {
    let scene = c1(10, 1e4).unwrap();
    let (eps, gain) = (1e-2, 8.0);
    for follow in [false, true] {
        let run = relaxed_run(&scene, eps, gain, follow);
        assert_held(&run, eps, &format!("follow {follow}"));
    }
}

/// The frame-tied design's gains graze their layers (raised over the floor `4 eps / mu`
/// only as far as returns `mu / 8` apart need) instead of sweeping them (raised to `2
/// sqrt(eps D)`): on the heavy-end 10-link chain at eps = 1e-3 over 1 s both keep the
/// layer and the strain, and grazing makes about half the updates (measured: 1,048
/// against 2,656 with the design's saturation; with `sgn(s)` in the law, over the whole
/// 5 s with the longest step `mu / 4`, 23 against 143 per frame).
#[test]
fn grazing_gains_keep_the_layer_with_fewer_updates_than_sweeping_ones() {
    let mut scene = c1(10, 1e4).unwrap();
    scene.duration = 1.0;
    let eps = 1e-3;
    let run = |graze: bool| {
        run_relaxed_with(&scene, eps, 4.0, Duration::from_secs(120), |s| {
            assert!(s.law.follows_drift().is_some_and(|(_, g)| g.is_some()));
            if graze {
                s
            } else {
                with_law(s, |d| {
                    if let GainRule::FollowDrift { graze, .. } = &mut d.gains {
                        *graze = None;
                    }
                })
            }
        })
    };
    let (grazing, sweeping) = (run(true), run(false));
    for (what, r) in [("grazing", &grazing), ("sweeping", &sweeping)] {
        assert_held(r, eps, what);
    }
    assert!(
        3 * grazing.counters.updates() < 2 * sweeping.counters.updates(),
        "updates: grazing {}, sweeping {}",
        grazing.counters.updates(),
        sweeping.counters.updates()
    );
}

/// `v` ramping against the drift between updates (`Settings::ramp_against_drift`) on
/// the light 100-link chain at eps = 1e-3 over its first second: the layer and the
/// strain are kept, with fewer updates than with `v` held (measured: 428 against 1,094;
/// over the whole 5 s with the longest step `mu / 4`, 300 against 851 per frame).
#[test]
fn a_ramp_against_the_drift_keeps_the_layer_with_fewer_updates_on_a_light_chain() {
    let mut scene = c1(100, 1.0).unwrap();
    scene.duration = 1.0;
    let eps = 1e-3;
    let run = |ramp: bool| {
        run_relaxed_with(&scene, eps, 4.0, Duration::from_secs(120), |s| {
            if ramp { ramped(s) } else { s }
        })
    };
    let (held, ramped) = (run(false), run(true));
    for (what, r) in [("held", &held), ("ramped", &ramped)] {
        assert_held(r, eps, what);
    }
    assert!(
        5 * ramped.counters.updates() < 4 * held.counters.updates(),
        "updates: ramped {}, held {}",
        ramped.counters.updates(),
        held.counters.updates()
    );
}

/// The frame-tied design asks a link inside its layer for the rate `-k s / eps`
/// (`Settings::saturate_in_layer`) instead of the method's `-k sgn(s)`: on a 10-link chain
/// over 1 s at eps = 1e-3, held and ramped, the layer and the strain are kept with
/// fewer updates than with `sgn` (measured: held 703 against 1,024, ramped 213
/// against 876).
#[test]
fn saturating_inside_the_layer_keeps_it_with_fewer_updates_on_a_chain() {
    let mut scene = c1(10, 1.0).unwrap();
    scene.duration = 1.0;
    let eps = 1e-3;
    for ramp in [false, true] {
        let run = |saturate: bool| {
            run_relaxed_with(&scene, eps, 4.0, Duration::from_secs(120), |s| {
                let s = with_law(s, |d| d.in_layer = in_layer(saturate));
                if ramp { ramped(s) } else { s }
            })
        };
        let (sat, sgn) = (run(true), run(false));
        for (what, r) in [("saturated", &sat), ("sgn", &sgn)] {
            assert_held(r, eps, &format!("{what}, ramp {ramp}"));
        }
        assert!(
            5 * sat.counters.updates() < 4 * sgn.counters.updates(),
            "ramp {ramp}: updates saturated {}, sgn {}",
            sat.counters.updates(),
            sgn.counters.updates()
        );
    }
}

/// The 16 x 16 cloth (C3 (a)) whose far edge has `slack`, 0.2 s ramped at eps = 1e-2,
/// the law saturated inside the layer (the design's) or with `sgn(s)`: its record, how
/// many updates each link asked for, and the links' ends.
fn cloth_ramped(slack: f64, saturate: bool) -> (ParticleRecord, Vec<u64>, Vec<(usize, usize)>) {
    let mut scene = c3_with_slack(16, GridPins::Corners, false, slack).unwrap();
    scene.duration = 0.2;
    let model = ParticleModel::new(&scene.system).unwrap();
    let ends = model.ends().to_vec();
    let settings = with_law(ramped(relaxed_settings(&model, 1e-2, 4.0)), |d| {
        d.in_layer = in_layer(saturate)
    });
    let mut backend = Dbsmc::new(model, settings, "ramped")
        .unwrap()
        .keep_going_after_bound_loss();
    let spec = MethodSpec::DbsmcRamped {
        eps: 1e-2,
        gain: 4.0,
    };
    let r = drive_scene(
        &scene,
        &spec,
        &mut backend,
        Duration::from_secs(120),
        None,
        None,
    );
    assert!(
        r.complete(),
        "slack {slack}, saturate {saturate}: {}",
        r.status
    );
    assert_eq!(
        r.counters.layer_lost_at(),
        None,
        "slack {slack}, saturate {saturate}"
    );
    assert_eq!(r.counters.factorisations, r.counters.updates());
    (r, backend.triggered_updates().to_vec(), ends)
}

/// The updates asked for by the links with a particle in the far row (`iy = W - 1`)
/// of a `w x w` cloth, and by all links.
fn far_edge_asks(w: usize, asked: &[u64], ends: &[(usize, usize)]) -> (u64, u64) {
    let far = |p: usize| p / w == w - 1;
    let at_edge = ends
        .iter()
        .zip(asked)
        .filter(|((a, b), _)| far(*a) || far(*b))
        .map(|(_, n)| n)
        .sum();
    (at_edge, asked.iter().sum())
}

/// The counters of a DBSMC run: one factorisation per control update (no pin changes
/// here), and on a cloth whose far edge has less slack (0.1 %) than the layers' strain
/// (1 %) only a few of the links ask for the updates: those at the far edge between
/// the pinned corners, which can come straight (and `J_Omega` singular) within the
/// layers (docs/particles.md). The oracle of "which" is the geometry: the particles of
/// the far row, `iy = W - 1`.
#[test]
fn on_a_nearly_taut_cloth_a_few_links_ask_for_every_update_and_each_update_factors_once() {
    let w = 16;
    let (r, asked, ends) = cloth_ramped(1e-3, true);
    let c = r.counters;
    assert!(c.updates() > 12, "{} updates", c.updates());
    let links = ends.len() as u64;
    eprintln!(
        "{} of {links} links asked for the {} updates",
        c.links_asking(),
        c.updates()
    );
    assert!(
        c.links_asking() > 0 && 10 * c.links_asking() < links,
        "{} of {links} links asked",
        c.links_asking()
    );
    // Per link: the counts agree with the counter, and the links with a particle in
    // the far row asked for most of them.
    let asking = asked.iter().filter(|&&n| n > 0).count() as u64;
    assert_eq!(asking, c.links_asking());
    let (at_edge, all) = far_edge_asks(w, &asked, &ends);
    // Every update but the one at the start was asked for by at least one link.
    assert!(
        all + 1 >= c.updates(),
        "{all} asks for {} updates",
        c.updates()
    );
    eprintln!("{at_edge} of the {all} asks came from links at the far edge");
    assert!(
        5 * at_edge >= 4 * all,
        "{at_edge} of {all} asks from links at the far edge"
    );
}

/// With the scene's slack (2 %, above the layers' 1 %) the far edge no longer comes
/// straight within the layers: the same run makes fewer updates than with 0.1 %. With
/// `sgn(s)` in the law (measured: 191 against 306 updates) the far edge's links then no
/// longer ask for nearly all of them, as they do with 0.1 % (at least four in five, the
/// test above): about half (106 of 201 asks; from 49 of 217 to 126 of 201 over seven
/// runs with eps moved by -3 % ... +3 %: the share is one draw from 23-63 %, and the
/// test asks for less than three in four). With the design's saturation (57 against 72)
/// the links elsewhere sit near the middle of their layers, and the far edge's, the most
/// strained, still ask for all of them (112 of 112 asks).
#[test]
fn a_far_edge_with_slack_above_the_layers_asks_for_fewer_updates() {
    let w = 16;
    for saturate in [false, true] {
        let (taut, _, _) = cloth_ramped(1e-3, saturate);
        let (slack, asked, ends) = cloth_ramped(FAR_EDGE_SLACK, saturate);
        let (u_slack, u_taut) = (slack.counters.updates(), taut.counters.updates());
        if saturate {
            assert!(
                u_slack < u_taut,
                "saturated: slack 2 % {u_slack}, 0.1 % {u_taut}"
            );
        } else {
            assert!(
                4 * u_slack < 3 * u_taut,
                "sgn: slack 2 % {u_slack}, 0.1 % {u_taut}"
            );
        }
        if !saturate {
            let (at_edge, all) = far_edge_asks(w, &asked, &ends);
            assert!(
                4 * at_edge < 3 * all,
                "sgn: {at_edge} of {all} asks from links at the far edge"
            );
        }
    }
}

/// A gain below the drift's `2 sqrt(eps D)` grazes the layer (`s` turns back inside the
/// side it left and returns to the same level), which located crossings keep: fixed
/// gains on the light 10-link chain at eps = 1e-4 hold the layer and the strain for the
/// whole 5 s. They left it at 1.398 s while the root search of a return to the level a
/// step started on took its side from the step's start (which rounding may put a hair
/// beyond the level) and accepted wherever it stopped; either fix alone (the side from
/// the cubic's motion at the event, `Cubic::side_before`, or a cut at the cubic's event
/// when no root is found) keeps this run in its layer.
#[test]
fn fixed_gains_that_graze_the_layer_keep_it_on_a_light_chain() {
    let scene = c1(10, 1.0).unwrap();
    let eps = 1e-4;
    let fixed = relaxed_run(&scene, eps, 8.0, false);
    assert!(fixed.complete(), "{}", fixed.status);
    assert_eq!(fixed.counters.layer_lost_at(), None);
    assert!(fixed.worst_strain <= 1.05 * eps, "{}", fixed.worst_strain);
}

/// Fixed gains on the heavy-end chain with steps of at most a sixteenth of the design's
/// longest (`relaxed_design`'s row "max step x 0.0625") keep the layer for the whole
/// 5 s. They left it twice: at 0.727 s, where a step started on the level (1.08e-4 of it
/// beyond, within the crossing tolerance), moved inside, then out through the level,
/// and the root search, bracketed by the whole step, found the start's crossing, so
/// the steps were cut ever shorter at their start until the progress guard took one
/// whole, blind (2.9 eps); and at 3.966 s, where a step counted as ending at the start
/// of an outward motion because its end came back near that value after an excursion
/// to 1.05 eps between them.
#[test]
fn fixed_gains_with_short_steps_keep_the_layer_on_the_heavy_end_chain() {
    let scene = c1(10, 1e4).unwrap();
    let eps = 1e-2;
    let run = run_relaxed_with(&scene, eps, 8.0, Duration::from_secs(240), |s| {
        let h = s.integration.max_step / 16.0;
        with_law(s, |d| d.gains = GainRule::Fixed).max_step(h)
    });
    assert!(run.complete(), "{}", run.status);
    assert_eq!(run.counters.layer_lost_at(), None);
    assert!(run.worst_strain <= 1.05 * eps, "{}", run.worst_strain);
}

/// The frame-tied design on `scene` for 5 s, its gains following the drift or fixed at
/// the floor, going on after a lost layer (to see the strain).
fn relaxed_run(scene: &ParticleScene, eps: f64, gain: f64, follow: bool) -> ParticleRecord {
    run_relaxed_with(scene, eps, gain, Duration::from_secs(120), |s| {
        if follow {
            s
        } else {
            with_law(s, |d| d.gains = GainRule::Fixed)
        }
    })
}

/// The wall budget holds inside a frame: the DBSMC backend stops at the deadline within
/// its first frame (status `budget`, no frame counted, nothing called a failure), while
/// XPBD, whose frames cost a bounded amount, finishes its first frame and stops after
/// it. Found on C4 W=8 (the pilot-based design, RK4, eps = 1e-3): during the grab's move
/// its updates came 0.1-1 ns apart from t = 1.442 s, and the run, whose budget was
/// checked only between frames, had not finished its frame after 13 min.
#[test]
fn the_budget_stops_a_run_inside_a_frame() {
    let scene = c1(10, 1.0).unwrap();
    let (bounds, pilot) =
        dae_bench::particle_bench::particle_pilot(&scene, 64, Duration::from_secs(60)).unwrap();
    assert!(pilot.complete(), "{}", pilot.status);
    let spec = MethodSpec::Dbsmc {
        eps: 1e-3,
        solver: SolverChoice::Auto,
        integrator: Integrator::Rk4,
    };
    let r = run_particle_method(&scene, &spec, Some(&bounds), Duration::ZERO, None, None);
    assert_eq!(r.status, "budget");
    assert_eq!(r.frames, 0);
    let r = run_particle_method(
        &scene,
        &MethodSpec::XpbdSubsteps(4),
        None,
        Duration::ZERO,
        None,
        None,
    );
    assert_eq!(r.status, "budget");
    assert_eq!(r.frames, 1);
}

/// The largest energy gain over `frames` frames of XPBD with one substep per frame in
/// `order`, in units of `M g 1 m` (`M` the free mass).
fn xpbd_energy_gain(sys: &System, order: SweepOrder, frames: u64) -> f64 {
    let mut b = Xpbd::new(sys, 1, 1, order).unwrap();
    let n = sys.n_particles();
    let (mut x, mut v) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    let e0 = sys.energy(sys.positions(), sys.velocities());
    // The benchmark's scale of the energy drift: the free mass times g times 1 m.
    let scale = sys.free_mass() * 9.81;
    let mut gain = f64::NEG_INFINITY;
    for f in 1..=frames {
        b.advance_to(f as f64 * FRAME).unwrap();
        b.positions(&mut x);
        b.velocities(&mut v);
        gain = gain.max((sys.energy(&x, &v) - e0) / scale);
    }
    gain
}

#[test]
fn xpbd_swept_by_colour_loses_energy_where_the_grid_builders_order_gains_it() {
    // The 64 x 64 cloth pinned at two corners, one substep of one sweep per frame, 5 s:
    // in the builder's order (a particle's x link, then its y link) one sweep turns
    // corrections into velocity faster than it takes them out, by colour it does not.
    let sys = c3_with_slack(64, GridPins::Corners, false, FAR_EDGE_SLACK)
        .unwrap()
        .system;
    let coloured = xpbd_energy_gain(&sys, SweepOrder::Coloured, 300);
    let system = xpbd_energy_gain(&sys, SweepOrder::System, 300);
    assert!(coloured <= 1e-9, "coloured sweep gained {coloured} M g m");
    assert!(system > 1.0, "builder's order gained only {system} M g m");
}

/// Runs side by side on two threads (the benchmark's default, `parallel_map`) end as
/// they do one at a time: the same steps, updates, evaluations, frames, status and worst
/// strain to the bit, for every kind of method, with the results in the order asked.
/// Only the wall time may differ (docs/particles.md, "Running it").
#[test]
fn runs_on_two_threads_end_as_they_do_one_at_a_time() {
    let mut light = c1(10, 1.0).unwrap();
    light.duration = 0.2;
    let mut heavy = c1(10, 1e4).unwrap();
    heavy.duration = 0.2;
    let specs = [
        MethodSpec::XpbdColoured(16),
        MethodSpec::XpbdSubsteps(16),
        MethodSpec::XpbdIterations(16),
        MethodSpec::IndexOne(16),
        MethodSpec::DbsmcRelaxed {
            eps: 1e-3,
            gain: 4.0,
        },
        MethodSpec::DbsmcRamped {
            eps: 1e-2,
            gain: 4.0,
        },
        MethodSpec::DbsmcRampGenerated {
            eps: 1e-3,
            gain: 4.0,
        },
    ];
    let runs: Vec<(&ParticleScene, &MethodSpec)> = [&light, &heavy]
        .into_iter()
        .flat_map(|sc| specs.iter().map(move |spec| (sc, spec)))
        .collect();
    let run = |i: usize| {
        let (scene, spec) = runs[i];
        run_particle_method(scene, spec, None, Duration::from_secs(120), None, None)
    };
    let one = dae_bench::particle_bench::parallel_map(runs.len(), 1, run);
    let two = dae_bench::particle_bench::parallel_map(runs.len(), 2, run);
    for ((a, b), (scene, spec)) in one.iter().zip(&two).zip(&runs) {
        let what = format!("{} {} {}", scene.title(), spec.method(), spec.knob());
        assert!(a.complete(), "{what}: {}", a.status);
        assert_eq!((&a.method, &a.knob), (&b.method, &b.knob), "{what}: order");
        assert_eq!(a.counters, b.counters, "{what}");
        assert_eq!((a.frames, &a.status), (b.frames, &b.status), "{what}");
        assert_eq!(a.worst_strain.to_bits(), b.worst_strain.to_bits(), "{what}");
    }
}

/// `mu` searched for during the run (`Dbsmc::adapt_mu`, the benchmark's `dbsmc-adapt`):
/// on a 30-link chain whose free end whips, and on the grab of an 8 x 8 cloth (a pin
/// moved and released while `mu` moves), every move keeps `s` continuous, and the runs
/// keep their layers and their strain; the search asks for a move at the end of a
/// window of 4 frames (not when its pair of `mu` moved onto the one in use), and the
/// simulator makes at least half of them (measured: 40 on the chain, 74 on the grab,
/// none refused).
#[test]
fn a_searched_mu_moves_and_keeps_every_layer_and_the_strain() {
    let mut chain = c1(30, 1.0).unwrap();
    chain.duration = 3.0;
    let grab = dae_bench::particle_bench::c4(8).unwrap();
    for (scene, eps) in [(&chain, 1e-3), (&grab, 1e-2)] {
        let what = scene.title();
        let model = ParticleModel::new(&scene.system).unwrap();
        let settings = ramped(relaxed_settings(&model, eps, 4.0));
        let mut backend = Dbsmc::new(model, settings, "adaptive")
            .unwrap()
            .adapt_mu(dae_particles::AdaptiveMu::default())
            .unwrap()
            .keep_going_after_bound_loss();
        let spec = MethodSpec::DbsmcAdaptive { eps, gain: 4.0 };
        let r = drive_scene(
            scene,
            &spec,
            &mut backend,
            Duration::from_secs(300),
            None,
            None,
        );
        assert_held(&r, eps, &what);
        let (made, refused) = backend.mu_moves();
        // The record (and the CSV) says what the search did.
        let search = r.counters.mu_search().expect("the run searched for mu");
        assert_eq!((search.moves, search.refused), (made, refused), "{what}");
        assert_eq!(search.scale, backend.mu_scale(), "{what}");
        eprintln!(
            "{what}: {made} moves, {refused} refused, mu ends at {} of the start's",
            backend.mu_scale()
        );
        let windows = r.frames / 4;
        assert!(
            made + refused <= windows,
            "{what}: at most one move a window"
        );
        assert!(made >= windows / 2, "{what}: {made} of {windows}");
    }
    // An invalid search is an error that names its field.
    let model = ParticleModel::new(&chain.system).unwrap();
    let settings = relaxed_settings(&model, 1e-3, 4.0);
    let err = Dbsmc::new(model, settings, "adaptive")
        .unwrap()
        .adapt_mu(dae_particles::AdaptiveMu {
            step: 0.5,
            ..Default::default()
        })
        .unwrap_err();
    assert!(err.reason.contains("step"), "{}", err.reason);
}

/// `settings` (the frame-tied design's DBSMC law) with its law changed by `change`.
fn with_law(
    mut settings: Settings,
    change: impl FnOnce(&mut dae_runtime::settings::Dbsmc),
) -> Settings {
    change(
        settings
            .dbsmc_mut()
            .expect("the frame-tied design uses the DBSMC law"),
    );
    settings
}

fn in_layer(saturate: bool) -> InLayer {
    if saturate {
        InLayer::Saturate
    } else {
        InLayer::Sign
    }
}

//! Family models in a scene through [`FamilyParticles`]: the interpreted
//! `examples/models/chain.dae` run by [`Dbsmc::online`] follows the hand-written
//! [`ParticleModel`] of the same chain through a grab and a release, and a family
//! model of another scene is refused with what differs.

use dae_particles::{
    Backend, Dbsmc, FamilyParticles, FamilyParticlesError, ParticleModel, Scene, chain, distance,
};
use dae_runtime::family::{FamilyInstance, Interpreter, Spec};

/// `examples/models/chain.dae`, interpreted, at `links` links and end-mass ratio
/// `end_mass_ratio`.
fn chain_dae(links: usize, end_mass_ratio: f64) -> FamilyInstance<Interpreter> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/models/chain.dae");
    let src = std::fs::read_to_string(path).unwrap();
    let compiled = dae_lang::compile_source(&src).unwrap().remove(0);
    let spec = Spec {
        sizes: vec![("N".into(), links as i64)],
        params: vec![("m_end".into(), end_mass_ratio)],
        ..Spec::default()
    };
    FamilyInstance::interpreted(Interpreter::new(compiled), &spec).unwrap()
}

/// The frames of the fall before the grab.
const FALL: usize = 12;

/// The positions of every particle at the end of every frame: 12 frames of the fall,
/// the end grabbed and moved 5 cm up over 0.1 s, 12 frames, released, 12 frames.
fn run<B: Backend>(mut scene: Scene<B>, end: usize) -> Vec<Vec<[f64; 3]>> {
    let mut frames = vec![scene.positions().to_vec()];
    for part in 0..3 {
        match part {
            1 => drop(scene.grab(end, [0.0, 0.0, 0.05], 0.1).unwrap()),
            2 => scene.release(end).unwrap(),
            _ => {}
        }
        for _ in 0..FALL {
            scene.step().unwrap();
            frames.push(scene.positions().to_vec());
        }
    }
    frames
}

/// A heavy-ended chain of 6 links (end 100 times heavier) at eps = 1e-3 under the
/// one-call design, on the hand-written model and on `chain.dae` behind
/// `FamilyParticles`: the two models compute the same functions up to rounding, so
/// during the fall every particle is within 1e-11 m of where the other run has it
/// (measured: 6e-14), and through the grab and the release, whose switches the
/// control's updates and located crossings make sensitive to rounding, within 1e-6 m,
/// under a hundredth of a layer (measured: 1.6e-7 m, the end having moved 0.34 m).
/// Both hold the strain bound at every frame.
#[test]
fn the_online_design_on_the_family_chain_gives_the_hand_written_positions() {
    let (links, ratio, eps) = (6, 1e2, 1e-3);
    let system = chain(links, ratio).unwrap();
    let hand = Dbsmc::online(ParticleModel::new(&system).unwrap(), eps, "hand").unwrap();
    let family = FamilyParticles::new(chain_dae(links, ratio), &system).unwrap();
    let family = Dbsmc::online(family, eps, "chain.dae").unwrap();
    let (hand_scene, family_scene) = (
        Scene::new(&system, hand).unwrap(),
        Scene::new(&system, family).unwrap(),
    );
    let hand_frames = run(hand_scene, links);
    let family_frames = run(family_scene, links);
    assert_eq!(hand_frames.len(), family_frames.len());
    for (f, (h, g)) in hand_frames.iter().zip(&family_frames).enumerate() {
        for (k, (a, b)) in h.iter().zip(g).enumerate() {
            let d = distance(*a, *b);
            let within = if f <= FALL { 1e-11 } else { 1e-6 };
            assert!(
                d <= within,
                "frame {f}, particle {k}: {a:?} and {b:?}, {d} m apart"
            );
        }
        for positions in [h, g] {
            let (strain, link) = dae_particles::worst_strain(system.links(), positions);
            assert!(
                strain <= 1.05 * eps,
                "frame {f}: strain {strain} on link {link}"
            );
        }
    }
    // The chain moved: the comparison is not of two runs at rest.
    let moved = distance(
        hand_frames[0][links],
        *hand_frames.last().unwrap().get(links).unwrap(),
    );
    assert!(moved > 0.1, "the end moved {moved} m");
}

/// A family model sized for another chain (other link count: other states; the same
/// count with another end mass: the end accelerates otherwise) is refused, naming what
/// differs.
#[test]
fn a_family_model_of_another_chain_is_refused_with_what_differs() {
    let system = chain(6, 1e2).unwrap();
    let e = FamilyParticles::new(chain_dae(5, 1e2), &system).unwrap_err();
    assert!(
        matches!(
            e,
            FamilyParticlesError::States {
                states: 36,
                particles: 7,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("36 states"), "{e}");
    let e = FamilyParticles::new(chain_dae(6, 1.0), &system).unwrap_err();
    assert!(
        matches!(
            e,
            FamilyParticlesError::Acceleration {
                particle: 6,
                pinned: false,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("particle 6 accelerates"), "{e}");
}

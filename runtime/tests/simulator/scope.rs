//! Block-local updates (`Scope::Blocks`) on the 3-D double pendulum of docs/method.md
//! section 8: one block of both rows is the global policy, to the bit; blocks of one
//! row keep the layer and say what they did; the laws they cannot serve are refused.

use crate::common;

use common::pendulum::Pendulum;
use dae_runtime::settings::{Dbsmc, GainRule, Law, Reaching, Scope, StepEnd, Update};
use dae_runtime::{Settings, SimError, Simulator, Summary, trace::NoTrace};

const MU: [f64; 2] = [0.076, 0.066];
const BETA: [f64; 2] = [1.3e3, 2.3e3];
const EPS: f64 = 0.2;

fn monitor(scope: Scope) -> Update {
    Update::Monitor {
        reaching: Reaching::AttractingSurfaces,
        scope,
    }
}

fn scene(law: Law, t_end: f64) -> Settings {
    let gains = (0..2).map(|i| MU[i] * MU[i] * BETA[i]).collect();
    Settings::new(vec![EPS; 2], MU.to_vec(), gains)
        .step(1e-4)
        .law(law)
        .t_end(t_end)
        .settle(1.0)
        .reaching_limit(1.0)
}

fn run(settings: Settings) -> Result<Summary, SimError> {
    Simulator::new(Pendulum::default(), settings)?.run(&mut NoTrace)
}

#[test]
fn one_block_of_every_row_is_the_global_policy_to_the_bit() {
    for law in [
        |scope| Law::from(Dbsmc::default().update(monitor(scope))),
        |scope| {
            Law::from(StepEnd {
                update: monitor(scope),
                ..StepEnd::default()
            })
        },
    ] {
        let global = run(scene(law(Scope::Global), 3.0)).unwrap();
        let one = run(scene(law(Scope::Blocks { size: 2 }), 3.0)).unwrap();
        assert_eq!(global.x, one.x);
        assert_eq!(global.z, one.z);
        assert_eq!(
            (global.steps, global.updates, global.located_crossings),
            (one.steps, one.updates, one.located_crossings)
        );
        assert_eq!(global.blocks, None);
        let b = one.blocks.expect("the block counts");
        assert_eq!((b.blocks, b.largest), (1, 2));
        // The first update is of every row; every later one is the single block's.
        assert_eq!(b.global_updates, 1);
        assert_eq!(b.block_solves, one.updates - 1);
    }
}

#[test]
fn blocks_of_one_row_keep_the_layer_and_count_their_solves() {
    let s = run(scene(
        Dbsmc::default()
            .update(monitor(Scope::Blocks { size: 1 }))
            .into(),
        4.0,
    ))
    .unwrap();
    assert!(s.bound_held(), "{:?}", s.bound_loss);
    let worst = s.max_abs_s.as_ref().expect("the statistics window");
    for (i, w) in worst.iter().enumerate() {
        assert!(
            *w <= EPS * (1.0 + 1e-3) * (1.0 + 1e-9),
            "row {i}: max |s| {w}"
        );
    }
    let b = s.blocks.expect("the block counts");
    assert_eq!((b.blocks, b.largest), (2, 1));
    assert!(b.global_updates >= 1);
    // Each update of blocks solves at least one; the global ones none.
    assert!(
        b.block_solves >= s.updates - b.global_updates,
        "{b:?}, {} updates",
        s.updates
    );
    // Each row asked for its own updates: both blocks were solved.
    assert!(
        s.triggered_updates.iter().all(|&c| c > 0),
        "{:?}",
        s.triggered_updates
    );
}

#[test]
fn block_updates_refuse_gains_that_follow_the_drift_and_empty_blocks() {
    let follow = Dbsmc::default()
        .update(monitor(Scope::Blocks { size: 1 }))
        .gains(GainRule::FollowDrift {
            safety: 1.0,
            graze: None,
            raise: None,
        });
    match run(scene(follow.into(), 1.0)) {
        Err(SimError::Settings { field, reason }) => {
            assert_eq!(field, "scope");
            assert!(reason.contains("fixed gains"), "{reason}");
        }
        other => panic!("expected a settings error, got {other:?}"),
    }
    let empty = Dbsmc::default().update(monitor(Scope::Blocks { size: 0 }));
    match run(scene(empty.into(), 1.0)) {
        Err(SimError::Settings { field, reason }) => {
            assert_eq!(field, "scope");
            assert!(reason.contains(">= 1"), "{reason}");
        }
        other => panic!("expected a settings error, got {other:?}"),
    }
}

//! The simulator allocates nothing per step or per update: the number of heap
//! allocations of a run does not depend on its length.

#[path = "simulator/common/mod.rs"]
mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use common::pendulum::Pendulum;
use dae_runtime::settings::{AlphaChoice, Dbsmc, GainRule, Hold, Integrator, Law, StepEnd, Update};
use dae_runtime::solve::SolverChoice;
use dae_runtime::trace::NoTrace;
use dae_runtime::{Settings, Simulator};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// Count only the allocations of the thread running the simulation (the test
    /// harness allocates on its own threads now and then).
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_of_run(
    (update, alpha, solver, integrator, located): (
        Option<Update>,
        AlphaChoice,
        SolverChoice,
        Integrator,
        bool,
    ),
    t_end: f64,
) -> (u64, u64) {
    let p = Pendulum::default();
    let raise = (!solver.is_exact()).then_some(0.1);
    let law: Law = match (update, located) {
        (None, _) => Law::Spsm,
        (Some(update), false) => StepEnd {
            update,
            raise,
            ..StepEnd::default()
        }
        .into(),
        // Every run that can follow the drift, graze and ramp does (their buffers are
        // the simulator's).
        (Some(update), true) => Dbsmc::default()
            .update(update)
            .gains(GainRule::FollowDrift {
                safety: 1.0,
                graze: Some(0.01),
                raise,
            })
            .hold(Hold::RampAgainstDrift)
            .into(),
    };
    let settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .law(law)
        .alpha(alpha)
        .solver(solver)
        .integrator(integrator)
        .t_end(t_end);
    let mut sim = Simulator::new(&p, settings).unwrap();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    // In pieces, with a forced update between them (the particle scenes' use).
    sim.start(&mut NoTrace).unwrap();
    sim.advance_to(0.5 * t_end, &mut NoTrace).unwrap();
    sim.request_update();
    sim.advance_to(t_end, &mut NoTrace).unwrap();
    COUNTING.with(|c| c.set(false));
    // Not counted: the summary, whose allocations depend on what it reports (a loss
    // record with names), not on the run's length.
    let summary = sim.finish(&mut NoTrace).unwrap();
    (
        ALLOCATIONS.load(Ordering::Relaxed) - before,
        summary.updates,
    )
}

// A single test: the counter is global, and tests in one binary run in parallel.
#[test]
fn run_allocations_do_not_grow_with_steps_or_updates() {
    let (rk4, located) = (Integrator::Rk4, true);
    let fixed = Some(Update::Fixed { period: 0.005 });
    let monitor = Some(Update::default());
    let cheap = AlphaChoice::Cheap;
    for case in [
        (monitor, cheap, SolverChoice::Auto, rk4, located),
        (monitor, cheap, SolverChoice::Auto, rk4, false),
        (
            monitor,
            cheap,
            SolverChoice::Auto,
            Integrator::DormandPrince,
            located,
        ),
        (
            monitor,
            AlphaChoice::Exact,
            SolverChoice::Auto,
            Integrator::BogackiShampine,
            located,
        ),
        (
            fixed,
            cheap,
            SolverChoice::Auto,
            Integrator::DormandPrince,
            located,
        ),
        (fixed, AlphaChoice::Exact, SolverChoice::Auto, rk4, located),
        (None, cheap, SolverChoice::Auto, rk4, located),
        (fixed, cheap, SolverChoice::Sparse, rk4, located),
        (fixed, cheap, SolverChoice::Tree, rk4, located),
        (fixed, cheap, SolverChoice::Jacobi, rk4, located),
        (fixed, cheap, SolverChoice::GaussSeidel(2), rk4, located),
        (fixed, cheap, SolverChoice::Cg(2), rk4, located),
        (fixed, cheap, SolverChoice::Ilu0, rk4, located),
    ] {
        let (update, _, solver, integrator, _) = case;
        let (short, short_updates) = allocations_of_run(case, 0.5);
        let (long, long_updates) = allocations_of_run(case, 2.0);
        assert!(
            long_updates > 2 * short_updates,
            "{update:?}, {solver}, {integrator:?}: {short_updates} vs {long_updates} updates"
        );
        assert_eq!(
            short, long,
            "{update:?}, {solver}, {integrator:?}: allocations {short} (0.5 s) vs {long} (2 s)"
        );
    }
}

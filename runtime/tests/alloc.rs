//! The simulator allocates nothing per step or per update: the number of heap
//! allocations of a run does not depend on its length.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use common::pendulum::Pendulum;
use dae_runtime::{
    AlphaChoice, Crossing, Integrator, NoTrace, Policy, Settings, Simulator, SolverChoice,
};

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
    (policy, alpha, solver, integrator, crossing): (
        Policy,
        AlphaChoice,
        SolverChoice,
        Integrator,
        Crossing,
    ),
    t_end: f64,
) -> (u64, u64) {
    let p = Pendulum::default();
    let mut settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .policy(policy)
        .alpha(alpha)
        .solver(solver)
        .integrator(integrator)
        .crossing(crossing)
        .t_end(t_end);
    if !solver.is_exact() {
        settings = settings.raise_gains(0.1);
    }
    if matches!(crossing, Crossing::Located { .. }) && policy != Policy::Spsm {
        // Every run that can follow the drift, graze and ramp does (their buffers are
        // the simulator's).
        settings = settings.follow_drift(1.0).graze(0.01).ramp_against_drift();
    }
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
    let (rk4, located) = (Integrator::Rk4, Crossing::default());
    let fixed = Policy::Fixed(0.005);
    let cheap = AlphaChoice::Cheap;
    for case in [
        (Policy::Monitor, cheap, SolverChoice::Auto, rk4, located),
        (
            Policy::Monitor,
            cheap,
            SolverChoice::Auto,
            rk4,
            Crossing::StepEnd,
        ),
        (
            Policy::Monitor,
            cheap,
            SolverChoice::Auto,
            Integrator::DormandPrince,
            located,
        ),
        (
            Policy::Monitor,
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
        (Policy::Spsm, cheap, SolverChoice::Auto, rk4, located),
        (fixed, cheap, SolverChoice::Sparse, rk4, located),
        (fixed, cheap, SolverChoice::Tree, rk4, located),
        (fixed, cheap, SolverChoice::Jacobi, rk4, located),
        (fixed, cheap, SolverChoice::GaussSeidel(2), rk4, located),
        (fixed, cheap, SolverChoice::Cg(2), rk4, located),
        (fixed, cheap, SolverChoice::Ilu0, rk4, located),
    ] {
        let (policy, _, solver, integrator, _) = case;
        let (short, short_updates) = allocations_of_run(case, 0.5);
        let (long, long_updates) = allocations_of_run(case, 2.0);
        assert!(
            long_updates > 2 * short_updates,
            "{policy:?}, {solver}, {integrator:?}: {short_updates} vs {long_updates} updates"
        );
        assert_eq!(
            short, long,
            "{policy:?}, {solver}, {integrator:?}: allocations {short} (0.5 s) vs {long} (2 s)"
        );
    }
}

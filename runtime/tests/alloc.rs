//! The simulator allocates nothing per step or per update: the number of heap
//! allocations of a run does not depend on its length.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use common::pendulum::Pendulum;
use dae_runtime::{AlphaChoice, NoTrace, Policy, Settings, Simulator, SolverChoice};

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
    policy: Policy,
    alpha: AlphaChoice,
    solver: SolverChoice,
    t_end: f64,
) -> (u64, u64) {
    let p = Pendulum::default();
    let mut settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .policy(policy)
        .alpha(alpha)
        .solver(solver)
        .t_end(t_end);
    if !solver.is_exact() {
        settings = settings.raise_gains(0.1);
    }
    let mut sim = Simulator::new(&p, settings).unwrap();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    let summary = sim.run(&mut NoTrace).unwrap();
    COUNTING.with(|c| c.set(false));
    (
        ALLOCATIONS.load(Ordering::Relaxed) - before,
        summary.updates,
    )
}

// A single test: the counter is global, and tests in one binary run in parallel.
#[test]
fn run_allocations_do_not_grow_with_steps_or_updates() {
    for (policy, alpha, solver) in [
        (Policy::Monitor, AlphaChoice::Cheap, SolverChoice::Auto),
        (Policy::Fixed(0.005), AlphaChoice::Exact, SolverChoice::Auto),
        (Policy::Spsm, AlphaChoice::Cheap, SolverChoice::Auto),
        (
            Policy::Fixed(0.005),
            AlphaChoice::Cheap,
            SolverChoice::Sparse,
        ),
        (Policy::Fixed(0.005), AlphaChoice::Cheap, SolverChoice::Tree),
        (
            Policy::Fixed(0.005),
            AlphaChoice::Cheap,
            SolverChoice::Jacobi,
        ),
        (
            Policy::Fixed(0.005),
            AlphaChoice::Cheap,
            SolverChoice::GaussSeidel(2),
        ),
        (
            Policy::Fixed(0.005),
            AlphaChoice::Cheap,
            SolverChoice::Cg(2),
        ),
        (Policy::Fixed(0.005), AlphaChoice::Cheap, SolverChoice::Ilu0),
    ] {
        let (short, short_updates) = allocations_of_run(policy, alpha, solver, 0.5);
        let (long, long_updates) = allocations_of_run(policy, alpha, solver, 2.0);
        assert!(
            long_updates > 2 * short_updates,
            "{policy:?}, {solver}: {short_updates} vs {long_updates} updates"
        );
        assert_eq!(
            short, long,
            "{policy:?}, {solver}: allocations {short} (0.5 s) vs {long} (2 s)"
        );
    }
}

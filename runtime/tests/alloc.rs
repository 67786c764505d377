//! The simulator allocates nothing per step or per update: the number of heap
//! allocations of a run does not depend on its length.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use common::pendulum::Pendulum;
use dae_runtime::{AlphaChoice, NoTrace, Policy, Settings, Simulator};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// Whether this thread's allocations are counted: only the test's own (the simulator
    /// runs on it). The test harness' main thread allocates now and then while a test
    /// runs, which a process-wide count would blame on the simulator.
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTED.with(Cell::get) {
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

fn allocations_of_run(policy: Policy, alpha: AlphaChoice, t_end: f64) -> (u64, u64) {
    let p = Pendulum::default();
    let settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .policy(policy)
        .alpha(alpha)
        .t_end(t_end);
    let mut sim = Simulator::new(&p, settings).unwrap();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let summary = sim.run(&mut NoTrace).unwrap();
    (
        ALLOCATIONS.load(Ordering::Relaxed) - before,
        summary.updates,
    )
}

// A single test: the counter is global, and tests in one binary run in parallel.
#[test]
fn run_allocations_do_not_grow_with_steps_or_updates() {
    COUNTED.with(|c| c.set(true));
    for (policy, alpha) in [
        (Policy::Monitor, AlphaChoice::Cheap),
        (Policy::Fixed(0.005), AlphaChoice::Exact),
        (Policy::Spsm, AlphaChoice::Cheap),
    ] {
        let (short, short_updates) = allocations_of_run(policy, alpha, 0.5);
        let (long, long_updates) = allocations_of_run(policy, alpha, 2.0);
        assert!(
            long_updates > 2 * short_updates,
            "{policy:?}: {short_updates} vs {long_updates} updates"
        );
        assert_eq!(
            short, long,
            "{policy:?}: allocations {short} (0.5 s) vs {long} (2 s)"
        );
    }
}

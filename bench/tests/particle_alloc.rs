//! A DBSMC particle run allocates nothing per frame: once it runs, the heap
//! allocations of its frames are none, on a chain and on a cloth, with the benchmark's
//! frame-tied design ramped ([`relaxed_settings`]: Dormand-Prince, crossings located,
//! `v` ramped against the drift, gains following it) whose `s'` comes from the particle
//! model's `Omega'` in one pass, and with the tensions' `J_Omega` factored at every
//! update (dense on the chain, sparse on the cloth).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use dae_bench::particle_bench::relaxed_settings;
use dae_particles::{
    Backend, Dbsmc, FRAME, GridPins, ParticleModel, System as Particles, chain, grid,
};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// Count only the allocations of the thread running the frames.
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

/// Allocations of frames `from + 1 ..= to` (positions read after each), and the
/// updates they made.
fn allocations_of_frames(b: &mut Dbsmc<ParticleModel>, from: usize, to: usize) -> (u64, u64) {
    let mut positions = vec![[0.0; 3]; b.n_particles()];
    let updates = b.counters().updates();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    for f in from + 1..=to {
        b.advance_to(f as f64 * FRAME).expect("the design holds");
        b.positions(&mut positions);
    }
    COUNTING.with(|c| c.set(false));
    (
        ALLOCATIONS.load(Ordering::Relaxed) - before,
        b.counters().updates() - updates,
    )
}

fn assert_no_allocation_per_frame(label: &str, system: &Particles, eps: f64) {
    let model = ParticleModel::new(system).unwrap();
    let settings = dae_bench::particle_bench::ramped(relaxed_settings(&model, eps, 4.0));
    let mut b = Dbsmc::new(model, settings, label).unwrap();
    // The first frames start the run (its buffers, the solver's symbolic analysis).
    allocations_of_frames(&mut b, 0, 2);
    let (allocations, updates) = allocations_of_frames(&mut b, 2, 30);
    assert!(updates > 20, "{label}: {updates} updates");
    assert_eq!(
        allocations, 0,
        "{label}: {allocations} allocations over 28 frames ({updates} updates)"
    );
}

#[test]
fn a_chain_and_a_cloth_allocate_nothing_per_frame() {
    assert_no_allocation_per_frame("chain", &chain(10, 1e2).unwrap(), 1e-3);
    assert_no_allocation_per_frame("cloth", &grid(8, GridPins::Corners, false).unwrap(), 1e-2);
}

//! A sized family model evaluates without allocating: the back end's scratch and the
//! input values are built at construction, and a run's allocations do not grow with its
//! length.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use dae_runtime::family::{FamilyInstance, Interpreter, Spec};
use dae_runtime::{Model, Settings, Simulator, model::w_offsets, trace::NoTrace};

struct Counting;

// Both the switch and the count are per thread: the tests of this file run in
// parallel, and one test's allocations must not land in another's count.
thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCATIONS.with(|a| a.set(a.get() + 1));
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn counted<T>(f: impl FnOnce() -> T) -> (T, u64) {
    let before = ALLOCATIONS.with(Cell::get);
    COUNTING.with(|c| c.set(true));
    let out = f();
    COUNTING.with(|c| c.set(false));
    (out, ALLOCATIONS.with(Cell::get) - before)
}

fn chain(n: i64) -> FamilyInstance<Interpreter> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/models/chain.dae");
    let src = std::fs::read_to_string(path).unwrap();
    let c = dae_lang::compile_source(&src).unwrap().remove(0);
    let spec = Spec {
        sizes: vec![("N".into(), n)],
        ..Spec::default()
    };
    FamilyInstance::interpreted(Interpreter::new(c), &spec).unwrap()
}

#[test]
fn evaluations_allocate_nothing() {
    let mut c = chain(300);
    // A moving input: re-evaluated at every new t.
    let i = c.input_index("pin[0].x").unwrap();
    c.set_input(i, 0.0, &[0.0, 0.1, 0.2, 0.3]).unwrap();
    let (n, m) = (c.n_states(), c.n_constraints());
    let mut x = vec![0.0; n];
    c.initial_state(&mut x);
    let z = vec![0.5; m];
    let mu = vec![0.1; m];
    let mut dx = vec![0.0; n];
    let mut w = vec![0.0; w_offsets(c.indices())[m]];
    let (mut s, mut ah, mut beta) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let mut j = vec![0.0; c.jacobian_pattern().len()];
    let ((), allocations) = counted(|| {
        for step in 0..20 {
            let t = step as f64 * 1e-3;
            c.rhs(t, &x, &z, &mut dx);
            c.sliding(t, &x, &z, &mu, &mut w, &mut s, &mut ah);
            c.jacobian(t, &x, &z, &mut j);
            c.beta(t, &x, &z, &mut beta);
        }
    });
    assert_eq!(allocations, 0);
    assert!(
        dx.iter()
            .chain(&w)
            .chain(&j)
            .chain(&beta)
            .all(|v| v.is_finite())
    );
}

#[test]
fn a_run_allocates_the_same_whatever_its_length() {
    let c = chain(50);
    let m = c.n_constraints();
    let run = |t_end: f64| {
        let settings = Settings::new(vec![1e-3; m], vec![0.02; m], vec![2.0; m])
            .step(2e-4)
            .t_end(t_end);
        let mut sim = Simulator::new(&c, settings).unwrap();
        let (s, a) = counted(|| sim.run(&mut NoTrace).unwrap());
        (s.steps, s.updates, a)
    };
    let (steps1, updates1, a1) = run(0.02);
    let (steps2, updates2, a2) = run(0.06);
    assert!(
        steps2 > 2 * steps1 && updates2 > updates1,
        "{updates1} {updates2}"
    );
    assert_eq!(
        a1, a2,
        "allocations of a run of {steps1} and of {steps2} steps"
    );
}

//! One step (or update) of each method on the planar double pendulum
//! (`cargo bench -p dae-bench --bench step`).
//!
//! The runtime's simulator exposes whole runs only, so DBSMC and SPSM are timed over
//! runs of `STEPS` steps and reported per step (criterion's throughput in elements/s is
//! steps/s); baseline (a) is timed one step at a time; the adaptive BDF over a 0.2 s run,
//! reported per accepted step.

use std::f64::consts::FRAC_PI_2;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dae_bench::{
    BdfSettings, IndexOneRk4, IndexOneSettings, PlanarChain, PlanarChainDae, bdf_index1,
    chain_scene,
};
use dae_runtime::{NoTrace, Policy, Settings, Simulator};

const STEPS: u64 = 1000;
const H: f64 = 1e-4;

fn steps(c: &mut Criterion) {
    let chain = PlanarChain::double_pendulum();
    let dae = PlanarChainDae::new(&chain).unwrap();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 1.0).expect("scene");
    let model = scene.started().unwrap();
    let mut g = c.benchmark_group("double_pendulum");
    g.measurement_time(Duration::from_secs(2)).sample_size(20);

    g.throughput(Throughput::Elements(1));
    let set = IndexOneSettings {
        mu: vec![0.05; 2],
        step: H,
        t_start: 0.0,
        t_end: 1.0,
        newton_tol: 1e-12,
    };
    let mut rk = IndexOneRk4::new(&model, set).expect("index-1");
    g.bench_function("index1_rk4_step", |b| {
        b.iter(|| rk.step(black_box(H)).expect("step"))
    });

    g.throughput(Throughput::Elements(STEPS));
    let t_end = STEPS as f64 * H;
    for (name, policy) in [
        ("dbsmc_step_no_update", Policy::Fixed(1e9)),
        ("dbsmc_step_with_update_every_step", Policy::Fixed(H)),
        ("dbsmc_monitor_step", Policy::Monitor),
        ("spsm_step", Policy::Spsm),
    ] {
        let settings = Settings::new(vec![1e-3; 2], vec![0.05; 2], scene.gains(0.05, 1.5))
            .step(H)
            .t_end(t_end)
            .policy(policy)
            .check_robustness(false);
        g.bench_function(name, |b| {
            b.iter(|| {
                Simulator::new(&model, settings.clone())
                    .expect("settings")
                    .run(&mut NoTrace)
                    .expect("run")
            })
        });
    }

    let bdf = BdfSettings {
        mu: vec![0.05; 2],
        rtol: 1e-8,
        atol: 1e-8,
        t_start: 0.0,
        t_end: 0.2,
    };
    let n = bdf_index1(&model, &bdf, None).expect("bdf").steps;
    g.throughput(Throughput::Elements(n));
    g.bench_function("bdf_step_tol1e-8", |b| {
        b.iter(|| bdf_index1(&model, &bdf, None).expect("bdf"))
    });
    g.finish();
}

criterion_group!(benches, steps);
criterion_main!(benches);

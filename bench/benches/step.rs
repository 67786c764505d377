//! One step (or update) of each method on the generated planar double pendulum and the
//! generated 5-link chain (`cargo bench -p dae-bench --bench step`).
//!
//! The runtime's simulator exposes whole runs only, so DBSMC and SPSM are timed over
//! runs of `STEPS` steps and reported per step (criterion's throughput in elements/s is
//! steps/s); baseline (a) is timed one step at a time; the adaptive BDF over a 0.2 s run,
//! reported per accepted step (with `--features bdf`).

use dae_runtime::settings::{Dbsmc, Law, Update};
use std::f64::consts::FRAC_PI_2;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
#[cfg(feature = "bdf")]
use dae_bench::{baseline::BdfSettings, baseline::bdf_index1};
use dae_bench::{
    baseline::IndexOneRk4, baseline::IndexOneSettings, generated::Chain5,
    generated::DoublePendulum, harness::Scene, scenes::chain_scene, truth::PlanarChain,
};
use dae_runtime::{Model, Settings, Simulator, trace::NoTrace};

const STEPS: u64 = 1000;
const H: f64 = 1e-4;

fn group<M: Model>(c: &mut Criterion, scene: &Scene<'_, M>) {
    let model = scene.model;
    let m = model.n_constraints();
    let mut g = c.benchmark_group(scene.name.as_str());
    g.measurement_time(Duration::from_secs(2)).sample_size(20);

    g.throughput(Throughput::Elements(1));
    let set = IndexOneSettings {
        mu: vec![0.05; m],
        step: H,
        t_start: 0.0,
        t_end: 1.0,
        newton_tol: 1e-12,
        initial: Some(scene.initial()),
    };
    let mut rk = IndexOneRk4::new(model, set).expect("index-1");
    g.bench_function("index1_rk4_step", |b| {
        b.iter(|| rk.step(black_box(H)).expect("step"))
    });

    g.throughput(Throughput::Elements(STEPS));
    let t_end = STEPS as f64 * H;
    for (name, policy) in [
        (
            "dbsmc_step_no_update",
            Law::from(Dbsmc::default().update(Update::Fixed { period: 1e9 })),
        ),
        (
            "dbsmc_step_with_update_every_step",
            Law::from(Dbsmc::default().update(Update::Fixed { period: H })),
        ),
        ("dbsmc_monitor_step", Law::default()),
        ("spsm_step", Law::Spsm),
    ] {
        let settings = Settings::new(vec![1e-3; m], vec![0.05; m], scene.gains(0.05, 1.5))
            .step(H)
            .t_end(t_end)
            .law(policy)
            .check_robustness(false)
            .initial(scene.x0.clone(), scene.z0.clone());
        g.bench_function(name, |b| {
            b.iter(|| {
                Simulator::new(model, settings.clone())
                    .expect("settings")
                    .run(&mut NoTrace)
                    .expect("run")
            })
        });
    }

    #[cfg(feature = "bdf")]
    bdf_group(&mut g, scene);
    g.finish();
}

/// The BDF over a 0.2 s run, per accepted step (feature `bdf`).
#[cfg(feature = "bdf")]
fn bdf_group<M: Model>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    scene: &Scene<'_, M>,
) {
    let (model, m) = (scene.model, scene.model.n_constraints());
    let bdf = BdfSettings {
        mu: vec![0.05; m],
        rtol: 1e-8,
        atol: 1e-8,
        t_start: 0.0,
        t_end: 0.2,
        initial: Some(scene.initial()),
    };
    let n = bdf_index1(model, &bdf, None).expect("bdf").steps;
    g.throughput(Throughput::Elements(n));
    g.bench_function("bdf_step_tol1e-8", |b| {
        b.iter(|| bdf_index1(model, &bdf, None).expect("bdf"))
    });
}

fn steps(c: &mut Criterion) {
    let dp = PlanarChain::double_pendulum();
    let dp_dae = DoublePendulum::default();
    let scene = chain_scene(
        "double_pendulum",
        &dp_dae,
        &dp,
        &[-FRAC_PI_2, -FRAC_PI_2],
        1.0,
    )
    .expect("scene");
    group(c, &scene);

    let chain = PlanarChain::new(vec![0.1; 5], vec![0.5; 5], 9.8).expect("chain");
    let chain_dae = Chain5 {
        L: 0.5,
        ..Chain5::default()
    };
    let scene = chain_scene(
        "chain5",
        &chain_dae,
        &chain,
        &[-1.2, -0.9, -0.6, -0.3, 0.0],
        1.0,
    )
    .expect("scene");
    group(c, &scene);
}

criterion_group!(benches, steps);
criterion_main!(benches);

// A model written with `dae!` builds, exposes its parameters as fields and simulates.
use dae_runtime::{Model, Settings, Simulator, Trace};

dae_runtime::dae! {
    // x' = z - x with x held on sin(t): an index-2 tracking problem.
    model Tracking {
        param a = 1.0;
        state x = 0.0;
        alg z = 1.0;
        der(x) = z - x;
        constraint follow: x = a * sin(t);
    }
}

fn main() {
    let model = Tracking { a: 1.0 };
    assert_eq!(model.indices(), &[2]);
    let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1])
        .step(1e-3)
        .t_end(1.0);
    let mut trace = Trace::new();
    let summary = Simulator::new(&model, settings)
        .expect("valid settings")
        .run(&mut trace)
        .expect("the simulation runs");
    let t = summary.t_end;
    assert!((summary.x[0] - t.sin()).abs() < 2e-3, "x = {}", summary.x[0]);
    assert!((summary.z_eq[0] - (t.sin() + t.cos())).abs() < 0.05);
}

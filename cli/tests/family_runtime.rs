//! The interpreted family versions of chain5 and the 3-D double pendulum against their
//! scalar (version-1) models run by the runtime's interpreter, both behind the runtime's
//! `Model` trait: the same f, w, s, alpha_hat, J_Omega and beta at random points (to
//! 1e-12), and the same simulation.

use std::path::Path;

use dae_runtime::family::{FamilyInstance, Interpreted, Interpreter, Spec};
use dae_runtime::settings::{Dbsmc, Update};
use dae_runtime::{Model, Settings, Simulator, Summary, model::w_offsets, trace::NoTrace};
use daec::interpret_source;

fn source(file: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/models")
        .join(file);
    std::fs::read_to_string(path).unwrap()
}

fn family(file: &str) -> FamilyInstance<Interpreter> {
    let c = dae_lang::compile_source(&source(file)).unwrap().remove(0);
    FamilyInstance::interpreted(Interpreter::new(c), &Spec::default()).unwrap()
}

fn scalar(file: &str) -> Interpreted {
    interpret_source(&source(file)).unwrap().remove(0)
}

/// SplitMix64.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * 1f64.max(a.abs()).max(b.abs())
}

/// Every output of a model at a point: rhs, w, s, alpha_hat, dense J, beta.
fn outputs(m: &dyn Model, t: f64, x: &[f64], z: &[f64], mu: &[f64]) -> [Vec<f64>; 6] {
    let n = m.n_constraints();
    let mut dx = vec![0.0; m.n_states()];
    m.rhs(t, x, z, &mut dx);
    let mut w = vec![0.0; w_offsets(m.indices())[n]];
    let (mut s, mut ah, mut beta) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    m.sliding(t, x, z, mu, &mut w, &mut s, &mut ah);
    let mut values = vec![0.0; m.jacobian_pattern().len()];
    m.jacobian(t, x, z, &mut values);
    let mut j = vec![0.0; n * n];
    for (&(r, c), v) in m.jacobian_pattern().iter().zip(values) {
        j[r * n + c] = v;
    }
    m.beta(t, x, z, &mut beta);
    [dx, w, s, ah, j, beta]
}

/// `map[i]`: the scalar state of family state `i` (`None`: the pin or pivot particle,
/// which the scalar version does not have).
fn state_map(
    f: &dyn Model,
    s: &dyn Model,
    name: impl Fn(&str, usize, &str) -> String,
) -> Vec<Option<usize>> {
    let map: Vec<Option<usize>> = (0..f.n_states())
        .map(|i| {
            let n = f.state_name(i);
            let (base, rest) = n.split_once('[').unwrap();
            let (k, comp) = rest.split_once("].").unwrap();
            let k: usize = k.parse().unwrap();
            (k > 0).then(|| {
                let sn = name(base, k, comp);
                (0..s.n_states())
                    .find(|&j| s.state_name(j) == sn)
                    .unwrap_or_else(|| panic!("no scalar state {sn}"))
            })
        })
        .collect();
    assert_eq!(map.iter().flatten().count(), s.n_states());
    map
}

fn agree_at_random_points(f: &dyn Model, s: &dyn Model, map: &[Option<usize>]) {
    assert_eq!(f.n_constraints(), s.n_constraints());
    assert_eq!(f.indices(), s.indices());
    let n = f.n_constraints();
    let mut rng = Rng(17);
    let mut x0 = vec![0.0; f.n_states()];
    f.initial_state(&mut x0);
    for _ in 0..10 {
        let mut fx = x0.clone();
        let mut sx = vec![0.0; s.n_states()];
        for (i, j) in map.iter().enumerate() {
            if let Some(j) = j {
                fx[i] += rng.uniform(-0.3, 0.3);
                sx[*j] = fx[i];
            }
        }
        let z: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let mu: Vec<f64> = (0..n).map(|_| rng.uniform(0.01, 0.2)).collect();
        let t = rng.uniform(0.0, 1.0);
        let a = outputs(f, t, &fx, &z, &mu);
        let b = outputs(s, t, &sx, &z, &mu);
        for (i, j) in map.iter().enumerate() {
            if let Some(j) = j {
                assert!(close(a[0][i], b[0][*j], 1e-12), "der({})", f.state_name(i));
            }
        }
        for (k, what) in [
            (1, "w"),
            (2, "s"),
            (3, "alpha_hat"),
            (4, "J_Omega"),
            (5, "beta"),
        ] {
            assert_eq!(a[k].len(), b[k].len(), "{what}");
            for (u, v) in a[k].iter().zip(&b[k]) {
                assert!(close(*u, *v, 1e-12), "{what}: {:?} vs {:?}", a[k], b[k]);
            }
        }
    }
}

fn simulate(m: &dyn Model, settings: Settings) -> Summary {
    Simulator::new(m, settings)
        .unwrap()
        .run(&mut NoTrace)
        .unwrap()
}

fn runs_agree(f: &dyn Model, s: &dyn Model, map: &[Option<usize>], settings: Settings) {
    let a = simulate(f, settings.clone());
    let b = simulate(s, settings);
    assert_eq!(a.steps, b.steps);
    assert!(a.updates > 10);
    // Round-off of a different evaluation order may move an update by a step (or add
    // or drop one); the motions stay together.
    let du = a.updates.abs_diff(b.updates);
    assert!(
        du <= 1 || du * 50 <= a.updates,
        "updates {} vs {}",
        a.updates,
        b.updates
    );
    for (i, j) in map.iter().enumerate() {
        if let Some(j) = j {
            assert!(
                (a.x[i] - b.x[*j]).abs() <= 1e-6,
                "{} = {} vs {}",
                f.state_name(i),
                a.x[i],
                b.x[*j]
            );
        }
    }
    for (u, v) in a.z_eq.iter().zip(&b.z_eq) {
        assert!(close(*u, *v, 1e-5), "z_eq {:?} vs {:?}", a.z_eq, b.z_eq);
    }
    for (u, v) in a.seen_max_abs_s.iter().zip(&b.seen_max_abs_s) {
        assert!(
            close(*u, *v, 1e-3),
            "max |s| {:?} vs {:?}",
            a.seen_max_abs_s,
            b.seen_max_abs_s
        );
    }
}

#[test]
fn family_chain5_is_chain5_planar() {
    let f = family("chain5_family.dae");
    let s = scalar("chain5_planar.dae");
    let map = state_map(&f, &s, |base, k, comp| match (base, comp) {
        ("x", c) => format!("{c}{k}"),
        (_, c) => format!("v{c}{k}"),
    });
    agree_at_random_points(&f, &s, &map);
    // Updates at a fixed period: with the monitor, the round-off of the two
    // formulations' `J_Omega` (one derivative against the kernels' sum of products)
    // can make a grazing crossing an update in one run and not in the other, after
    // which the runs are different (equally valid) motions inside the layers.
    let settings = Settings::new(vec![0.01; 5], vec![0.05; 5], vec![2.0; 5])
        .step(1e-4)
        .t_end(0.3)
        .law(Dbsmc::default().update(Update::Fixed { period: 0.005 }));
    runs_agree(&f, &s, &map, settings);
}

#[test]
fn family_double_pendulum_is_the_3d_double_pendulum() {
    let f = family("double_pendulum_family.dae");
    let s = scalar("double_pendulum_3d.dae");
    let map = state_map(&f, &s, |base, k, comp| match base {
        "x" => format!("p{k}{comp}"),
        _ => format!("v{k}{comp}"),
    });
    agree_at_random_points(&f, &s, &map);
    let settings = Settings::new(vec![0.2; 2], vec![0.076, 0.066], vec![7.5, 10.0])
        .step(1e-4)
        .t_end(1.0);
    runs_agree(&f, &s, &map, settings);
}

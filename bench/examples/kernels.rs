//! Where the generated family models' extra cost is: one evaluation of each per-step
//! function (`rhs`, `sliding`, `jacobian`, `beta`, `omega_rate`) of the generated model of a scene
//! (`dae_bench::particle_methods::generated_chain`, `generated_grid`: the `.dae` family compiled by
//! `dae_file!`, behind `FamilyParticles`) against the hand-written
//! `dae_particles::ParticleModel` of the same system, both through the runtime's `Model`
//! trait, at the scene's initial point with every tension 1.
//!
//! ```text
//! cargo run --release -p dae-bench --example kernels
//! cargo build --release -p dae-bench --example kernels
//! valgrind --tool=callgrind target/release/examples/kernels --calls c1:100
//! callgrind_annotate --inclusive=yes callgrind.out.* | grep 'as dae_runtime::model::Model>::'
//! ```
//!
//! Chains of 100, 1,000 and 10,000 links (C1, end-mass ratio 1e2) and cloths of 16 x 16,
//! 32 x 32 and 64 x 64 (C3 (a)). Times are the best of 5 batches of at least 20 ms
//! each, one core; the ratios, measured in one run, are what to read (the benchmark's
//! DBSMC runs on the generated models cost 1.46x those on the hand-written model, median
//! of 26 complete runs). The last column is the sum of the five, weighted as a DBSMC step
//! calls them (7 `rhs`, 3.5 `sliding`, 0.4 `jacobian`, 0.4 `beta`, 1.4 `omega_rate`: the
//! calls per step of the frame-tied design, `dbsmc-ramp-generated`, on the 10-link chain
//! with end-mass ratio 1e2 at eps = 1e-3, counted with callgrind (6.99, 3.50, 0.40, 0.40,
//! 1.40): `J_Omega` and `beta` at the updates only, `Omega'` at every step's end and
//! update).
//!
//! Times on a shared machine move by 10-20 % between runs; instruction counts do not.
//! `--calls c1:N` or `--calls c3:W` evaluates each function of both models of one scene
//! 100 times, untimed, for `callgrind`: `ParticleModel as ... Model>::rhs` is the
//! hand-written model's, `FamilyParticles<K> as ... Model>::rhs` the generated one's.

use std::hint::black_box;

use dae_bench::{
    particle_methods::generated_chain, particle_methods::generated_grid, timing::best_time,
};
use dae_particles::{FAR_EDGE_SLACK, GridPins, ParticleModel, System};
use dae_runtime::Model;

/// The arguments and outputs of one evaluation of each function, at the initial point.
struct Point {
    x: Vec<f64>,
    z: Vec<f64>,
    mu: Vec<f64>,
    dx: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    alpha_hat: Vec<f64>,
    jacobian: Vec<f64>,
    beta: Vec<f64>,
    zdot: Vec<f64>,
    rate: Vec<f64>,
}

impl Point {
    fn initial(m: &dyn Model) -> Point {
        let (n, k) = (m.n_states(), m.n_constraints());
        let mut x = vec![0.0; n];
        m.initial_state(&mut x);
        let nw: usize = m.indices().iter().sum();
        Point {
            x,
            z: vec![1.0; k],
            mu: vec![0.1; k],
            dx: vec![0.0; n],
            w: vec![0.0; nw],
            s: vec![0.0; k],
            alpha_hat: vec![0.0; k],
            jacobian: vec![0.0; m.jacobian_pattern().len()],
            beta: vec![0.0; k],
            zdot: vec![0.5; k],
            rate: vec![0.0; k],
        }
    }
}

/// Seconds per evaluation of rhs, sliding, jacobian, beta and omega_rate at the initial
/// point.
fn times(m: &dyn Model) -> [f64; 5] {
    let p = &mut Point::initial(m);
    [
        best_time(|| m.rhs(0.1, black_box(&p.x), &p.z, &mut p.dx)),
        best_time(|| {
            let (w, s, ah) = (&mut p.w, &mut p.s, &mut p.alpha_hat);
            m.sliding(0.1, black_box(&p.x), &p.z, &p.mu, w, s, ah)
        }),
        best_time(|| m.jacobian(0.1, black_box(&p.x), &p.z, &mut p.jacobian)),
        best_time(|| m.beta(0.1, black_box(&p.x), &p.z, &mut p.beta)),
        best_time(|| {
            let given = m.omega_rate(0.1, black_box(&p.x), &p.z, &p.zdot, &mut p.rate);
            assert!(given, "{} gives Omega'", m.name());
        }),
    ]
}

/// `--calls`: each function evaluated `CALLS` times, untimed, for an instruction count.
fn calls(m: &dyn Model) {
    let p = &mut Point::initial(m);
    for _ in 0..CALLS {
        m.rhs(0.1, black_box(&p.x), &p.z, &mut p.dx);
        let (w, s, ah) = (&mut p.w, &mut p.s, &mut p.alpha_hat);
        m.sliding(0.1, black_box(&p.x), &p.z, &p.mu, w, s, ah);
        m.jacobian(0.1, black_box(&p.x), &p.z, &mut p.jacobian);
        m.beta(0.1, black_box(&p.x), &p.z, &mut p.beta);
        m.omega_rate(0.1, black_box(&p.x), &p.z, &p.zdot, &mut p.rate);
    }
}

/// Evaluations per function and model under `--calls`.
const CALLS: usize = 100;

/// Calls per DBSMC step (rhs, sliding, jacobian, beta, omega_rate); see the module docs.
const PER_STEP: [f64; 5] = [7.0, 3.5, 0.4, 0.4, 1.4];

fn row(scene: &str, links: usize, hand: &dyn Model, generated: &dyn Model) {
    let (h, g) = (times(hand), times(generated));
    let cell = |i: usize| format!("{:.1} / {:.1} ({:.2})", h[i] * 1e6, g[i] * 1e6, g[i] / h[i]);
    let step = |t: &[f64; 5]| t.iter().zip(PER_STEP).map(|(t, k)| t * k).sum::<f64>();
    println!(
        "| {scene} | {links} | {} | {} | {} | {} | {} | {:.2} |",
        cell(0),
        cell(1),
        cell(2),
        cell(3),
        cell(4),
        step(&g) / step(&h)
    );
}

/// The hand-written and the generated model of `c1:N` (C1, end-mass ratio 1e2) or
/// `c3:W` (C3 (a)), with the table's name of the scene and its number of links.
type Models = (String, usize, Box<dyn Model>, Box<dyn Model>);

fn models(scene: &str) -> Result<Models, String> {
    let size = |n: &str| -> Result<usize, String> {
        n.parse()
            .map_err(|_| format!("`{n}` in `{scene}` is not a size"))
    };
    match scene.split(':').collect::<Vec<_>>().as_slice() {
        ["c1", n] => {
            let n = size(n)?;
            let system: System = dae_particles::chain(n, 1e2).map_err(|e| e.to_string())?;
            let hand = ParticleModel::new(&system).map_err(|e| e.to_string())?;
            let generated = generated_chain(&system, n, 1e2)?;
            Ok(("C1 r=1e2".into(), n, Box::new(hand), Box::new(generated)))
        }
        ["c3", w] => {
            let w = size(w)?;
            let system =
                dae_particles::grid_with_slack(w, GridPins::Corners, false, FAR_EDGE_SLACK)
                    .map_err(|e| e.to_string())?;
            let hand = ParticleModel::new(&system).map_err(|e| e.to_string())?;
            let generated = generated_grid(&system, w, GridPins::Corners, false, FAR_EDGE_SLACK)?;
            let links = system.links().len();
            Ok((
                format!("C3 (a) {w} x {w}"),
                links,
                Box::new(hand),
                Box::new(generated),
            ))
        }
        _ => Err(format!("`{scene}`: a scene is c1:N or c3:W")),
    }
}

fn main() {
    let fail = |e: String| -> ! {
        eprintln!("kernels: {e}");
        std::process::exit(1);
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => {}
        [flag, scene] if flag == "--calls" => {
            let (_, _, hand, generated) = models(scene).unwrap_or_else(|e| fail(e));
            calls(hand.as_ref());
            calls(generated.as_ref());
            return;
        }
        _ => fail("usage: kernels [--calls c1:N|c3:W]".into()),
    }
    println!(
        "Microseconds per evaluation, hand-written / generated (ratio); last column: the five weighted as a step calls them, generated / hand-written.\n"
    );
    println!("| scene | links | rhs | sliding | jacobian | beta | omega_rate | per step |");
    println!("|---|---|---|---|---|---|---|---|");
    for scene in ["c1:100", "c1:1000", "c1:10000", "c3:16", "c3:32", "c3:64"] {
        let (name, links, hand, generated) = models(scene).unwrap_or_else(|e| fail(e));
        row(&name, links, hand.as_ref(), generated.as_ref());
    }
}

//! What the report of a singular `J_Omega` costs (`dae_runtime::solve::Redundancy`, the
//! rank and the implied constraints of `daec check` and `daec run`), on the `J_Omega =
//! G M^-1 G^T` of a flat cloth of side `W` with rigid links along the grid and both
//! diagonals of every square as rigid links too (two corners pinned): `4 W^2 - 6 W + 2`
//! constraints on `2 W^2 - 4` coordinates in the plane, so about half of them implied.
//!
//! ```text
//! cargo run --release -p dae-bench --example redundancy
//! ```
//!
//! Prints, per size, the constraints, the rank beside the closed form (the coordinates
//! of the free particles in the plane, `2 W^2 - 4`: the grid alone is rigid there, so
//! every coordinate direction is resisted), the implied count, whether the rows
//! were taken family by family (the diagonals after the links) or, past the budget, in
//! the solver's order, and the median time of five analyses; then the exponent of time
//! against constraints fitted over the sizes.

use std::collections::HashMap;
use std::time::Instant;

use dae_bench::particle_bench::fitted_exponent;
use dae_runtime::solve::Redundancy;

/// `J_Omega` of the cloth: size, pattern, values and the class of each row (0: along
/// the grid, 1: diagonal).
struct Cloth {
    m: usize,
    pattern: Vec<(usize, usize)>,
    values: Vec<f64>,
    class: Vec<usize>,
}

fn rigid_shear_cloth(w: usize) -> Cloth {
    let id = |i: usize, j: usize| i + w * j;
    let mut links = Vec::new();
    for j in 0..w {
        for i in 0..w - 1 {
            links.push((id(i, j), id(i + 1, j)));
        }
    }
    for j in 0..w - 1 {
        for i in 0..w {
            links.push((id(i, j), id(i, j + 1)));
        }
    }
    let along = links.len();
    for j in 0..w - 1 {
        for i in 0..w - 1 {
            links.push((id(i, j), id(i + 1, j + 1)));
            links.push((id(i + 1, j), id(i, j + 1)));
        }
    }
    let pinned = |p: usize| p == id(0, w - 1) || p == id(w - 1, w - 1);
    // Positions slightly uneven (a fixed pattern), so that no two links are parallel by
    // accident; unit masses.
    let pos = |p: usize| {
        let (i, j) = ((p % w) as f64, (p / w) as f64);
        (
            i + 0.05 * (1.7 * j + 0.3 * i).sin(),
            j + 0.05 * (2.3 * i - 0.7 * j).cos(),
        )
    };
    // G's rows: per link, its gradient at each free end.
    let grad: Vec<Vec<(usize, (f64, f64))>> = links
        .iter()
        .map(|&(a, b)| {
            let (pa, pb) = (pos(a), pos(b));
            let d = (pb.0 - pa.0, pb.1 - pa.1);
            let mut g = Vec::new();
            if !pinned(a) {
                g.push((a, (-d.0, -d.1)));
            }
            if !pinned(b) {
                g.push((b, d));
            }
            g
        })
        .collect();
    // J = G G^T: links sharing a free particle.
    let mut at: HashMap<usize, Vec<usize>> = HashMap::new();
    for (l, g) in grad.iter().enumerate() {
        for &(p, _) in g {
            at.entry(p).or_default().push(l);
        }
    }
    let mut entries: HashMap<(usize, usize), f64> = HashMap::new();
    for (&p, ls) in &at {
        for &k in ls {
            for &l in ls {
                let gk = grad[k].iter().find(|e| e.0 == p).unwrap().1;
                let gl = grad[l].iter().find(|e| e.0 == p).unwrap().1;
                *entries.entry((k, l)).or_default() += gk.0 * gl.0 + gk.1 * gl.1;
            }
        }
    }
    let mut pattern: Vec<(usize, usize)> = entries.keys().copied().collect();
    pattern.sort_unstable();
    let values = pattern.iter().map(|e| entries[e]).collect();
    let class = (0..links.len()).map(|l| usize::from(l >= along)).collect();
    Cloth {
        m: links.len(),
        pattern,
        values,
        class,
    }
}

fn main() {
    println!("| W | constraints | rank | 2 W^2 - 4 | implied | order | median ms |");
    println!("|---|---|---|---|---|---|---|");
    let mut points = Vec::new();
    for w in [5, 16, 50] {
        let Cloth {
            m,
            pattern,
            values,
            class,
        } = rigid_shear_cloth(w);
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..5 {
            let t0 = Instant::now();
            let r = Redundancy::of(m, &pattern, &values, &class).expect("a valid pattern");
            times.push(t0.elapsed().as_secs_f64());
            last = Some(r);
        }
        times.sort_by(f64::total_cmp);
        let r = last.expect("five runs");
        println!(
            "| {w} | {m} | {} | {} | {} | {} | {:.2} |",
            r.rank(),
            2 * w * w - 4,
            r.implied().len(),
            if r.by_class() {
                "by family"
            } else {
                "solver's"
            },
            times[2] * 1e3
        );
        points.push((m as f64, times[2]));
    }
    match fitted_exponent(&points) {
        Some(e) => println!("\ntime ~ constraints^{e:.2}"),
        None => println!("\nno exponent (a time of zero)"),
    }
}

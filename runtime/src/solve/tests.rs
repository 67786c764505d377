//! Unit tests of the solver seam on small hand-made matrices; the particle Jacobians
//! (chains, cloth, random trees) and the example models are tested in dae-bench.

use super::*;

/// A deterministic pseudo-random sequence in [-1, 1) (the solver modules' tests share
/// it).
pub(crate) struct Lcg(pub(crate) u64);
impl Lcg {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// `-(B B^T + c I)` restricted to the pattern of a `w x w` grid graph (5-point),
/// values symmetric; negative definite by diagonal dominance.
fn grid(w: usize, rng: &mut Lcg) -> (usize, Vec<(usize, usize)>, Vec<f64>) {
    let m = w * w;
    let mut pat = Vec::new();
    let mut off = std::collections::HashMap::new();
    for i in 0..m {
        let (r, c) = (i / w, i % w);
        let mut nb = vec![];
        if r > 0 {
            nb.push(i - w);
        }
        if c > 0 {
            nb.push(i - 1);
        }
        if c + 1 < w {
            nb.push(i + 1);
        }
        if r + 1 < w {
            nb.push(i + w);
        }
        nb.push(i);
        nb.sort_unstable();
        for j in nb {
            pat.push((i, j));
            if i < j {
                off.insert((i, j), rng.next());
            }
        }
    }
    let vals: Vec<f64> = pat
        .iter()
        .map(|&(i, j)| {
            if i == j {
                -5.0
            } else {
                off[&(i.min(j), i.max(j))]
            }
        })
        .collect();
    (m, pat, vals)
}

fn dense_of(m: usize, pat: &[(usize, usize)], vals: &[f64], d: &[f64]) -> Vec<f64> {
    let mut a = vec![0.0; m * m];
    for (&(i, j), v) in pat.iter().zip(vals) {
        a[i * m + j] = d[i] * v;
    }
    a
}

fn residual(m: usize, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    (0..m)
        .map(|i| {
            let ax: f64 = (0..m).map(|j| a[i * m + j] * x[j]).sum();
            (ax - b[i]).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn exact_solvers_solve_a_grid_with_row_scaling() {
    let mut rng = Lcg(7);
    let (m, pat, vals) = grid(6, &mut rng);
    let d: Vec<f64> = (0..m).map(|i| 0.01 + 0.02 * (i % 5) as f64).collect();
    let a = dense_of(m, &pat, &vals, &d);
    let b: Vec<f64> = (0..m).map(|_| rng.next()).collect();
    for choice in [
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Auto,
    ] {
        let mut s = Solver::new(m, &pat, choice).unwrap();
        s.factor(&vals, &d).unwrap();
        let mut x = b.clone();
        s.solve(&mut x);
        let r = residual(m, &a, &x, &b);
        assert!(r < 1e-12, "{choice}: residual {r}");
        assert_eq!(s.stats().factorisations, 1);
        assert_eq!(s.stats().solves, 1);
    }
    // The grid has cycles: the tree solver refuses it with a clear message.
    let err = Solver::new(m, &pat, SolverChoice::Tree).err().unwrap();
    assert!(err.to_string().contains("forest"), "{err}");
}

#[test]
fn sparse_lu_handles_unsymmetric_values_and_pattern() {
    let mut rng = Lcg(3);
    let (m, mut pat, mut vals) = grid(5, &mut rng);
    // Perturb the values unsymmetrically and drop one mirrored entry.
    for (v, &(i, j)) in vals.iter_mut().zip(&pat) {
        if i > j {
            *v += 0.3 * rng.next();
        }
    }
    let drop = pat
        .iter()
        .position(|&(i, j)| i == 7 && j == 2)
        .unwrap_or(pat.len() - 1);
    pat.remove(drop);
    vals.remove(drop);
    let d = vec![1.0; m];
    let a = dense_of(m, &pat, &vals, &d);
    let b: Vec<f64> = (0..m).map(|_| rng.next()).collect();
    let mut s = Solver::new(m, &pat, SolverChoice::Sparse).unwrap();
    s.factor(&vals, &d).unwrap();
    assert_eq!(s.name(), "sparse-lu");
    let mut x = b.clone();
    s.solve(&mut x);
    assert!(residual(m, &a, &x, &b) < 1e-12);
    // CG refuses unsymmetric values with the offending entry.
    let err = match Solver::new(m, &pat, SolverChoice::Cg(3)) {
        Err(e) => e,
        Ok(mut cg) => cg.factor(&vals, &d).unwrap_err(),
    };
    assert!(matches!(err, SolveError::NotSymmetric { .. }), "{err}");
}

#[test]
fn approximate_solvers_converge_with_more_iterations() {
    let mut rng = Lcg(11);
    let (m, pat, vals) = grid(8, &mut rng);
    let d: Vec<f64> = (0..m).map(|i| 1.0 + (i % 3) as f64).collect();
    let a = dense_of(m, &pat, &vals, &d);
    let b: Vec<f64> = (0..m).map(|_| rng.next()).collect();
    for (few, many) in [
        (SolverChoice::GaussSeidel(2), SolverChoice::GaussSeidel(40)),
        (SolverChoice::Cg(2), SolverChoice::Cg(40)),
    ] {
        let mut r = [0.0; 2];
        for (k, c) in [few, many].into_iter().enumerate() {
            let mut s = Solver::new(m, &pat, c).unwrap();
            s.factor(&vals, &d).unwrap();
            let mut x = b.clone();
            s.solve(&mut x);
            r[k] = residual(m, &a, &x, &b);
        }
        assert!(
            r[1] < 1e-10 && r[0] > 100.0 * r[1],
            "{few} vs {many}: {r:?}"
        );
    }
    // Jacobi and ILU(0) are linear and cheaper than exact, but not exact here.
    for c in [SolverChoice::Jacobi, SolverChoice::Ilu0] {
        let mut s = Solver::new(m, &pat, c).unwrap();
        s.factor(&vals, &d).unwrap();
        let mut x = b.clone();
        s.solve(&mut x);
        let r = residual(m, &a, &x, &b);
        let bn = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        assert!(r > 1e-6 && r < bn, "{c}: residual {r}");
    }
}

#[test]
fn a_singular_matrix_names_its_dependent_rows() {
    // Row 1 = 2 row 0, row 2 independent, row 3 coupled to row 2 only.
    let pat = vec![
        (0, 0),
        (0, 1),
        (1, 0),
        (1, 1),
        (2, 2),
        (2, 3),
        (3, 2),
        (3, 3),
    ];
    let vals = [1.0, 2.0, 2.0, 4.0, 1.0, 0.5, 0.5, 2.0];
    for c in [
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Tree,
    ] {
        let mut s = Solver::new(4, &pat, c).unwrap();
        let err = s.factor(&vals, &[1.0, 0.5, 1.0, 1.0]).unwrap_err();
        assert_eq!(
            err,
            SolveError::Singular {
                constraints: vec![0, 1]
            },
            "{c}"
        );
    }
}

#[test]
fn a_zero_pivot_of_a_nonsingular_matrix_is_a_breakdown() {
    // [[0, 1], [1, 0]]: a forest, nonsingular, but no usable diagonal pivot.
    let pat = vec![(0, 0), (0, 1), (1, 0), (1, 1)];
    let vals = [0.0, 1.0, 1.0, 0.0];
    let mut tree = Solver::new(2, &pat, SolverChoice::Tree).unwrap();
    let err = tree.factor(&vals, &[1.0, 1.0]).unwrap_err();
    assert!(matches!(err, SolveError::Breakdown { .. }), "{err}");
    assert!(err.to_string().contains("dense"), "{err}");
    let mut dense = Solver::new(2, &pat, SolverChoice::Dense).unwrap();
    dense.factor(&vals, &[1.0, 1.0]).unwrap();
}

#[test]
fn choices_round_trip_through_text() {
    for c in [
        SolverChoice::Auto,
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Tree,
        SolverChoice::Jacobi,
        SolverChoice::GaussSeidel(3),
        SolverChoice::Cg(10),
        SolverChoice::Ilu0,
    ] {
        assert_eq!(c.to_string().parse::<SolverChoice>(), Ok(c));
    }
    assert!("cg:0".parse::<SolverChoice>().unwrap_err().contains(">= 1"));
    assert!(
        "lu".parse::<SolverChoice>()
            .unwrap_err()
            .contains("gauss-seidel:K")
    );
}

#[test]
fn malformed_patterns_are_rejected() {
    assert!(Solver::new(2, &[(0, 0), (2, 1)], SolverChoice::Dense).is_err());
    let dup = Solver::new(2, &[(0, 0), (0, 0), (1, 1)], SolverChoice::Sparse).err();
    assert!(dup.unwrap().to_string().contains("twice"));
}

#[test]
fn a_chordal_pattern_is_factored_without_fill() {
    // Links of a particle tree: three links at particle A (0, 1, 2) form a clique, link 2
    // continues to a branch point with links 3 and 4, link 4 to link 5: a block graph.
    let edges = [(0, 1), (0, 2), (1, 2), (2, 3), (2, 4), (3, 4), (4, 5)];
    let mut pat: Vec<(usize, usize)> = (0..6).map(|i| (i, i)).collect();
    for &(i, j) in &edges {
        pat.push((i, j));
        pat.push((j, i));
    }
    let sparse = sparse::SparseSolver::new(Structure::new(6, &pat).unwrap());
    // Strictly lower factor = strictly lower pattern: no fill.
    assert_eq!(sparse.fill(), (true, edges.len()));
}

#[test]
fn an_empty_system_factors_and_solves_with_every_solver() {
    // A model without constraints (an ODE) has m = 0.
    for choice in [
        SolverChoice::Auto,
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Tree,
        SolverChoice::Jacobi,
        SolverChoice::GaussSeidel(2),
        SolverChoice::Cg(2),
        SolverChoice::Ilu0,
    ] {
        let mut s = Solver::new(0, &[], choice).unwrap();
        s.factor(&[], &[]).unwrap();
        let mut b: [f64; 0] = [];
        s.solve(&mut b);
        s.solve_from(&[], &mut []);
        assert_eq!(s.pivot_range(), None, "{choice}");
    }
}

#[test]
fn pivot_ranges_bound_the_pivots() {
    // diag(4, -0.5) in a dense and a tree/sparse/Jacobi form: pivots 4 and 0.5.
    let pattern = [(0, 0), (1, 1)];
    for choice in [
        SolverChoice::Dense,
        SolverChoice::Sparse,
        SolverChoice::Tree,
        SolverChoice::Jacobi,
        SolverChoice::Ilu0,
    ] {
        let mut s = Solver::new(2, &pattern, choice).unwrap();
        s.factor(&[4.0, -0.5], &[1.0, 1.0]).unwrap();
        assert_eq!(s.pivot_range(), Some((0.5, 4.0)), "{choice}");
    }
    let mut s = Solver::new(2, &pattern, SolverChoice::Cg(2)).unwrap();
    s.factor(&[4.0, 0.5], &[1.0, 1.0]).unwrap();
    assert_eq!(s.pivot_range(), None);
}

#[test]
fn sparse_reads_symmetry_from_the_values_of_a_symmetric_pattern() {
    let mut rng = Lcg(5);
    let (m, pat, vals) = grid(5, &mut rng);
    let d = vec![1.0; m];
    let b: Vec<f64> = (0..m).map(|_| rng.next()).collect();
    let scale = vals.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    // One entry below the diagonal moved: by rounding (symmetric still), or by more.
    let below = pat.iter().position(|&(i, j)| i > j).unwrap();
    for (bump, name) in [(1e-14 * scale, "sparse-ldlt"), (1e-6 * scale, "sparse-lu")] {
        let mut v = vals.clone();
        v[below] += bump;
        let mut s = Solver::new(m, &pat, SolverChoice::Sparse).unwrap();
        s.factor(&v, &d).unwrap();
        assert_eq!(s.name(), name, "bump {bump}");
        let mut x = b.clone();
        s.solve(&mut x);
        assert!(residual(m, &dense_of(m, &pat, &v, &d), &x, &b) < 1e-10);
    }
    // A value that is not finite is named by its row.
    let mut v = vals.clone();
    v[below] = f64::NAN;
    let mut s = Solver::new(m, &pat, SolverChoice::Sparse).unwrap();
    let err = s.factor(&v, &d).unwrap_err();
    assert!(
        matches!(err, SolveError::NonFinite { row } if row == pat[below].0),
        "{err}"
    );
}

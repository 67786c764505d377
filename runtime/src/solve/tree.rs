//! Exact elimination along a forest: when the graph of the off-diagonal entries has no
//! cycle (a chain of links, a hair strand), eliminating leaves before their parents
//! creates no fill, so factor and solve cost `O(m)`.
//!
//! The pivots are the diagonal entries (no row exchanges): for particle systems
//! `J_Omega = -G M^-1 G^T` is negative definite and every pivot is safe. The values may
//! be unsymmetric (the elimination is an `LU` on the symmetric structure).

use super::diagnose::pivot_failure;
use super::structure::NONE;
use super::{
    InverseKind, LinearSolver, PIVOT_TOL, SolveError, SolverStats, Structure, checked_scale,
};

#[derive(Clone)]
pub(crate) struct TreeSolver {
    st: Structure,
    /// Nodes in elimination order: every node after all of its children.
    order: Vec<usize>,
    /// Parent of each node (`NONE` for roots).
    parent: Vec<usize>,
    /// Entry indices of `(k, parent)`, `(parent, k)` and `(k, k)` (`NONE` if absent).
    up: Vec<usize>,
    down: Vec<usize>,
    /// Pivots, the multipliers `a_pk / piv_k` (L) and `a_kp` (U) of each node.
    piv: Vec<f64>,
    lmul: Vec<f64>,
    uval: Vec<f64>,
    scale: Vec<f64>,
    stats: SolverStats,
}

impl TreeSolver {
    pub(crate) fn new(st: Structure) -> Result<Self, SolveError> {
        if !st.is_forest() {
            return Err(SolveError::Pattern(format!(
                "the tree solver needs a pattern whose graph is a forest; this one has {} rows and {} links between rows (a cycle): use the sparse solver",
                st.m,
                st.edges()
            )));
        }
        let m = st.m;
        let mut parent = vec![NONE; m];
        let mut seen = vec![false; m];
        let mut bfs = Vec::with_capacity(m);
        for root in 0..m {
            if seen[root] {
                continue;
            }
            seen[root] = true;
            let start = bfs.len();
            bfs.push(root);
            let mut head = start;
            while head < bfs.len() {
                let k = bfs[head];
                head += 1;
                for &c in st.neighbours(k) {
                    if !seen[c] {
                        seen[c] = true;
                        parent[c] = k;
                        bfs.push(c);
                    }
                }
            }
        }
        // Reverse breadth-first order puts every child before its parent.
        let order: Vec<usize> = bfs.into_iter().rev().collect();
        let find = |i: usize, j: usize| -> usize {
            let row = &st.cols[st.row_ptr[i]..st.row_ptr[i + 1]];
            row.binary_search(&j)
                .map_or(NONE, |k| st.entry[st.row_ptr[i] + k])
        };
        let up = (0..m)
            .map(|k| {
                if parent[k] == NONE {
                    NONE
                } else {
                    find(k, parent[k])
                }
            })
            .collect();
        let down = (0..m)
            .map(|k| {
                if parent[k] == NONE {
                    NONE
                } else {
                    find(parent[k], k)
                }
            })
            .collect();
        Ok(Self {
            order,
            parent,
            up,
            down,
            piv: vec![0.0; m],
            lmul: vec![0.0; m],
            uval: vec![0.0; m],
            scale: vec![1.0; m],
            st,
            stats: SolverStats::default(),
        })
    }

    pub(crate) fn stored_values(&self) -> usize {
        4 * self.st.m
    }

    /// Left null vector of the leading block when the pivot of `k` vanished:
    /// `y_k = 1`, `y_c = -lmul_c y_parent(c)` down the subtree of `k`.
    fn leading_null(&self, k: usize) -> Vec<f64> {
        let mut y = vec![0.0; self.st.m];
        y[k] = 1.0;
        // Parents come after children in `order`, so walk it backwards from `k`.
        let pos = self.order.iter().position(|&n| n == k).unwrap_or(0);
        for &c in self.order[..pos].iter().rev() {
            let p = self.parent[c];
            if p != NONE && y[p] != 0.0 {
                y[c] = -self.lmul[c] * y[p];
            }
        }
        y
    }
}

fn value(values: &[f64], e: usize) -> f64 {
    if e == NONE { 0.0 } else { values[e] }
}

impl LinearSolver for TreeSolver {
    fn name(&self) -> &str {
        "tree"
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Exact
    }

    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        let tol = PIVOT_TOL * checked_scale(&self.st, values, row_scale)?;
        self.scale.copy_from_slice(row_scale);
        for k in 0..self.st.m {
            self.piv[k] = value(values, self.st.diag[k]);
        }
        for &k in &self.order {
            let d = self.piv[k];
            if d.abs() <= tol {
                let y = self.leading_null(k);
                return Err(pivot_failure(&self.st, values, row_scale, k, || y));
            }
            let p = self.parent[k];
            if p != NONE {
                let l = value(values, self.down[k]) / d;
                let u = value(values, self.up[k]);
                self.lmul[k] = l;
                self.uval[k] = u;
                self.piv[p] -= l * u;
            }
        }
        Ok(())
    }

    fn solve(&mut self, b: &mut [f64]) {
        self.stats.solves += 1;
        for (bi, d) in b.iter_mut().zip(&self.scale) {
            *bi /= d;
        }
        for &k in &self.order {
            let p = self.parent[k];
            if p != NONE {
                b[p] -= self.lmul[k] * b[k];
            }
        }
        for &k in self.order.iter().rev() {
            let p = self.parent[k];
            let above = if p == NONE { 0.0 } else { self.uval[k] * b[p] };
            b[k] = (b[k] - above) / self.piv[k];
        }
    }

    fn pivot_range(&self) -> Option<(f64, f64)> {
        super::abs_range(self.piv.iter().copied())
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

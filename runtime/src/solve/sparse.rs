//! Exact sparse direct solver: symbolic analysis once per pattern, numeric
//! factorisation per update (written from Davis, *Direct Methods for Sparse Linear
//! Systems*, SIAM 2006, chapters 4 and 6: elimination tree, row patterns by tree
//! reaches, up-looking factorisation).
//!
//! The symbolic step orders the symmetrised graph ([`elimination_order`]: perfect for
//! chordal graphs, minimum degree otherwise), builds the elimination tree and the
//! pattern of `L`. The numeric step computes `J_Omega = L D U` (unit triangular `L`,
//! `U` with the structure of `L^T`) with diagonal pivots in that order; when the values
//! are symmetric it skips `U` (`U = L^T`, an `LDL^T`, half the work). No row exchanges:
//! a negligible pivot is diagnosed ([`pivot_failure`]) as a singular matrix (with the
//! dependent rows) or a breakdown (then use the dense solver). For particle systems
//! `J_Omega = -G M^-1 G^T` is negative definite when the links are independent, so the
//! diagonal pivots are safe; a redundant link makes it semidefinite and the failed
//! pivot's leading-block null vector names the links of the dependency.

use super::diagnose::pivot_failure;
use super::order::{OrderKind, elimination_order};
use super::structure::NONE;
use super::supernodal::Supernodal;
use super::{
    InverseKind, LinearSolver, PIVOT_TOL, SolveError, SolverStats, Structure, checked_scale,
};

#[derive(Clone)]
pub(crate) struct SparseSolver {
    st: Structure,
    /// `perm[k]` is the original row eliminated `k`-th.
    perm: Vec<usize>,
    /// CSC pattern of the strictly lower `L` (rows ascending per column).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Row patterns of `L` (columns ascending): `(column, slot in the CSC arrays)`.
    row_ptr: Vec<usize>,
    row_cols: Vec<(u32, u32)>,
    /// Per permuted row `k`: entries `A[k, j]` and `A[j, k]` for `j < k` (permuted `j`,
    /// entry index), and the diagonal entry.
    lower: Vec<(u32, u32)>,
    upper: Vec<(u32, u32)>,
    tri_ptr: Vec<usize>,
    diag: Vec<usize>,
    lx: Vec<f64>,
    ux: Vec<f64>,
    d: Vec<f64>,
    symmetric_values: bool,
    /// The multifrontal kernel (symmetric values), and whether it holds the factors.
    /// Built for patterns with fill only: on chordal patterns every supernode is a
    /// column and the up-looking kernel is faster.
    multifrontal: Option<Supernodal>,
    use_multifrontal: bool,
    work_y: Vec<f64>,
    work_t: Vec<f64>,
    scale: Vec<f64>,
    name: &'static str,
    #[cfg_attr(not(test), allow(dead_code))]
    order_kind: OrderKind,
    stats: SolverStats,
}

impl SparseSolver {
    pub(crate) fn new(st: Structure) -> Self {
        let n = st.m;
        let (perm, order_kind) = elimination_order(&st);
        let mut pinv = vec![0; n];
        for (k, &v) in perm.iter().enumerate() {
            pinv[v] = k;
        }
        // Entries of the permuted matrix below/above the diagonal, per row (CSR-like).
        let mut tri_ptr = vec![0; n + 1];
        for &(i, j) in &st.entries {
            let (pi, pj) = (pinv[i], pinv[j]);
            if pi != pj {
                tri_ptr[pi.max(pj) + 1] += 1;
            }
        }
        for k in 0..n {
            tri_ptr[k + 1] += tri_ptr[k];
        }
        let mut lower = vec![(0, ABSENT); tri_ptr[n]];
        let mut upper = vec![(0, ABSENT); tri_ptr[n]];
        // Slots are shared: the structure is symmetrised, a missing mirror entry stays NONE.
        let mut slot_of = std::collections::HashMap::new();
        let mut fill = tri_ptr.clone();
        for (e, &(i, j)) in st.entries.iter().enumerate() {
            let (pi, pj) = (pinv[i], pinv[j]);
            if pi == pj {
                continue;
            }
            let (k, other) = (pi.max(pj), pi.min(pj));
            let slot = *slot_of.entry((k, other)).or_insert_with(|| {
                let s = fill[k];
                fill[k] += 1;
                s
            });
            lower[slot].0 = other as u32;
            upper[slot].0 = other as u32;
            if pi == k {
                lower[slot].1 = e as u32; // A[k, other]
            } else {
                upper[slot].1 = e as u32; // A[other, k]
            }
        }
        // Compact each row to the slots used, sorted by column.
        let mut ptr = vec![0; n + 1];
        let (mut lo, mut up) = (Vec::new(), Vec::new());
        for k in 0..n {
            let mut row: Vec<((u32, u32), (u32, u32))> = (tri_ptr[k]..fill[k])
                .map(|s| (lower[s], upper[s]))
                .collect();
            row.sort_unstable_by_key(|r| r.0.0);
            for (l, u) in row {
                lo.push(l);
                up.push(u);
            }
            ptr[k + 1] = lo.len();
        }
        let (lower, upper, tri_ptr) = (lo, up, ptr);
        // Elimination tree (Liu's algorithm with path compression).
        let mut parent = vec![NONE; n];
        let mut ancestor = vec![NONE; n];
        for k in 0..n {
            for &(j, _) in &lower[tri_ptr[k]..tri_ptr[k + 1]] {
                let mut i = j as usize;
                while i != NONE && i < k {
                    let next = ancestor[i];
                    ancestor[i] = k;
                    if next == NONE {
                        parent[i] = k;
                    }
                    i = next;
                }
            }
        }
        // Row patterns of L: the reach of row k's entries up the tree, stopped at k.
        let mut mark = vec![NONE; n];
        let mut row_ptr = vec![0; n + 1];
        let mut rows: Vec<u32> = Vec::new();
        for k in 0..n {
            mark[k] = k;
            let start = rows.len();
            for &(j, _) in &lower[tri_ptr[k]..tri_ptr[k + 1]] {
                let mut i = j as usize;
                while mark[i] != k {
                    mark[i] = k;
                    rows.push(i as u32);
                    i = parent[i];
                }
            }
            rows[start..].sort_unstable();
            row_ptr[k + 1] = rows.len();
        }
        // CSC of L from the row patterns; a row's entry goes to the end of its column.
        let mut col_ptr = vec![0; n + 1];
        for &j in &rows {
            col_ptr[j as usize + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0; rows.len()];
        let mut row_cols = Vec::with_capacity(rows.len());
        for k in 0..n {
            for &j in &rows[row_ptr[k]..row_ptr[k + 1]] {
                let slot = next[j as usize];
                next[j as usize] += 1;
                row_idx[slot] = k;
                row_cols.push((j, slot as u32));
            }
        }
        let nnz_l = rows.len();
        let symmetric_pattern = st.symmetric;
        let diag: Vec<usize> = perm.iter().map(|&i| st.diag[i]).collect();
        let multifrontal = (order_kind == OrderKind::MinimumDegree)
            .then(|| Supernodal::new(&parent, &col_ptr, &row_idx, &lower, &tri_ptr, &diag));
        Self {
            multifrontal,
            use_multifrontal: false,
            perm,
            col_ptr,
            row_idx,
            row_ptr,
            row_cols,
            lower,
            upper,
            tri_ptr,
            diag,
            lx: vec![0.0; nnz_l],
            ux: vec![0.0; nnz_l],
            d: vec![0.0; n],
            symmetric_values: symmetric_pattern,
            work_y: vec![0.0; n],
            work_t: vec![0.0; n],
            scale: vec![1.0; n],
            name: "sparse-ldlt",
            order_kind,
            st,
            stats: SolverStats::default(),
        }
    }

    /// Values kept: both triangles of the factor (fill included), the diagonal and the
    /// work vectors.
    pub(crate) fn stored_values(&self) -> usize {
        2 * self.row_idx.len()
            + 4 * self.st.m
            + self
                .multifrontal
                .as_ref()
                .map_or(0, Supernodal::stored_values)
    }

    /// Whether the ordering was a perfect elimination ordering (no fill), and the
    /// nonzeros of the strictly lower factor.
    #[cfg(test)]
    pub(crate) fn fill(&self) -> (bool, usize) {
        (self.order_kind == OrderKind::Perfect, self.row_idx.len())
    }

    /// Left null vector (original numbering) of the leading block when pivot `k`
    /// vanished: `y = L^{-T} e_k` over rows `0..=k`.
    fn leading_null(&self, k: usize) -> Vec<f64> {
        let mut yp = vec![0.0; self.st.m];
        yp[k] = 1.0;
        for j in (0..k).rev() {
            let mut s = 0.0;
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let r = self.row_idx[p];
                if r > k {
                    break;
                }
                s -= self.lx[p] * yp[r];
            }
            yp[j] = s;
        }
        let mut y = vec![0.0; self.st.m];
        for (k, &i) in self.perm.iter().enumerate() {
            y[i] = yp[k];
        }
        y
    }
}

/// An absent entry in the compact `(column, entry)` tables.
const ABSENT: u32 = u32::MAX;

fn value(values: &[f64], e: u32) -> f64 {
    if e == ABSENT { 0.0 } else { values[e as usize] }
}

impl LinearSolver for SparseSolver {
    fn name(&self) -> &str {
        self.name
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Exact
    }

    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        let scale = checked_scale(&self.st, values, row_scale)?;
        self.symmetric_values = self.st.symmetric && self.st.asymmetry(values, scale).is_none();
        self.name = if self.symmetric_values {
            "sparse-ldlt"
        } else {
            "sparse-lu"
        };
        self.scale.copy_from_slice(row_scale);
        let tol = PIVOT_TOL * scale;
        self.use_multifrontal = false;
        if let (true, Some(mf)) = (self.symmetric_values, &mut self.multifrontal) {
            if mf.factor(values, tol).is_ok() {
                self.use_multifrontal = true;
                return Ok(());
            }
        }
        // Unsymmetric values, or a failed pivot: the up-looking kernel (which finds the
        // same pivot and diagnoses it).
        let n = self.st.m;
        let sym = self.symmetric_values;
        let (y, t) = (&mut self.work_y, &mut self.work_t);
        for k in 0..n {
            let tri = self.tri_ptr[k]..self.tri_ptr[k + 1];
            for (&(j, e), &(_, f)) in self.lower[tri.clone()].iter().zip(&self.upper[tri]) {
                y[j as usize] = value(values, f); // A[j, k], column k above the diagonal
                t[j as usize] = value(values, e); // A[k, j], row k left of the diagonal
            }
            let mut dk = if self.diag[k] == NONE {
                0.0
            } else {
                values[self.diag[k]]
            };
            for &(j, slot) in &self.row_cols[self.row_ptr[k]..self.row_ptr[k + 1]] {
                let (j, slot) = (j as usize, slot as usize);
                let start = self.col_ptr[j];
                let yj = y[j];
                y[j] = 0.0;
                if sym {
                    t[j] = 0.0;
                    for p in start..slot {
                        y[self.row_idx[p]] -= self.lx[p] * yj;
                    }
                    let l = yj / self.d[j];
                    self.lx[slot] = l;
                    dk -= l * yj;
                } else {
                    let tj = t[j];
                    t[j] = 0.0;
                    for p in start..slot {
                        let r = self.row_idx[p];
                        y[r] -= self.lx[p] * yj;
                        t[r] -= self.ux[p] * tj;
                    }
                    let dj = self.d[j];
                    self.lx[slot] = tj / dj;
                    self.ux[slot] = yj / dj;
                    dk -= tj * yj / dj;
                }
            }
            if dk.abs() <= tol || dk.is_nan() {
                // Clear the work vectors for the next factorisation, then diagnose.
                y.fill(0.0);
                t.fill(0.0);
                let yl = self.leading_null(k);
                return Err(pivot_failure(
                    &self.st,
                    values,
                    row_scale,
                    self.perm[k],
                    || yl,
                ));
            }
            self.d[k] = dk;
        }
        Ok(())
    }

    fn solve(&mut self, b: &mut [f64]) {
        self.stats.solves += 1;
        let n = self.st.m;
        let x = &mut self.work_y;
        for (k, &i) in self.perm.iter().enumerate() {
            x[k] = b[i] / self.scale[i];
        }
        if let (true, Some(mf)) = (self.use_multifrontal, &self.multifrontal) {
            mf.solve(x);
            for (k, &i) in self.perm.iter().enumerate() {
                b[i] = x[k];
                x[k] = 0.0;
            }
            return;
        }
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                    x[self.row_idx[p]] -= self.lx[p] * xj;
                }
            }
        }
        for (xj, d) in x.iter_mut().zip(&self.d) {
            *xj /= d;
        }
        let u = if self.symmetric_values {
            &self.lx
        } else {
            &self.ux
        };
        for j in (0..n).rev() {
            let mut s = x[j];
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                s -= u[p] * x[self.row_idx[p]];
            }
            x[j] = s;
        }
        for (k, &i) in self.perm.iter().enumerate() {
            b[i] = x[k];
            x[k] = 0.0;
        }
    }

    fn pivot_range(&self) -> Option<(f64, f64)> {
        match (&self.multifrontal, self.use_multifrontal) {
            (Some(mf), true) => super::abs_range(mf.pivots().iter().copied()),
            _ => super::abs_range(self.d.iter().copied()),
        }
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

//! Approximate inverses `J_hat^{-1}` that cost `O(nnz)` per update: the inverse
//! diagonal, Gauss-Seidel sweeps, Jacobi-preconditioned conjugate gradients and the
//! incomplete factorisation `ILU(0)`. All work on `J_Omega` with the right-hand side
//! scaled by `diag(d)^{-1}` (`J_s = diag(d) J_Omega`), which leaves each of them the same
//! method as on `J_s` (row scaling commutes with the diagonal, the sweeps and the
//! incomplete factors) and keeps a symmetric `J_Omega` symmetric for CG.

use super::diagnose::pivot_failure;
use super::structure::NONE;
use super::{
    InverseKind, LinearSolver, PIVOT_TOL, SolveError, SolverStats, Structure, check_finite, max_abs,
};

/// Values of `J_Omega` in CSR order, the row scaling and the diagonal's CSR slots.
#[derive(Clone)]
struct Csr {
    st: Structure,
    vals: Vec<f64>,
    scale: Vec<f64>,
    diag_slot: Vec<usize>,
}

impl Csr {
    fn new(st: Structure) -> Self {
        let m = st.m;
        let mut diag_slot = vec![NONE; m];
        for (i, slot) in diag_slot.iter_mut().enumerate() {
            for p in st.row_ptr[i]..st.row_ptr[i + 1] {
                if st.cols[p] == i {
                    *slot = p;
                }
            }
        }
        Self {
            vals: vec![0.0; st.cols.len()],
            scale: vec![1.0; m],
            diag_slot,
            st,
        }
    }

    /// Load values and scaling in one pass; fail on a non-finite value or a negligible
    /// diagonal entry (diagnosed).
    fn load(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        let (mut big, mut finite) = (0.0f64, true);
        for (v, &e) in self.vals.iter_mut().zip(&self.st.entry) {
            let x = values[e];
            *v = x;
            big = big.max(x.abs());
            finite &= x.is_finite();
        }
        if !finite {
            check_finite(&self.st, values, row_scale)?;
        }
        self.scale.copy_from_slice(row_scale);
        if row_scale.iter().any(|d| !d.is_finite() || *d == 0.0) {
            check_finite(&self.st, values, row_scale)?;
        }
        let tol = PIVOT_TOL * big;
        for i in 0..self.st.m {
            let s = self.diag_slot[i];
            if s == NONE || self.vals[s].abs() <= tol {
                let mut y = vec![0.0; self.st.m];
                y[i] = 1.0;
                return Err(pivot_failure(&self.st, values, row_scale, i, || y));
            }
        }
        Ok(())
    }

    fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.st.row_ptr[i]..self.st.row_ptr[i + 1]
    }

    /// `y = J_Omega x`.
    fn mul(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            let mut s = 0.0;
            for p in self.row(i) {
                s += self.vals[p] * x[self.st.cols[p]];
            }
            *yi = s;
        }
    }
}

/// `J_hat = diag(J_s)`.
#[derive(Clone)]
pub(crate) struct Jacobi {
    a: Csr,
    inv: Vec<f64>,
    stats: SolverStats,
}

impl Jacobi {
    pub(crate) fn new(st: Structure) -> Self {
        let m = st.m;
        Self {
            a: Csr::new(st),
            inv: vec![0.0; m],
            stats: SolverStats::default(),
        }
    }
}

impl Jacobi {
    pub(crate) fn stored_values(&self) -> usize {
        self.a.vals.len() + 2 * self.a.st.m
    }
}

impl LinearSolver for Jacobi {
    fn name(&self) -> &str {
        "jacobi"
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Diagonal
    }
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        self.a.load(values, row_scale)?;
        for (i, inv) in self.inv.iter_mut().enumerate() {
            *inv = 1.0 / (self.a.scale[i] * self.a.vals[self.a.diag_slot[i]]);
        }
        Ok(())
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.stats.solves += 1;
        for (bi, inv) in b.iter_mut().zip(&self.inv) {
            *bi *= inv;
        }
    }
    fn pivot_range(&self) -> Option<(f64, f64)> {
        super::abs_range(self.inv.iter().map(|v| 1.0 / v))
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

/// A fixed number of forward Gauss-Seidel sweeps on `J_Omega y = diag(d)^{-1} b`.
#[derive(Clone)]
pub(crate) struct GaussSeidel {
    a: Csr,
    sweeps: u32,
    rhs: Vec<f64>,
    name: String,
    stats: SolverStats,
}

impl GaussSeidel {
    pub(crate) fn new(st: Structure, sweeps: u32) -> Self {
        let m = st.m;
        Self {
            a: Csr::new(st),
            sweeps,
            rhs: vec![0.0; m],
            name: format!("gauss-seidel:{sweeps}"),
            stats: SolverStats::default(),
        }
    }
}

impl GaussSeidel {
    pub(crate) fn stored_values(&self) -> usize {
        self.a.vals.len() + 2 * self.a.st.m
    }
}

impl LinearSolver for GaussSeidel {
    fn name(&self) -> &str {
        &self.name
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Approximate
    }
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        self.a.load(values, row_scale)
    }
    fn solve(&mut self, b: &mut [f64]) {
        let b0 = std::mem::take(&mut self.rhs);
        let mut rhs = b0;
        rhs.copy_from_slice(b);
        b.fill(0.0);
        self.solve_from(&rhs, b);
        self.rhs = rhs;
    }
    fn solve_from(&mut self, b: &[f64], x: &mut [f64]) {
        self.stats.solves += 1;
        self.stats.iterations += u64::from(self.sweeps);
        let a = &self.a;
        for _ in 0..self.sweeps {
            for i in 0..a.st.m {
                let mut s = b[i] / a.scale[i];
                let mut diag = 0.0;
                for p in a.row(i) {
                    let j = a.st.cols[p];
                    if j == i {
                        diag = a.vals[p];
                    } else {
                        s -= a.vals[p] * x[j];
                    }
                }
                x[i] = s / diag;
            }
        }
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

/// At most a fixed number of Jacobi-preconditioned conjugate-gradient iterations on
/// `J_Omega y = diag(d)^{-1} b` (symmetric definite `J_Omega`, of either sign: the
/// step lengths are ratios in which the sign cancels).
#[derive(Clone)]
pub(crate) struct Cg {
    a: Csr,
    iters: u32,
    checked: bool,
    rhs: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    name: String,
    stats: SolverStats,
}

impl Cg {
    pub(crate) fn new(st: Structure, iters: u32) -> Result<Self, SolveError> {
        if !st.symmetric {
            let e = st.transpose.iter().position(|&t| t == NONE).unwrap_or(0);
            let (row, col) = st.entries[e];
            return Err(SolveError::NotSymmetric { row, col });
        }
        let m = st.m;
        let v = || vec![0.0; m];
        Ok(Self {
            a: Csr::new(st),
            iters,
            checked: false,
            rhs: v(),
            r: v(),
            z: v(),
            p: v(),
            q: v(),
            name: format!("cg:{iters}"),
            stats: SolverStats::default(),
        })
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Cg {
    pub(crate) fn stored_values(&self) -> usize {
        self.a.vals.len() + 6 * self.a.st.m
    }
}

impl LinearSolver for Cg {
    fn name(&self) -> &str {
        &self.name
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Approximate
    }
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        // Symmetry is checked at the first factorisation only (it costs a scattered
        // pass over the values): CG on a slightly unsymmetric J_Omega later is only a
        // worse approximation, which the residual-based robustness check sees.
        if !self.checked {
            if let Some((row, col)) = self.a.st.asymmetry(values, max_abs(values)) {
                return Err(SolveError::NotSymmetric { row, col });
            }
            self.checked = true;
        }
        self.a.load(values, row_scale)
    }
    fn solve(&mut self, b: &mut [f64]) {
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.copy_from_slice(b);
        b.fill(0.0);
        self.solve_from(&rhs, b);
        self.rhs = rhs;
    }
    // Indexed loops: five parallel vectors.
    #[allow(clippy::needless_range_loop)]
    fn solve_from(&mut self, b: &[f64], x: &mut [f64]) {
        self.stats.solves += 1;
        let a = &self.a;
        let m = a.st.m;
        a.mul(x, &mut self.q);
        for i in 0..m {
            self.r[i] = b[i] / a.scale[i] - self.q[i];
            self.z[i] = self.r[i] / a.vals[a.diag_slot[i]];
        }
        self.p.copy_from_slice(&self.z);
        let bnorm = b
            .iter()
            .zip(&a.scale)
            .map(|(b, d)| (b / d) * (b / d))
            .sum::<f64>()
            .sqrt();
        let mut rz = dot(&self.r, &self.z);
        for _ in 0..self.iters {
            if dot(&self.r, &self.r).sqrt() <= 1e-15 * bnorm {
                break;
            }
            self.stats.iterations += 1;
            a.mul(&self.p, &mut self.q);
            let pq = dot(&self.p, &self.q);
            if pq == 0.0 || !pq.is_finite() {
                break;
            }
            let alpha = rz / pq;
            for i in 0..m {
                x[i] += alpha * self.p[i];
                self.r[i] -= alpha * self.q[i];
                self.z[i] = self.r[i] / a.vals[a.diag_slot[i]];
            }
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..m {
                self.p[i] = self.z[i] + beta * self.p[i];
            }
        }
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

/// Incomplete LU without fill on the pattern of `J_Omega` (diagonal pivots), applied
/// exactly: `J_hat = diag(d) L U`.
#[derive(Clone)]
pub(crate) struct Ilu0 {
    a: Csr,
    /// Position of column `j` in the row being factored (`NONE` elsewhere).
    marker: Vec<usize>,
    stats: SolverStats,
}

impl Ilu0 {
    pub(crate) fn new(st: Structure) -> Self {
        let m = st.m;
        Self {
            a: Csr::new(st),
            marker: vec![NONE; m],
            stats: SolverStats::default(),
        }
    }
}

impl Ilu0 {
    pub(crate) fn stored_values(&self) -> usize {
        self.a.vals.len() + self.a.st.m
    }
}

// Indexed loops: CSR rows addressed through positions and a column marker.
#[allow(clippy::needless_range_loop)]
impl LinearSolver for Ilu0 {
    fn name(&self) -> &str {
        "ilu0"
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Approximate
    }
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        self.a.load(values, row_scale)?;
        let tol = PIVOT_TOL * max_abs(&self.a.vals);
        let a = &mut self.a;
        let (cols, row_ptr) = (&a.st.cols, &a.st.row_ptr);
        for i in 0..a.st.m {
            let row = row_ptr[i]..row_ptr[i + 1];
            for p in row.clone() {
                self.marker[cols[p]] = p;
            }
            for p in row.clone() {
                let k = cols[p];
                if k >= i {
                    break;
                }
                let lik = a.vals[p] / a.vals[a.diag_slot[k]];
                a.vals[p] = lik;
                for q in a.diag_slot[k] + 1..row_ptr[k + 1] {
                    let slot = self.marker[cols[q]];
                    if slot != NONE {
                        a.vals[slot] -= lik * a.vals[q];
                    }
                }
            }
            for p in row {
                self.marker[cols[p]] = NONE;
            }
            if a.vals[a.diag_slot[i]].abs() <= tol {
                let mut y = vec![0.0; a.st.m];
                y[i] = 1.0;
                return Err(pivot_failure(&a.st, values, row_scale, i, || y));
            }
        }
        Ok(())
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.stats.solves += 1;
        let a = &self.a;
        let (cols, row_ptr) = (&a.st.cols, &a.st.row_ptr);
        let m = a.st.m;
        for i in 0..m {
            let mut s = b[i] / a.scale[i];
            for p in row_ptr[i]..a.diag_slot[i] {
                s -= a.vals[p] * b[cols[p]];
            }
            b[i] = s;
        }
        for i in (0..m).rev() {
            let mut s = b[i];
            for p in a.diag_slot[i] + 1..row_ptr[i + 1] {
                s -= a.vals[p] * b[cols[p]];
            }
            b[i] = s / a.vals[a.diag_slot[i]];
        }
    }
    fn pivot_range(&self) -> Option<(f64, f64)> {
        let a = &self.a;
        super::abs_range((0..a.st.m).map(|i| a.scale[i] * a.vals[a.diag_slot[i]]))
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

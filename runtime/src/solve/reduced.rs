//! Solving with a singular `J_s` whose dependent rows are implied by the others
//! ([`RedundantRows::Drop`]): the implied rows are set aside and the rest solved exactly.
//!
//! When the factorisation of the whole `J_s` finds it singular, [`Redundancy`] names the
//! rows the others imply (family by family, the later family implied) and, for each kept
//! row, its pivot column. The kept rows restricted to the pivot columns form a
//! nonsingular `r x r` system `J_KP` (on a symmetric semidefinite `J_s`, a principal
//! submatrix: the pivot of a kept row is its own column); `J_hat^{-1} b` is its solution
//! on the pivot columns and zero on the others. Every kept row's equation holds exactly;
//! an implied row's holds to the extent that `b` is consistent with the dependency (for
//! constraints that are dependent as functions, `b` from the sliding law is: see the
//! guarantee in `docs/method.md`). The reduced solver is built at the first singular
//! factorisation and again only when the implied rows change (the error path of the
//! no-allocation rule); while the whole `J_s` factors, it is used and nothing changes.

use serde::{Deserialize, Serialize};

use super::redundancy::{CLASS_ORDER_BUDGET, Orders};
use super::{LinearSolver, Redundancy, SolveError, Solver, SolverChoice};

/// What the solver does when `J_s` is singular.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum RedundantRows {
    /// Refuse: the factorisation fails with [`SolveError::Singular`] (the run stops and
    /// names the dependent constraints).
    #[default]
    Refuse,
    /// Drop the rows the others imply and solve the rest exactly (see the module
    /// documentation of `solve::reduced`).
    Drop,
}

/// The reduced system of the last singular factorisation.
#[derive(Clone)]
pub(crate) struct Reduced {
    /// The structure and row orders of the pattern for [`Redundancy`], found once (the
    /// classes are the constraint families).
    orders: Orders,
    pattern: Vec<(usize, usize)>,
    /// The values of `J_s`, for the analysis.
    scaled: Vec<f64>,
    choice: SolverChoice,
    /// Whether the last factorisation went through the reduced system.
    pub(crate) active: bool,
    /// Kept rows and their pivot columns (in the order of the reduced system).
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// The implied rows.
    dropped: Vec<usize>,
    /// The most implied rows at one factorisation since the counters were reset.
    pub(crate) rows_max: u64,
    /// For each entry of the reduced pattern, the entry of the whole pattern.
    from: Vec<usize>,
    solver: Option<Box<Solver>>,
    values: Vec<f64>,
    scale: Vec<f64>,
    b: Vec<f64>,
}

impl Reduced {
    pub(crate) fn new(
        pattern: &[(usize, usize)],
        choice: SolverChoice,
        class: &[usize],
    ) -> Result<Self, SolveError> {
        Ok(Self {
            orders: Orders::new(class.len(), pattern, class)?,
            pattern: pattern.to_vec(),
            scaled: vec![0.0; pattern.len()],
            choice,
            active: false,
            rows: Vec::new(),
            cols: Vec::new(),
            dropped: Vec::new(),
            rows_max: 0,
            from: Vec::new(),
            solver: None,
            values: Vec::new(),
            scale: Vec::new(),
            b: Vec::new(),
        })
    }

    /// Factor the reduced system of `J_s = diag(row_scale) J_Omega` (`values` in the
    /// order of the whole pattern).
    pub(crate) fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        for ((s, &(i, _)), v) in self.scaled.iter_mut().zip(&self.pattern).zip(values) {
            *s = row_scale[i] * v;
        }
        let red = Redundancy::with_orders(&self.orders, &self.scaled, CLASS_ORDER_BUDGET);
        if red.implied() != self.dropped.as_slice() || self.solver.is_none() {
            self.rebuild(&red)?;
        }
        for (k, &e) in self.from.iter().enumerate() {
            self.values[k] = values[e];
        }
        for (k, &i) in self.rows.iter().enumerate() {
            self.scale[k] = row_scale[i];
        }
        let solver = self.solver.as_mut().expect("built above");
        solver
            .factor(&self.values, &self.scale)
            .map_err(|e| match e {
                // The kept rows are independent; a failure here names the original rows.
                SolveError::Singular { constraints } => SolveError::Singular {
                    constraints: constraints.iter().map(|&k| self.rows[k]).collect(),
                },
                e => e,
            })?;
        self.active = true;
        self.rows_max = self.rows_max.max(self.dropped.len() as u64);
        Ok(())
    }

    fn rebuild(&mut self, red: &Redundancy) -> Result<(), SolveError> {
        let m = self.orders.rows();
        self.dropped = red.implied().to_vec();
        // In the rows' own order: on a semidefinite `J_s` the reduced system is then the
        // principal submatrix as it stands, factored as the model without the implied
        // constraints would factor it.
        let mut pairs = red.kept_pivots();
        pairs.sort_unstable();
        self.rows = pairs.iter().map(|&(i, _)| i).collect();
        self.cols = pairs.iter().map(|&(_, c)| c).collect();
        const NONE: usize = usize::MAX;
        let (mut row_at, mut col_at) = (vec![NONE; m], vec![NONE; m]);
        for (k, (&i, &c)) in self.rows.iter().zip(&self.cols).enumerate() {
            row_at[i] = k;
            col_at[c] = k;
        }
        let mut sub = Vec::new();
        self.from.clear();
        for (e, &(i, j)) in self.pattern.iter().enumerate() {
            if row_at[i] != NONE && col_at[j] != NONE {
                sub.push((row_at[i], col_at[j]));
                self.from.push(e);
            }
        }
        let r = self.rows.len();
        self.solver = Some(Box::new(Solver::new(r, &sub, self.choice)?));
        self.values = vec![0.0; sub.len()];
        self.scale = vec![0.0; r];
        self.b = vec![0.0; r];
        Ok(())
    }

    /// `b <- J_hat^{-1} b` through the reduced system (zero on the columns it leaves).
    pub(crate) fn solve(&mut self, b: &mut [f64]) {
        for (k, &i) in self.rows.iter().enumerate() {
            self.b[k] = b[i];
        }
        let solver = self.solver.as_mut().expect("factored");
        solver.solve(&mut self.b);
        b.fill(0.0);
        for (k, &c) in self.cols.iter().enumerate() {
            b[c] = self.b[k];
        }
    }

    /// Zero the reduced solver's counters.
    pub(crate) fn reset_stats(&mut self) {
        self.rows_max = 0;
        if let Some(s) = self.solver.as_mut() {
            s.reset_stats();
        }
    }

    /// The reduced solver (after a successful [`Reduced::factor`]).
    pub(crate) fn solver(&self) -> Option<&Solver> {
        self.solver.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `J = G G^T` of two rows of `G` and their sum: the third row is implied. With a
    /// consistent right-hand side (the third entry the sum of the first two) every
    /// equation holds; the third unknown is left at zero.
    #[test]
    fn a_singular_system_is_solved_without_its_implied_row() {
        let g = [[1.0, 2.0, 0.0], [0.0, 1.0, -1.0], [1.0, 3.0, -1.0]];
        let mut pattern = Vec::new();
        let mut values = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                pattern.push((i, j));
                values.push((0..3).map(|k| g[i][k] * g[j][k]).sum::<f64>());
            }
        }
        let ones = [1.0; 3];
        let mut refuse = Solver::new(3, &pattern, SolverChoice::Auto).unwrap();
        assert!(matches!(
            refuse.factor(&values, &ones),
            Err(SolveError::Singular { .. })
        ));
        let mut drop = Solver::new(3, &pattern, SolverChoice::Auto)
            .unwrap()
            .redundant_rows(RedundantRows::Drop, &pattern, &[0, 0, 1])
            .unwrap();
        drop.factor(&values, &ones).unwrap();
        let b = [1.0, -2.0, -1.0];
        let mut x = [0.0; 3];
        drop.solve_from(&b, &mut x);
        assert_eq!(x[2], 0.0);
        for i in 0..3 {
            let r: f64 = (0..3).map(|j| values[3 * i + j] * x[j]).sum();
            assert!((r - b[i]).abs() < 1e-12, "row {i}: {r} against {}", b[i]);
        }
        let stats = drop.stats();
        assert_eq!((stats.set_aside, stats.set_aside_rows_max), (1, 1));
        // A nonsingular matrix goes through the whole solver, as without the option.
        let eye = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        drop.factor(&eye, &ones).unwrap();
        drop.solve_from(&b, &mut x);
        assert_eq!(x, b);
        assert_eq!(drop.stats().set_aside, 1);
    }
}

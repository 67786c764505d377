//! Block-local control updates ([`Scope::Blocks`](crate::settings::Scope::Blocks)): the
//! constraints partitioned into blocks close in the graph of `J_Omega`, and the law
//! solved for the blocks whose rows asked, each with its own block of `J_s` and the
//! other rows' `v` held.
//!
//! For a block `b` the solve is
//!
//! ```text
//! J_s[b,b] v_b = -alpha_hat_b - K_b sgn(s_b) - J_s[b,not b] v_not_b
//! ```
//!
//! so that every row of `b` gets exactly the rate a global update gives it,
//! `s_i' = -k_i sgn(s_i) + (alpha_i - alpha_hat_i)`; the updates of the other blocks
//! are jumps of `s_i'` that the monitor answers when they send `s_i` to its boundary.
//! Blocks due at the same update are solved in their order, each with the `v` its
//! predecessors just set (a block Gauss-Seidel sweep). The cost of an update is the
//! evaluation of `J_Omega` (and `beta` with the exact alpha) and the solves of the due
//! blocks, not a factorisation of all of `J_s`.

use std::collections::VecDeque;

use super::{Check, Controller, Switch};

/// Sweeps over the blocks at one update before it gives way to an update of every
/// row: each sweep solves the blocks whose rows the previous one sent outward from
/// their boundaries (a block Gauss-Seidel iteration on those rows, which converges for
/// the symmetric definite `J_Omega` of particle systems).
pub(crate) const MAX_SWEEPS: usize = 8;

/// What an update of blocks did.
pub(crate) struct BlockOutcome {
    /// Updated rows failing T 3.22 (when counted).
    pub(crate) failures: u64,
    /// No row next to a solved block was left on its boundary moving outward.
    pub(crate) settled: bool,
}
use crate::solve::{LinearSolver, SolveError, Solver, SolverChoice, SolverStats, Structure};
use crate::{Model, SimError};

/// One block: its rows, its own pattern and solver, and the entries of its rows in
/// other blocks' columns.
struct Block {
    rows: Vec<usize>,
    /// For each entry of the block's own pattern, its index in the model's pattern.
    inner: Vec<usize>,
    /// The rows of other blocks with an entry in this block's columns: the rows whose
    /// rate this block's update changes.
    kicked: Vec<usize>,
    /// Entries of the block's rows outside its columns: the index in the model's
    /// pattern, the row within the block, the column.
    outer: Vec<(usize, usize, usize)>,
    solver: Solver,
    values: Vec<f64>,
    scale: Vec<f64>,
    rhs: Vec<f64>,
    x: Vec<f64>,
}

/// The partition and the blocks due at the next update.
pub(crate) struct BlockSet {
    block_of: Vec<usize>,
    blocks: Vec<Block>,
    due: Vec<bool>,
    /// The model's pattern, for the rows of the kicked rates.
    structure: Structure,
    /// The blocks solved in the current sweep.
    solved: Vec<usize>,
    /// Block solves made (each one factorisation of a block).
    pub(crate) solves: u64,
}

/// Rows grouped into blocks of at most `size`: breadth-first over the graph of the
/// pattern from the lowest row not yet placed, cut every `size` rows and at the end of
/// each connected part. `O(m + nnz)`.
fn partition(st: &Structure, size: usize) -> Vec<Vec<usize>> {
    let mut placed = vec![false; st.m];
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    let mut queue = VecDeque::new();
    for root in 0..st.m {
        if placed[root] {
            continue;
        }
        placed[root] = true;
        queue.push_back(root);
        let mut current: Vec<usize> = Vec::with_capacity(size);
        while let Some(i) = queue.pop_front() {
            current.push(i);
            if current.len() == size {
                blocks.push(std::mem::take(&mut current));
            }
            for &j in st.neighbours(i) {
                if !placed[j] {
                    placed[j] = true;
                    queue.push_back(j);
                }
            }
        }
        if !current.is_empty() {
            blocks.push(current);
        }
    }
    blocks
}

/// A block solver's error with the block's rows named by the model's constraints.
fn to_model_rows(e: SolveError, rows: &[usize]) -> SolveError {
    match e {
        SolveError::Singular { constraints } => {
            let mut constraints: Vec<usize> = constraints.iter().map(|&i| rows[i]).collect();
            constraints.sort_unstable();
            SolveError::Singular { constraints }
        }
        SolveError::Breakdown { row } => SolveError::Breakdown { row: rows[row] },
        SolveError::NotSymmetric { row, col } => SolveError::NotSymmetric {
            row: rows[row],
            col: rows[col],
        },
        SolveError::NonFinite { row } => SolveError::NonFinite { row: rows[row] },
        SolveError::Pattern(p) => SolveError::Pattern(p),
    }
}

impl BlockSet {
    /// Blocks of at most `size` rows for the analysed pattern, each with an exact
    /// solver for its own pattern ([`SolverChoice::Auto`]).
    pub(crate) fn new(structure: &Structure, size: usize) -> Result<Self, SolveError> {
        let (m, pattern) = (structure.m, &structure.entries);
        let groups = partition(structure, size.max(1));
        let mut block_of = vec![0usize; m];
        let mut local = vec![0usize; m];
        for (b, rows) in groups.iter().enumerate() {
            for (l, &i) in rows.iter().enumerate() {
                block_of[i] = b;
                local[i] = l;
            }
        }
        let mut inner: Vec<Vec<usize>> = vec![Vec::new(); groups.len()];
        let mut sub: Vec<Vec<(usize, usize)>> = vec![Vec::new(); groups.len()];
        let mut outer: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); groups.len()];
        for (k, &(i, j)) in pattern.iter().enumerate() {
            let b = block_of[i];
            if block_of[j] == b {
                inner[b].push(k);
                sub[b].push((local[i], local[j]));
            } else {
                outer[b].push((k, local[i], j));
            }
        }
        let mut kicked: Vec<Vec<usize>> = vec![Vec::new(); groups.len()];
        for &(i, j) in pattern {
            let b = block_of[j];
            if block_of[i] != b {
                kicked[b].push(i);
            }
        }
        for k in &mut kicked {
            k.sort_unstable();
            k.dedup();
        }
        let mut blocks = Vec::with_capacity(groups.len());
        for (((rows, inner), (sub, outer)), kicked) in groups
            .into_iter()
            .zip(inner)
            .zip(sub.into_iter().zip(outer))
            .zip(kicked)
        {
            let n = rows.len();
            let solver =
                Solver::new(n, &sub, SolverChoice::Auto).map_err(|e| to_model_rows(e, &rows))?;
            blocks.push(Block {
                values: vec![0.0; inner.len()],
                inner,
                kicked,
                outer,
                solver,
                scale: vec![0.0; n],
                rhs: vec![0.0; n],
                x: vec![0.0; n],
                rows,
            });
        }
        Ok(Self {
            block_of,
            structure: structure.clone(),
            solved: Vec::with_capacity(blocks.len()),
            due: vec![false; blocks.len()],
            blocks,
            solves: 0,
        })
    }

    /// Row `i` asked for an update: its block is due.
    pub(crate) fn ask(&mut self, i: usize) {
        self.due[self.block_of[i]] = true;
    }

    /// Forget the blocks asked for (a global update serves them all).
    pub(crate) fn clear(&mut self) {
        self.due.fill(false);
    }

    /// Number of blocks and the most rows in one.
    pub(crate) fn shape(&self) -> (usize, usize) {
        let largest = self.blocks.iter().map(|b| b.rows.len()).max().unwrap_or(0);
        (self.blocks.len(), largest)
    }

    /// The block solvers' work, summed.
    pub(crate) fn stats(&self) -> SolverStats {
        let mut s = SolverStats::default();
        for b in &self.blocks {
            s.add(b.solver.stats());
        }
        s
    }

    /// Reset the block solvers' counts for a new run.
    pub(crate) fn reset(&mut self) {
        for b in &mut self.blocks {
            b.solver.reset_stats();
        }
        self.clear();
        self.solves = 0;
    }
}

impl Controller {
    /// The partition of block-local updates, if the law updates by blocks.
    pub(crate) fn blocks(&self) -> Option<&BlockSet> {
        self.blocks.as_ref()
    }

    /// [`Self::blocks`], to ask for blocks or clear them.
    pub(crate) fn blocks_mut(&mut self) -> Option<&mut BlockSet> {
        self.blocks.as_mut()
    }

    /// The law on the blocks that asked ([`BlockSet::ask`]), with `s`/`alpha_hat` from
    /// the last `sliding` call and `J_Omega` from the last evaluation, both at
    /// `(t, x, z)`; `v` of the other rows is kept. Evaluates `beta` (unless
    /// `check.beta_ready`): the rates of the rows next to a solved block need it.
    ///
    /// A solved block changes the rates of the rows next to it in other blocks; one of
    /// them on its layer boundary (within `tol`) and sent outward asks for its block in
    /// a further sweep at the same point, as the monitor would at once, up to
    /// [`MAX_SWEEPS`] sweeps. Returns the failing rows of T 3.22 (when counted) and
    /// whether the sweeps settled; if not, the caller updates every row.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn law_blocks<M: Model + ?Sized>(
        &mut self,
        model: &M,
        (t, x, z): (f64, &[f64], &[f64]),
        switch: Switch,
        check: Check,
        tol: f64,
        v: &mut [f64],
    ) -> Result<BlockOutcome, SimError> {
        if !check.beta_ready {
            model.beta(t, x, z, &mut self.beta);
            self.beta_evals += 1;
        }
        let Some(mut set) = self.blocks.take() else {
            return Ok(BlockOutcome {
                failures: 0,
                settled: true,
            });
        };
        let mut failures = 0;
        let mut settled = false;
        let mut result = Ok(());
        for _ in 0..MAX_SWEEPS {
            if let Err(e) = self.solve_due(&mut set, model, t, switch, check, v, &mut failures) {
                result = Err(e);
                break;
            }
            if !self.ask_kicked(&mut set, tol, v) {
                settled = true;
                break;
            }
        }
        set.clear();
        self.blocks = Some(set);
        self.global_stale = true;
        result.map(|()| BlockOutcome {
            failures: if check.count { failures } else { 0 },
            settled,
        })
    }

    /// Solve the due blocks in their order (each with the `v` its predecessors set),
    /// and clear them.
    #[allow(clippy::too_many_arguments)]
    fn solve_due<M: Model + ?Sized>(
        &self,
        set: &mut BlockSet,
        model: &M,
        t: f64,
        switch: Switch,
        check: Check,
        v: &mut [f64],
        failures: &mut u64,
    ) -> Result<(), SimError> {
        set.solved.clear();
        for (b, (blk, due)) in set.blocks.iter_mut().zip(&mut set.due).enumerate() {
            if !std::mem::take(due) {
                continue;
            }
            set.solved.push(b);
            for (value, &k) in blk.values.iter_mut().zip(&blk.inner) {
                *value = self.jvals[k];
            }
            for (scale, &i) in blk.scale.iter_mut().zip(&blk.rows) {
                *scale = self.mu_pow[i];
            }
            if let Err(e) = blk.solver.factor(&blk.values, &blk.scale) {
                return Err(self.solver_error(model, t, to_model_rows(e, &blk.rows)));
            }
            for (rhs, &i) in blk.rhs.iter_mut().zip(&blk.rows) {
                let (row, holds) = self.law_row(i, switch);
                if check.evaluate && !holds {
                    *failures += 1;
                }
                *rhs = row;
            }
            for &(k, l, j) in &blk.outer {
                blk.rhs[l] -= self.mu_pow[blk.rows[l]] * self.jvals[k] * v[j];
            }
            blk.solver.solve_from(&blk.rhs, &mut blk.x);
            for (&i, &xi) in blk.rows.iter().zip(&blk.x) {
                v[i] = xi;
            }
            set.solves += 1;
        }
        Ok(())
    }

    /// The rows next to the blocks just solved that are on their layer boundary
    /// (within `tol`) and now move outward: their blocks are due. Whether any is.
    fn ask_kicked(&self, set: &mut BlockSet, tol: f64, v: &[f64]) -> bool {
        let mut any = false;
        for &b in &set.solved {
            for &i in &set.blocks[b].kicked {
                let s = self.s[i];
                if s.abs() < self.eps[i] * (1.0 - tol) {
                    continue;
                }
                let st = &set.structure;
                let mut omega_rate = self.beta[i];
                for p in st.row_ptr[i]..st.row_ptr[i + 1] {
                    omega_rate += self.jvals[st.entry[p]] * v[st.cols[p]];
                }
                let rate = self.ah[i] + self.mu_pow[i] * omega_rate;
                if s * rate > 0.0 {
                    set.due[set.block_of[i]] = true;
                    any = true;
                }
            }
        }
        any
    }

    /// Whether block updates came after the last global factorisation, so that
    /// `z_eq` needs `J_s` factored again at the current point.
    pub(crate) fn global_factor_stale(&self) -> bool {
        self.global_stale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain_pattern(m: usize) -> Vec<(usize, usize)> {
        let mut p = Vec::new();
        for i in 0..m {
            if i > 0 {
                p.push((i, i - 1));
            }
            p.push((i, i));
            if i + 1 < m {
                p.push((i, i + 1));
            }
        }
        p
    }

    #[test]
    fn a_chain_is_cut_into_consecutive_segments() {
        let blocks = partition(&Structure::new(10, &chain_pattern(10)).unwrap(), 4);
        assert_eq!(blocks, vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7], vec![8, 9]]);
    }

    #[test]
    fn a_block_never_spans_two_unconnected_parts() {
        // Two chains of three rows, interleaved in the numbering.
        let p = [
            (0, 0),
            (2, 2),
            (4, 4),
            (0, 2),
            (2, 0),
            (2, 4),
            (4, 2),
            (1, 1),
            (3, 3),
            (5, 5),
            (1, 3),
            (3, 1),
            (3, 5),
            (5, 3),
        ];
        let blocks = partition(&Structure::new(6, &p).unwrap(), 5);
        assert_eq!(blocks, vec![vec![0, 2, 4], vec![1, 3, 5]]);
    }

    #[test]
    fn every_row_is_in_exactly_one_block() {
        // A 5 x 5 grid's 4-neighbour graph.
        let w = 5;
        let mut p = Vec::new();
        for i in 0..w * w {
            p.push((i, i));
            if i % w + 1 < w {
                p.push((i, i + 1));
                p.push((i + 1, i));
            }
            if i + w < w * w {
                p.push((i, i + w));
                p.push((i + w, i));
            }
        }
        let blocks = partition(&Structure::new(w * w, &p).unwrap(), 7);
        let mut seen = vec![0; w * w];
        for b in &blocks {
            assert!(!b.is_empty() && b.len() <= 7, "{b:?}");
            for &i in b {
                seen[i] += 1;
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "{seen:?}");
    }

    #[test]
    fn a_singular_block_names_the_models_rows() {
        let e = to_model_rows(
            SolveError::Singular {
                constraints: vec![1, 0],
            },
            &[7, 3],
        );
        assert_eq!(
            e,
            SolveError::Singular {
                constraints: vec![3, 7]
            }
        );
    }
}

//! What the solvers need to know about a pattern, computed once: rows in CSR order,
//! the diagonal and transposed entries, and the undirected graph of the off-diagonal
//! entries (for orderings, forests and chordality).

use super::SolveError;

/// Marks an absent entry in the index tables.
pub(crate) const NONE: usize = usize::MAX;

/// The analysed pattern of an `m x m` matrix whose values arrive in pattern order.
#[derive(Clone)]
pub(crate) struct Structure {
    pub(crate) m: usize,
    /// The pattern as given (the order of the values).
    pub(crate) entries: Vec<(usize, usize)>,
    /// CSR: row `i` holds `cols[row_ptr[i]..row_ptr[i+1]]` (ascending), whose values are
    /// `values[entry[p]]`.
    pub(crate) row_ptr: Vec<usize>,
    pub(crate) cols: Vec<usize>,
    pub(crate) entry: Vec<usize>,
    /// Entry index of `(i, i)`, or `NONE`.
    pub(crate) diag: Vec<usize>,
    /// For entry `e = (i, j)`, the entry index of `(j, i)`, or `NONE`.
    pub(crate) transpose: Vec<usize>,
    /// Whether every `(i, j)` has a `(j, i)`.
    pub(crate) symmetric: bool,
    /// The entries the symmetry check compares, in the pattern's order: `(e, t)` for
    /// each `(i, j)`, `i < j`, with `t` its mirror's entry (or `NONE`), and `(e, NONE)`
    /// for each `(i, j)`, `i > j`, without a mirror.
    symmetry_pairs: Vec<(usize, usize)>,
    /// Undirected graph of the off-diagonal entries (`(i, j)` or `(j, i)` present):
    /// neighbours of `i` are `adj[adj_ptr[i]..adj_ptr[i+1]]`, ascending.
    pub(crate) adj_ptr: Vec<usize>,
    pub(crate) adj: Vec<usize>,
}

impl Structure {
    /// Analyse a pattern; rejects entries outside `m x m` and duplicates.
    pub(crate) fn new(m: usize, pattern: &[(usize, usize)]) -> Result<Self, SolveError> {
        if let Some(&(i, j)) = pattern.iter().find(|(i, j)| *i >= m || *j >= m) {
            return Err(SolveError::Pattern(format!(
                "pattern entry ({i}, {j}) outside {m} x {m}"
            )));
        }
        let nnz = pattern.len();
        let mut order: Vec<usize> = (0..nnz).collect();
        order.sort_unstable_by_key(|&e| pattern[e]);
        if let Some(w) = order.windows(2).find(|w| pattern[w[0]] == pattern[w[1]]) {
            let (i, j) = pattern[w[0]];
            return Err(SolveError::Pattern(format!(
                "pattern entry ({i}, {j}) is listed twice"
            )));
        }
        let mut row_ptr = vec![0; m + 1];
        for &(i, _) in pattern {
            row_ptr[i + 1] += 1;
        }
        for i in 0..m {
            row_ptr[i + 1] += row_ptr[i];
        }
        let cols: Vec<usize> = order.iter().map(|&e| pattern[e].1).collect();
        let entry = order;
        let mut diag = vec![NONE; m];
        for (p, &e) in entry.iter().enumerate() {
            let (i, j) = pattern[e];
            debug_assert!(p >= row_ptr[i] && p < row_ptr[i + 1]);
            if i == j {
                diag[i] = e;
            }
        }
        let find = |i: usize, j: usize| -> usize {
            let row = &cols[row_ptr[i]..row_ptr[i + 1]];
            row.binary_search(&j)
                .map_or(NONE, |k| entry[row_ptr[i] + k])
        };
        let transpose: Vec<usize> = pattern.iter().map(|&(i, j)| find(j, i)).collect();
        let symmetric = transpose.iter().all(|&t| t != NONE);
        let symmetry_pairs = pattern
            .iter()
            .enumerate()
            .filter(|&(e, &(i, j))| i < j || (i > j && transpose[e] == NONE))
            .map(|(e, _)| (e, transpose[e]))
            .collect();
        // Undirected off-diagonal graph, deduplicated.
        let mut deg = vec![0usize; m + 1];
        for (e, &(i, j)) in pattern.iter().enumerate() {
            if i != j && (transpose[e] == NONE || i < j) {
                deg[i + 1] += 1;
                deg[j + 1] += 1;
            }
        }
        for i in 0..m {
            deg[i + 1] += deg[i];
        }
        let adj_ptr = deg;
        let mut fill = adj_ptr.clone();
        let mut adj = vec![0; adj_ptr[m]];
        for (e, &(i, j)) in pattern.iter().enumerate() {
            if i != j && (transpose[e] == NONE || i < j) {
                adj[fill[i]] = j;
                fill[i] += 1;
                adj[fill[j]] = i;
                fill[j] += 1;
            }
        }
        for i in 0..m {
            adj[adj_ptr[i]..adj_ptr[i + 1]].sort_unstable();
        }
        Ok(Self {
            m,
            entries: pattern.to_vec(),
            row_ptr,
            cols,
            entry,
            diag,
            transpose,
            symmetric,
            symmetry_pairs,
            adj_ptr,
            adj,
        })
    }

    /// Neighbours of `i` in the undirected off-diagonal graph.
    pub(crate) fn neighbours(&self, i: usize) -> &[usize] {
        &self.adj[self.adj_ptr[i]..self.adj_ptr[i + 1]]
    }

    /// Row of the CSR slot `p`.
    pub(crate) fn row_of(&self, p: usize) -> usize {
        self.entries[self.entry[p]].0
    }

    /// Number of undirected off-diagonal edges.
    pub(crate) fn edges(&self) -> usize {
        self.adj.len() / 2
    }

    /// Whether every diagonal entry is in the pattern.
    pub(crate) fn has_full_diagonal(&self) -> bool {
        self.diag.iter().all(|&d| d != NONE)
    }

    /// Whether the undirected graph has no cycle (union-find over the edges).
    pub(crate) fn is_forest(&self) -> bool {
        let mut parent: Vec<usize> = (0..self.m).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for i in 0..self.m {
            for &j in self.neighbours(i) {
                if j > i {
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    if a == b {
                        return false;
                    }
                    parent[a] = b;
                }
            }
        }
        true
    }

    /// Whether the values are symmetric: `|a_ij - a_ji| <= tol * scale` for every pair
    /// (false for an unsymmetric pattern). Returns the first offending entry if not.
    pub(crate) fn asymmetry(&self, values: &[f64], scale: f64) -> Option<(usize, usize)> {
        let tol = 1e-12 * scale;
        self.symmetry_pairs
            .iter()
            .find(|&&(e, t)| {
                let other = if t == NONE { 0.0 } else { values[t] };
                (values[e] - other).abs() > tol
            })
            .map(|&(e, _)| self.entries[e])
    }
}

//! The structural rank of a sparse pattern by bipartite matching (rows to columns), the
//! initial check of a large `J_Omega` that needs no dense decomposition.

/// The result of [`structural_rank`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructuralRank {
    /// The size of a maximum matching of rows to columns through the entries: the
    /// largest rank any values on this pattern can give.
    pub rank: usize,
    /// Rows left unmatched by that matching (empty when `rank == n`): constraints that
    /// no choice of values makes independent of the others.
    pub unmatched_rows: Vec<usize>,
}

/// The structural rank of an `n x n` pattern of `(row, col)` entries: a greedy matching
/// completed by augmenting paths (depth-first, iterative: no recursion, whatever the
/// length of the path). Linear in the entries on the patterns of particle models (the
/// greedy pass matches almost every row, each augmentation is short); `O(n nnz)` in the
/// worst case.
pub fn structural_rank(n: usize, entries: &[(usize, usize)]) -> StructuralRank {
    // Rows as CSR.
    let mut start = vec![0usize; n + 1];
    for &(r, _) in entries {
        start[r + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut cols = vec![0usize; entries.len()];
    let mut fill = start.clone();
    for &(r, c) in entries {
        cols[fill[r]] = c;
        fill[r] += 1;
    }
    const NONE: usize = usize::MAX;
    let mut row_of = vec![NONE; n]; // column -> matched row
    let mut col_of = vec![NONE; n]; // row -> matched column
    for r in 0..n {
        if let Some(&c) = cols[start[r]..start[r + 1]]
            .iter()
            .find(|&&c| row_of[c] == NONE)
        {
            row_of[c] = r;
            col_of[r] = c;
        }
    }
    let mut seen = vec![NONE; n]; // column -> the augmentation that visited it
    // The path: (row, next entry to try).
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let mut unmatched_rows = Vec::new();
    for root in 0..n {
        if col_of[root] != NONE {
            continue;
        }
        stack.clear();
        stack.push((root, start[root]));
        let mut found = NONE;
        while let Some(top) = stack.last_mut() {
            let (r, next) = *top;
            if next == start[r + 1] {
                stack.pop();
                continue;
            }
            top.1 += 1;
            let c = cols[next];
            if seen[c] == root {
                continue;
            }
            seen[c] = root;
            if row_of[c] == NONE {
                found = c;
                break;
            }
            let r2 = row_of[c];
            stack.push((r2, start[r2]));
        }
        if found == NONE {
            unmatched_rows.push(root);
            continue;
        }
        // Flip the path: each row on the stack takes the column it reached.
        let mut c = found;
        while let Some((r, _)) = stack.pop() {
            let previous = col_of[r];
            row_of[c] = r;
            col_of[r] = c;
            c = previous;
        }
    }
    StructuralRank {
        rank: n - unmatched_rows.len(),
        unmatched_rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_and_deficient_patterns() {
        // A path needs augmentation when the greedy pass takes the wrong column.
        let path = [(0, 0), (0, 1), (1, 0)];
        assert_eq!(structural_rank(2, &path).rank, 2);
        // Two rows that only reach one column.
        let r = structural_rank(3, &[(0, 0), (1, 0), (2, 1), (2, 2)]);
        assert_eq!(r.rank, 2);
        assert_eq!(r.unmatched_rows, vec![1]);
        // A long chain whose greedy matching is off by one everywhere: row i reaches
        // columns i + 1 (first) and i.
        let n = 10_000;
        let mut e = Vec::new();
        for i in 0..n {
            if i + 1 < n {
                e.push((i, i + 1));
            }
            e.push((i, i));
        }
        assert_eq!(structural_rank(n, &e).rank, n);
        assert_eq!(structural_rank(0, &[]).rank, 0);
    }
}

//! Which constraints the others imply: the numerical rank of `J_Omega` and the rows it
//! does not need, for the reports of a singular `J_Omega` (a cloth with rigid diagonals,
//! a constraint written twice, a linkage over-constrained in the plane).
//!
//! The rows are taken one by one, in the order of the classes the caller gives (the
//! constraint families in the order they were declared, so that a later family is the
//! one found implied by an earlier one) and, within a class, in the fill-reducing order
//! of the sparse solver (minimum degree on the pattern's graph). Each row, scaled to a
//! largest entry of one, is reduced against the rows kept before it (sparse
//! elimination: each kept row has its pivot on its diagonal where that entry is at least
//! a tenth of the row's largest, else at its largest, and is zero at the pivots of the
//! rows kept before it, so that reducing in the order the rows were kept never brings
//! back a pivot already cleared). A row is implied by the rows before it when its
//! remainder is negligible: on a symmetric `J_Omega` that behaves as a semidefinite one
//! (the particle models' `-G M^-1 G^T`; a sign no such matrix has switches to the other
//! test), when the remainder's diagonal, a squared distance of the row's factor from
//! the span of those before it, falls to `1e-10` of the row's diagonal (the pivot is
//! then always the diagonal); otherwise when its largest entry falls to `1e-10` of the
//! largest magnitude met while reducing it. Otherwise it is kept. The multipliers are
//! recorded, so that the combination of rows that
//! annihilates an implied row (`y^T J_Omega = 0`) can be written out afterwards
//! ([`Redundancy::combination`]).
//!
//! A row whose pivot is weak (its remainder small, not negligible: nearly dependent)
//! is taken again after all the others: kept early, its large multipliers would amplify
//! the rounding of every row reduced by it, and rows that are exactly implied would come
//! out kept.
//!
//! Cost: a row implied by the rows of earlier classes is reduced against all of them,
//! which on a cloth with rigid diagonals costs about the whole factor per diagonal,
//! `O(m^2)` in all; past a budget ([`Redundancy::by_class`]) the rows are taken in the
//! solver's order alone, where the work is that of the sparse factor.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::SolveError;
use super::Structure;

/// Relative size of a remainder below which a row counts as implied: a few hundred
/// roundings of the magnitudes the elimination met.
const IMPLIED_TOL: f64 = 1e-10;

/// For a symmetric semidefinite matrix, the relative size of the remainder's diagonal
/// (a squared distance: `1e-10` is a distance of `1e-5` of the row's factor from the
/// span of the rows before it) below which a row counts as implied.
const IMPLIED_TOL_SQUARED: f64 = 1e-10;

/// A pivot below this (relative, squared as [`IMPLIED_TOL_SQUARED`]) is weak: its row
/// is taken again after the others.
const WEAK_PIVOT: f64 = 1e-3;

/// A remainder's diagonal of the wrong sign beyond this (relative) says the matrix is
/// not semidefinite.
const INDEFINITE_TOL: f64 = 1e-6;

/// The rank of `J_Omega` and its implied rows; see the module documentation.
#[derive(Debug, Clone)]
pub struct Redundancy {
    by_class: bool,
    m: usize,
    rank: usize,
    implied: Vec<usize>,
    /// Per row (original numbering): its scale (1 / largest entry) and the multipliers
    /// of the kept rows subtracted from it: `row_i * scale_i - sum mult_k kept_k =
    /// remainder_i`.
    scale: Vec<f64>,
    steps: Vec<Vec<(usize, f64)>>,
    /// The original row of each kept row, and its pivot column.
    kept_row: Vec<usize>,
    kept_pivot: Vec<usize>,
}

const NONE: usize = usize::MAX;

/// When a row counts as implied.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Test {
    /// Its remainder's diagonal is negligible against its diagonal (a symmetric
    /// semidefinite matrix: `J_Omega = -G M^-1 G^T` of particle models).
    Diagonal,
    /// Its remainder's largest entry is negligible against the largest magnitude met.
    Row,
}

enum Outcome {
    Done(Redundancy),
    OverBudget,
    /// A sign no semidefinite matrix has: the diagonal test does not apply.
    Indefinite,
}

/// Whether the values are symmetric to a relative `1e-9` of the largest.
fn symmetric(st: &Structure, values: &[f64]) -> bool {
    let top = values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    st.symmetric
        && st
            .transpose
            .iter()
            .enumerate()
            .all(|(e, &t)| (values[e] - values[t]).abs() <= 1e-9 * top)
}

/// What the analysis needs of a pattern, found once: its structure, the order of its
/// rows by class (within a class, the solver's fill-reducing order) and that order
/// alone.
#[derive(Clone)]
pub(crate) struct Orders {
    st: Structure,
    by_class: Vec<usize>,
    elimination: Vec<usize>,
}

impl Orders {
    /// The orders of an `m x m` pattern whose rows have the classes `class`.
    pub(crate) fn new(
        m: usize,
        pattern: &[(usize, usize)],
        class: &[usize],
    ) -> Result<Self, SolveError> {
        if class.len() != m {
            return Err(SolveError::Pattern(format!(
                "{} classes for {m} rows",
                class.len()
            )));
        }
        let st = Structure::new(m, pattern)?;
        let (elimination, _) = super::order::elimination_order(&st);
        let mut position = vec![0usize; m];
        for (k, &i) in elimination.iter().enumerate() {
            position[i] = k;
        }
        let mut by_class: Vec<usize> = (0..m).collect();
        by_class.sort_unstable_by_key(|&i| (class[i], position[i]));
        Ok(Orders {
            st,
            by_class,
            elimination,
        })
    }

    /// The rows of the pattern.
    pub(crate) fn rows(&self) -> usize {
        self.st.m
    }
}

/// The multiply-adds the elimination in the order of the classes may spend before it
/// gives way to the solver's order (about a tenth of a second): a row implied by rows
/// of earlier classes is reduced against all of them, which on a cloth with rigid
/// diagonals costs about the whole factor per diagonal, `O(m^2)` in all.
pub(crate) const CLASS_ORDER_BUDGET: u64 = 100_000_000;

impl Redundancy {
    /// The analysis of the `m x m` matrix with `pattern` and `values` (in pattern
    /// order), its rows taken class by class (`class[i]` of row `i`, ascending; see the
    /// module documentation). A pattern entry outside `m x m` or repeated, or `class`
    /// not of length `m`, is an error. A row of zeros, or one with a non-finite entry,
    /// counts as implied (it determines nothing).
    pub fn of(
        m: usize,
        pattern: &[(usize, usize)],
        values: &[f64],
        class: &[usize],
    ) -> Result<Self, SolveError> {
        Self::of_budgeted(m, pattern, values, class, CLASS_ORDER_BUDGET)
    }

    fn of_budgeted(
        m: usize,
        pattern: &[(usize, usize)],
        values: &[f64],
        class: &[usize],
        budget: u64,
    ) -> Result<Self, SolveError> {
        if values.len() != pattern.len() {
            return Err(SolveError::Pattern(format!(
                "{} values for {} entries",
                values.len(),
                pattern.len()
            )));
        }
        let orders = Orders::new(m, pattern, class)?;
        Ok(Self::with_orders(&orders, values, budget))
    }

    /// The analysis with the orders of the pattern found once ([`Orders`]), for a
    /// pattern analysed at many values (the reduced solver's factorisations).
    pub(crate) fn with_orders(orders: &Orders, values: &[f64], budget: u64) -> Self {
        let (st, order, elimination) = (&orders.st, &orders.by_class, &orders.elimination);
        let mut test = if symmetric(st, values) {
            Test::Diagonal
        } else {
            Test::Row
        };
        let mut budget = Some(budget);
        loop {
            let rows = if budget.is_some() { order } else { elimination };
            match Self::in_order(st, values, rows, budget, test) {
                Outcome::Done(mut r) => {
                    r.by_class = budget.is_some();
                    return r;
                }
                Outcome::OverBudget => budget = None,
                Outcome::Indefinite => test = Test::Row,
            }
        }
    }

    /// The analysis with the rows taken in `order`, stopped once the elimination has
    /// spent more than `budget` multiply-adds, or (diagonal test) at a sign that a
    /// semidefinite matrix cannot have.
    fn in_order(
        st: &Structure,
        values: &[f64],
        order: &[usize],
        budget: Option<u64>,
        test: Test,
    ) -> Outcome {
        // The sign of the diagonal of a semidefinite matrix (0: not seen yet).
        let mut sign = 0.0f64;
        let mut spent = 0u64;
        let m = st.m;
        // Kept rows, sparse, each with its pivot column.
        let mut kept: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut kept_row = Vec::new();
        let mut kept_max: Vec<f64> = Vec::new();
        let mut pivot_of_col = vec![NONE; m]; // column -> kept row whose pivot it is
        let mut work = vec![0.0f64; m];
        let mut in_work = vec![false; m];
        let mut nonzero: Vec<usize> = Vec::new();
        let mut heap: BinaryHeap<Reverse<usize>> = BinaryHeap::new();
        // Kept rows waiting in the heap (each at most once per reduced row).
        let mut queued = vec![false; m];
        let mut scale = vec![0.0; m];
        let mut steps = vec![Vec::new(); m];
        let mut implied = Vec::new();
        // Rows whose pivot is weak (nearly dependent, not negligibly) go to the end of the
        // queue once: kept early, their large multipliers would amplify the rounding of
        // every row reduced by them.
        let mut queue: Vec<usize> = order.to_vec();
        let first_pass = queue.len();
        let mut next = 0;
        while next < queue.len() {
            let i = queue[next];
            let may_defer = next < first_pass;
            next += 1;
            let range = st.row_ptr[i]..st.row_ptr[i + 1];
            let mut big = 0.0f64;
            let mut finite = true;
            for p in range.clone() {
                let v = values[st.entry[p]];
                finite &= v.is_finite();
                big = big.max(v.abs());
            }
            if big == 0.0 || !finite {
                implied.push(i);
                continue;
            }
            scale[i] = 1.0 / big;
            nonzero.clear();
            let diag0 = match st.diag[i] {
                NONE => 0.0,
                e => values[e] * scale[i],
            };
            if test == Test::Diagonal {
                if diag0 == 0.0 || sign * diag0 < 0.0 {
                    return Outcome::Indefinite;
                }
                sign = diag0.signum();
            }
            for p in range {
                let c = st.cols[p];
                work[c] = values[st.entry[p]] * scale[i];
                in_work[c] = true;
                nonzero.push(c);
                let q = pivot_of_col[c];
                if q != NONE && !queued[q] {
                    queued[q] = true;
                    heap.push(Reverse(q));
                }
            }
            let mut peak = 1.0f64;
            // The magnitudes subtracted from the diagonal (its rounding grows with them).
            let mut subtracted = 0.0f64;
            while let Some(Reverse(k)) = heap.pop() {
                queued[k] = false;
                let row = &kept[k];
                let pivot_col = row[0].0;
                let w = work[pivot_col];
                if w == 0.0 {
                    continue;
                }
                let mult = w / row[0].1;
                steps[i].push((k, mult));
                spent += row.len() as u64;
                if budget.is_some_and(|b| spent > b) {
                    return Outcome::OverBudget;
                }
                // A bound of the magnitudes this step writes (each kept row's largest
                // entry is its pivot or within ten times it).
                peak = peak.max((mult * kept_max[k]).abs());
                for &(c, v) in row.iter() {
                    if !in_work[c] {
                        in_work[c] = true;
                        nonzero.push(c);
                        work[c] = 0.0;
                    }
                    work[c] -= mult * v;
                    if c == i {
                        subtracted += (mult * v).abs();
                    }
                    let q = pivot_of_col[c];
                    if q != NONE && q > k && !queued[q] {
                        queued[q] = true;
                        heap.push(Reverse(q));
                    }
                }
                work[pivot_col] = 0.0;
            }
            // The remainder: its diagonal or its largest entry is the new pivot, unless
            // it is negligible.
            let mut best = (NONE, 0.0f64);
            for &c in &nonzero {
                if pivot_of_col[c] == NONE && work[c].abs() > best.1.abs() {
                    best = (c, work[c]);
                }
            }
            let own = if in_work[i] && pivot_of_col[i] == NONE {
                work[i]
            } else {
                0.0
            };
            let negligible = match test {
                // A semidefinite matrix: the remainder's diagonal is the squared distance
                // of the row's factor from the span of those before it, computed to a
                // few roundings of the original diagonal; a zero diagonal there means a
                // zero row.
                Test::Diagonal => {
                    let size = diag0.abs().max(subtracted);
                    let negligible = own.abs() <= IMPLIED_TOL_SQUARED * size;
                    if sign * own < -INDEFINITE_TOL * size {
                        return Outcome::Indefinite;
                    }
                    negligible
                }
                Test::Row => best.0 == NONE || best.1.abs() <= IMPLIED_TOL * peak,
            };
            // The diagonal is the pivot of a semidefinite row, and of any other row where
            // it is at least a tenth of the largest entry.
            let diagonal_pivot = match test {
                Test::Diagonal => !negligible,
                Test::Row => own != 0.0 && own.abs() >= 0.1 * best.1.abs(),
            };
            if diagonal_pivot {
                best = (i, own);
            }
            let weak = match test {
                Test::Diagonal => own.abs() < WEAK_PIVOT * diag0.abs(),
                Test::Row => best.1.abs() < WEAK_PIVOT.sqrt() * peak,
            };
            if negligible {
                implied.push(i);
            } else if weak && may_defer {
                steps[i].clear();
                queue.push(i);
            } else {
                let mut row = vec![best];
                for &c in &nonzero {
                    if c != best.0 && pivot_of_col[c] == NONE && work[c] != 0.0 {
                        row.push((c, work[c]));
                    }
                }
                kept_max.push(row.iter().fold(0.0f64, |s, (_, v)| s.max(v.abs())));
                pivot_of_col[best.0] = kept.len();
                kept.push(row);
                kept_row.push(i);
            }
            for &c in &nonzero {
                work[c] = 0.0;
                in_work[c] = false;
            }
        }
        implied.sort_unstable();
        let kept_pivot = kept.iter().map(|row| row[0].0).collect();
        Outcome::Done(Redundancy {
            kept_pivot,
            by_class: true,
            m,
            rank: kept.len(),
            implied,
            scale,
            steps,
            kept_row,
        })
    }

    /// Whether the rows were taken in the order of their classes (else, past a budget of
    /// 10^8 multiply-adds, in the solver's fill-reducing order alone: the rank is the
    /// same, and the implied rows are a set whose removal leaves the others independent,
    /// not necessarily in the latest classes).
    pub fn by_class(&self) -> bool {
        self.by_class
    }

    /// The kept rows with their pivot columns, `(row, column)`, in the order they were
    /// kept: the kept rows restricted to these columns are a nonsingular system.
    pub fn kept_pivots(&self) -> Vec<(usize, usize)> {
        self.kept_row
            .iter()
            .copied()
            .zip(self.kept_pivot.iter().copied())
            .collect()
    }

    /// The numerical rank.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// The rows that the rows taken before them imply, ascending (`m - rank` of them):
    /// without them the others are independent.
    pub fn implied(&self) -> &[usize] {
        &self.implied
    }

    /// For an implied `row`: the combination `y` of rows (index, coefficient) with
    /// `y^T J_Omega = 0` to the tolerance, its own coefficient 1 and every other row one
    /// taken before it; empty for a row that is not implied. A zero or non-finite row is its
    /// own combination (`[(row, 1)]`).
    pub fn combination(&self, row: usize) -> Vec<(usize, f64)> {
        if row >= self.m || self.implied.binary_search(&row).is_err() {
            return Vec::new();
        }
        // row * scale - sum_k mult_k kept_k = 0, and each kept row is its original row
        // (scaled) minus the kept rows it was reduced by: unfold from the latest kept
        // row down, so that every kept row's coefficient is complete when it is unfolded.
        let mut on_kept = vec![0.0f64; self.rank];
        let mut y = vec![(row, 1.0)];
        for &(k, mult) in &self.steps[row] {
            on_kept[k] -= mult / self.scale[row];
        }
        for k in (0..self.rank).rev() {
            let a = on_kept[k];
            if a == 0.0 {
                continue;
            }
            let orig = self.kept_row[k];
            // kept_k = orig * scale_orig - sum mult_j kept_j.
            y.push((orig, a * self.scale[orig]));
            for &(j, mult) in &self.steps[orig] {
                on_kept[j] -= a * mult;
            }
        }
        let big = y.iter().fold(0.0f64, |s, (_, v)| s.max(v.abs()));
        y.retain(|(_, v)| v.abs() > 1e-9 * big);
        y.sort_unstable_by_key(|(i, _)| *i);
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::tests::Lcg;
    use nalgebra::DMatrix;

    /// The pattern (nonzeros) and values of a dense matrix.
    fn sparse(a: &DMatrix<f64>) -> (Vec<(usize, usize)>, Vec<f64>) {
        let mut pattern = Vec::new();
        let mut values = Vec::new();
        for i in 0..a.nrows() {
            for j in 0..a.ncols() {
                if a[(i, j)] != 0.0 {
                    pattern.push((i, j));
                    values.push(a[(i, j)]);
                }
            }
        }
        (pattern, values)
    }

    /// The rank by singular values, the oracle.
    fn svd_rank(a: &DMatrix<f64>) -> usize {
        let sv = a.clone().svd(false, false).singular_values;
        let top = sv.max();
        sv.iter().filter(|&&s| s > 1e-9 * top).count()
    }

    /// Every implied row's combination annihilates the matrix, relative to its size.
    fn assert_combinations_annihilate(a: &DMatrix<f64>, r: &Redundancy) {
        let top = a.amax();
        for &row in r.implied() {
            let y = r.combination(row);
            assert!(y.contains(&(row, 1.0)), "row {row}: {y:?}");
            let scale = y.iter().fold(0.0f64, |s, (_, v)| s.max(v.abs()));
            for j in 0..a.ncols() {
                let s: f64 = y.iter().map(|&(i, v)| v * a[(i, j)]).sum();
                assert!(
                    s.abs() <= 1e-9 * top * scale,
                    "row {row}, column {j}: {s:e}"
                );
            }
        }
    }

    #[test]
    fn random_products_of_known_rank() {
        let mut rng = Lcg(7);
        for (m, r) in [(1, 0), (5, 5), (12, 7), (30, 1), (40, 39)] {
            let b = DMatrix::from_fn(m, r, |_, _| rng.next());
            let c = DMatrix::from_fn(r, m, |_, _| rng.next());
            let a = &b * &c;
            let (pattern, values) = sparse(&a);
            let red = Redundancy::of(m, &pattern, &values, &vec![0; m]).unwrap();
            assert_eq!(red.rank(), svd_rank(&a), "m = {m}, r = {r}");
            assert_eq!(red.rank(), r);
            assert_eq!(red.implied().len(), m - r);
            assert_combinations_annihilate(&a, &red);
        }
    }

    /// `G G^T` of a planar grid of particles with both diagonals of every square as
    /// rigid links (the cloth with rigid shear): more links than coordinates, so a rank
    /// of `G`'s, and the implied rows are diagonals (the links along the grid come
    /// first and are independent).
    #[test]
    fn a_flat_grid_with_both_diagonals_implies_diagonals() {
        for w in [4, 12] {
            flat_grid_with_both_diagonals(w);
        }
    }

    fn flat_grid_with_both_diagonals(w: usize) {
        let id = |i: usize, j: usize| i + w * j;
        let mut links = Vec::new();
        for j in 0..w {
            for i in 0..w - 1 {
                links.push((id(i, j), id(i + 1, j)));
                links.push((id(j, i), id(j, i + 1)));
            }
        }
        let along = links.len();
        for j in 0..w - 1 {
            for i in 0..w - 1 {
                links.push((id(i, j), id(i + 1, j + 1)));
                links.push((id(i + 1, j), id(i, j + 1)));
            }
        }
        // Slightly uneven positions, so that no link is parallel to another by
        // accident; the particle 0 pinned (its coordinates left out).
        let mut rng = Lcg(3);
        let pos: Vec<(f64, f64)> = (0..w * w)
            .map(|p| {
                let (i, j) = (p % w, p / w);
                (i as f64 + 0.1 * rng.next(), j as f64 + 0.1 * rng.next())
            })
            .collect();
        let n = 2 * (w * w - 1);
        let mut g = DMatrix::zeros(links.len(), n);
        for (l, &(a, b)) in links.iter().enumerate() {
            let d = (pos[b].0 - pos[a].0, pos[b].1 - pos[a].1);
            for (p, sign) in [(a, -1.0), (b, 1.0)] {
                if p > 0 {
                    g[(l, 2 * (p - 1))] += sign * d.0;
                    g[(l, 2 * (p - 1) + 1)] += sign * d.1;
                }
            }
        }
        let j = &g * g.transpose();
        let (pattern, values) = sparse(&j);
        let class: Vec<usize> = (0..links.len()).map(|l| usize::from(l >= along)).collect();
        let red = Redundancy::of(links.len(), &pattern, &values, &class).unwrap();
        assert_eq!(red.rank(), svd_rank(&g));
        // A grid pinned at one particle still turns about it: one coordinate direction
        // no link resists, so the rank is one short of the coordinates.
        assert_eq!(red.rank(), n - 1);
        assert_eq!(red.implied().len(), links.len() - (n - 1));
        assert!(red.by_class());
        assert!(
            red.implied().iter().all(|&l| l >= along),
            "{:?}",
            red.implied()
        );
        assert_combinations_annihilate(&j, &red);
        // Past its budget the order of the classes gives way to the solver's: the same
        // rank, and implied rows that are still implied.
        let fast = Redundancy::of_budgeted(links.len(), &pattern, &values, &class, 10).unwrap();
        assert!(!fast.by_class());
        assert_eq!(
            (fast.rank(), fast.implied().len()),
            (red.rank(), red.implied().len())
        );
        assert_combinations_annihilate(&j, &fast);
    }

    #[test]
    fn a_repeated_a_zero_and_a_non_finite_row_are_implied() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                2.0, 1.0, 0.0, 0.0, //
                4.0, 2.0, 0.0, 0.0, //
                0.0, 0.0, 0.0, 0.0, //
                0.0, 1.0, 3.0, 1.0,
            ],
        );
        let (pattern, values) = sparse(&a);
        let red = Redundancy::of(4, &pattern, &values, &[0, 1, 2, 3]).unwrap();
        assert_eq!(red.rank(), 2);
        assert_eq!(red.implied(), [1, 2]);
        assert_eq!(red.combination(1), [(0, -2.0), (1, 1.0)]);
        assert_eq!(red.combination(2), [(2, 1.0)]);
        assert!(red.combination(0).is_empty());
        let nan = Redundancy::of(2, &[(0, 0), (1, 1)], &[1.0, f64::NAN], &[0, 0]).unwrap();
        assert_eq!((nan.rank(), nan.implied()), (1, &[1][..]));
        assert!(Redundancy::of(2, &[(0, 2)], &[1.0], &[0, 0]).is_err());
        assert!(Redundancy::of(2, &[(0, 0)], &[1.0], &[0]).is_err());
    }

    /// Symmetric matrices take the diagonal test while they behave as semidefinite ones,
    /// and the row test once a sign says they are not.
    #[test]
    fn symmetric_indefinite_matrices_fall_back_to_the_row_test() {
        let cases: [(&[f64], usize); 4] = [
            (&[0.0, 1.0, 1.0, 0.0], 2),   // a zero diagonal: indefinite, full rank
            (&[1.0, 2.0, 2.0, 1.0], 2),   // the Schur complement -3: indefinite
            (&[1.0, 2.0, 2.0, 4.0], 1),   // semidefinite, rank 1
            (&[-2.0, 1.0, 1.0, -0.5], 1), // negative semidefinite, rank 1
        ];
        for (v, rank) in cases {
            let a = DMatrix::from_row_slice(2, 2, v);
            let pattern = [(0, 0), (0, 1), (1, 0), (1, 1)];
            let red = Redundancy::of(2, &pattern, v, &[0, 0]).unwrap();
            assert_eq!(red.rank(), rank, "{v:?}");
            assert_eq!(red.rank(), svd_rank(&a), "{v:?}");
            assert_combinations_annihilate(&a, &red);
        }
    }
}

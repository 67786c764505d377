//! A small dense LU with partial pivoting in a preallocated buffer: the baselines factor
//! an `m x m` matrix at every stage, and allocating there would bias their timings.

/// The matrix was singular (pivot negligible against the matrix scale) or not finite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Singular {
    /// The elimination step at which no usable pivot was left.
    pub column: usize,
}

/// Relative pivot size under which the matrix is declared singular.
const PIVOT_TOL: f64 = 1e-14;

/// Dense LU factors of an `n x n` row-major matrix, written into `a` before
/// [`Lu::factor`].
#[derive(Debug, Clone)]
pub struct Lu {
    n: usize,
    /// Row-major matrix; after factoring, packed `L\U` (unit lower diagonal).
    pub a: Vec<f64>,
    perm: Vec<usize>,
}

impl Lu {
    /// Buffers for an `n x n` matrix.
    pub fn new(n: usize) -> Self {
        Self {
            n,
            a: vec![0.0; n * n],
            perm: vec![0; n],
        }
    }

    /// Factor `a` in place.
    pub fn factor(&mut self) -> Result<(), Singular> {
        let n = self.n;
        let scale = self.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !scale.is_finite() || scale == 0.0 {
            return Err(Singular { column: 0 });
        }
        let tol = PIVOT_TOL * scale;
        for k in 0..n {
            let mut p = k;
            for r in k + 1..n {
                if self.a[r * n + k].abs() > self.a[p * n + k].abs() {
                    p = r;
                }
            }
            let piv = self.a[p * n + k];
            if piv.is_nan() || piv.abs() <= tol {
                return Err(Singular { column: k });
            }
            self.perm[k] = p;
            if p != k {
                for c in 0..n {
                    self.a.swap(k * n + c, p * n + c);
                }
            }
            for r in k + 1..n {
                let l = self.a[r * n + k] / piv;
                self.a[r * n + k] = l;
                if l != 0.0 {
                    for c in k + 1..n {
                        self.a[r * n + c] -= l * self.a[k * n + c];
                    }
                }
            }
        }
        Ok(())
    }

    /// Solve `A y = b` in place with the factors.
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        for k in 0..n {
            b.swap(k, self.perm[k]);
        }
        for r in 0..n {
            let row = &self.a[r * n..r * n + r];
            let dot: f64 = row.iter().zip(&b[..r]).map(|(l, y)| l * y).sum();
            b[r] -= dot;
        }
        for r in (0..n).rev() {
            let row = &self.a[r * n + r + 1..(r + 1) * n];
            let dot: f64 = row.iter().zip(&b[r + 1..n]).map(|(u, y)| u * y).sum();
            b[r] = (b[r] - dot) / self.a[r * n + r];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let m = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.5, 4.0];
        let y_true = [1.5, -2.0, 0.25];
        let mut b = [0.0; 3];
        for r in 0..3 {
            b[r] = (0..3).map(|c| m[r * 3 + c] * y_true[c]).sum();
        }
        let mut lu = Lu::new(3);
        lu.a.copy_from_slice(&m);
        lu.factor().unwrap();
        lu.solve(&mut b);
        for (y, t) in b.iter().zip(y_true) {
            assert!((y - t).abs() < 1e-14, "{b:?}");
        }
    }

    #[test]
    fn reports_a_singular_matrix() {
        let mut lu = Lu::new(2);
        lu.a.copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert_eq!(lu.factor(), Err(Singular { column: 1 }));
    }
}

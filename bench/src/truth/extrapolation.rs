//! An adaptive Gragg-Bulirsch-Stoer extrapolation integrator for the reference
//! solutions.
//!
//! Each macro step `H` runs Gragg's modified midpoint rule with `n_j = 2 (j + 1)`
//! substeps for `j = 0 .. columns`; its error expands in even powers of `H / n_j`, so
//! Aitken-Neville extrapolation in `(H / n_j)^2` raises the order by two per column
//! (order `2 * columns` at the last one). The difference between the last two
//! extrapolated values estimates the local error of the lower one and drives the step
//! size. With 8 columns (order 16) a tolerance of `1e-13` costs a few thousand `f`
//! evaluations per second of pendulum motion: the truth is cheap, so it can be
//! recomputed at several tolerances to check itself (see the tests).
//!
//! Chosen over an embedded Runge-Kutta pair because it needs no coefficient tables
//! (nothing to mistype) and reaches round-off level accuracy at large steps.

/// Why a reference integration stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TruthError {
    /// The chain's masses or lengths are unusable.
    #[error("invalid chain: {0}")]
    InvalidChain(String),
    /// The step size fell below round-off relative to `t`.
    #[error("step size underflow at t = {t} (h = {h})")]
    StepUnderflow {
        /// Time reached.
        t: f64,
        /// Rejected step size.
        h: f64,
    },
    /// More than the allowed number of macro steps.
    #[error("more than {max_steps} steps before t = {t}")]
    TooManySteps {
        /// The limit.
        max_steps: usize,
        /// Time reached.
        t: f64,
    },
}

/// Counts from one reference integration.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TruthStats {
    /// Accepted macro steps.
    pub steps: usize,
    /// Rejected macro steps.
    pub rejected: usize,
    /// Evaluations of `f`.
    pub f_evals: usize,
}

/// Adaptive extrapolation integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrapolation {
    /// Relative tolerance per macro step.
    pub rtol: f64,
    /// Absolute tolerance per macro step.
    pub atol: f64,
    /// Number of extrapolation columns (order `2 * columns`), at least 2.
    pub columns: usize,
    /// First trial macro step.
    pub h0: f64,
    /// Maximum number of macro steps (accepted and rejected).
    pub max_steps: usize,
}

impl Default for Extrapolation {
    fn default() -> Self {
        Self {
            rtol: 1e-13,
            atol: 1e-13,
            columns: 8,
            h0: 1e-2,
            max_steps: 10_000_000,
        }
    }
}

impl Extrapolation {
    /// Integrate `y' = f(t, y)` from `t0` to `t_end`, updating `y` in place.
    pub fn integrate<F>(
        &self,
        mut f: F,
        t0: f64,
        y: &mut [f64],
        t_end: f64,
    ) -> Result<TruthStats, TruthError>
    where
        F: FnMut(f64, &[f64], &mut [f64]),
    {
        let d = y.len();
        let kc = self.columns.max(2);
        // table[j][k]: extrapolated value of row j, column k (only k <= j used).
        let mut table = vec![vec![vec![0.0; d]; kc]; kc];
        let mut f0 = vec![0.0; d];
        let (mut zm, mut zc, mut zn, mut fz) =
            (vec![0.0; d], vec![0.0; d], vec![0.0; d], vec![0.0; d]);
        let mut stats = TruthStats::default();
        let mut t = t0;
        let mut h = self.h0.min(t_end - t0);
        while t < t_end {
            if stats.steps + stats.rejected >= self.max_steps {
                return Err(TruthError::TooManySteps {
                    max_steps: self.max_steps,
                    t,
                });
            }
            let last = t + h >= t_end;
            let hh = if last { t_end - t } else { h };
            if hh <= 1e-15 * t.abs().max(1.0) {
                return Err(TruthError::StepUnderflow { t, h: hh });
            }
            f(t, y, &mut f0);
            stats.f_evals += 1;
            for j in 0..kc {
                let n = 2 * (j + 1);
                let sub = hh / n as f64;
                // Modified midpoint: z0 = y, z1 = y + sub f(y), z_{m+1} = z_{m-1} + 2 sub f(z_m).
                zm.copy_from_slice(y);
                for i in 0..d {
                    zc[i] = y[i] + sub * f0[i];
                }
                for m in 1..n {
                    f(t + m as f64 * sub, &zc, &mut fz);
                    for i in 0..d {
                        zn[i] = zm[i] + 2.0 * sub * fz[i];
                    }
                    std::mem::swap(&mut zm, &mut zc);
                    std::mem::swap(&mut zc, &mut zn);
                }
                f(t + hh, &zc, &mut fz);
                stats.f_evals += n;
                for i in 0..d {
                    table[j][0][i] = 0.5 * (zc[i] + zm[i] + sub * fz[i]);
                }
                for k in 1..=j {
                    let ratio = (n as f64 / (2 * (j - k + 1)) as f64).powi(2) - 1.0;
                    let (upper, lower) = table.split_at_mut(j);
                    let prev = &upper[j - 1][k - 1];
                    let row = &mut lower[0];
                    for i in 0..d {
                        let cur = row[k - 1][i];
                        row[k][i] = cur + (cur - prev[i]) / ratio;
                    }
                }
            }
            let best = &table[kc - 1][kc - 1];
            let lower = &table[kc - 1][kc - 2];
            let mut err = 0.0f64;
            for i in 0..d {
                let sc = self.atol + self.rtol * y[i].abs().max(best[i].abs());
                err = err.max((best[i] - lower[i]).abs() / sc);
            }
            if err.is_nan() {
                err = f64::INFINITY;
            }
            let grow = if err == 0.0 {
                4.0
            } else {
                (0.9 * err.powf(-1.0 / (2 * kc - 1) as f64)).clamp(0.2, 4.0)
            };
            if err <= 1.0 {
                y.copy_from_slice(best);
                t = if last { t_end } else { t + hh };
                stats.steps += 1;
                if !last {
                    h = hh * grow;
                }
            } else {
                stats.rejected += 1;
                h = hh * grow;
            }
        }
        Ok(stats)
    }
}

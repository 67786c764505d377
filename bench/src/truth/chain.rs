//! Planar N-link pendulum chains in minimal coordinates (absolute link angles).
//!
//! Point masses `m_k` at the end of massless rigid links of lengths `L_k`; link 0 is
//! pinned at the origin; gravity `-g e_y`. Link `k` makes the angle `theta_k` with the
//! downward vertical, so particle `k` sits at
//! `x_k = sum_{i<=k} L_i sin theta_i`, `y_k = -sum_{i<=k} L_i cos theta_i`.
//!
//! Derivation (Lagrange). With `mu_ij = sum_{k >= max(i,j)} m_k` (the mass carried
//! beyond both links), the kinetic energy is `T = 1/2 theta'^T M theta'` with
//! `M_ij = mu_ij L_i L_j cos(theta_i - theta_j)` and the potential
//! `V = -g sum_i mu_ii L_i cos theta_i`. `d/dt dT/dtheta_i' - dT/dtheta_i = -dV/dtheta_i`
//! gives, after the `theta_i'` terms of the two sides cancel,
//!
//! ```text
//! sum_j M_ij theta_j'' = -sum_j mu_ij L_i L_j sin(theta_i - theta_j) theta_j'^2
//!                        - g mu_ii L_i sin theta_i
//! ```
//!
//! which [`PlanarChain::accelerations`] solves (dense LU, `M` is symmetric positive
//! definite) at every evaluation.

use dae_runtime::{solve::LinearSolver, solve::Solver, solve::SolverChoice};

use crate::truth::TruthError;

/// A planar chain of point masses on massless rigid links, first joint pinned at the
/// origin, gravity along `-y`.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarChain {
    /// Masses `m_k` (particle `k` at the end of link `k`).
    pub masses: Vec<f64>,
    /// Link lengths `L_k`.
    pub lengths: Vec<f64>,
    /// Gravity.
    pub g: f64,
}

impl PlanarChain {
    /// A chain with the given masses and lengths (same count, at least one, all finite
    /// and positive) and gravity (finite).
    pub fn new(masses: Vec<f64>, lengths: Vec<f64>, g: f64) -> Result<Self, TruthError> {
        let bad = |v: &f64| !(v.is_finite() && *v > 0.0);
        if masses.is_empty() || masses.len() != lengths.len() {
            return Err(TruthError::InvalidChain(format!(
                "{} masses and {} lengths (need the same number, at least one)",
                masses.len(),
                lengths.len()
            )));
        }
        if masses.iter().chain(&lengths).any(bad) || !g.is_finite() {
            return Err(TruthError::InvalidChain(format!(
                "masses {masses:?}, lengths {lengths:?} must be finite and > 0, g = {g} finite"
            )));
        }
        Ok(Self { masses, lengths, g })
    }

    /// The planar double pendulum of docs/language.md: `m1 = m2 = 0.1`, `L1 = L2 = 2`,
    /// `g = 9.8`.
    pub fn double_pendulum() -> Self {
        Self {
            masses: vec![0.1, 0.1],
            lengths: vec![2.0, 2.0],
            g: 9.8,
        }
    }

    /// Number of links (= particles).
    pub fn links(&self) -> usize {
        self.masses.len()
    }

    /// `mu_ij = sum_{k >= max(i, j)} m_k`.
    fn carried(&self, i: usize) -> f64 {
        self.masses[i..].iter().sum()
    }

    /// The mass matrix `M(theta)` (row-major `N x N`) into `out`.
    pub fn mass_matrix(&self, theta: &[f64], out: &mut [f64]) {
        let n = self.links();
        for i in 0..n {
            for j in 0..n {
                let mu = self.carried(i.max(j));
                out[i * n + j] =
                    mu * self.lengths[i] * self.lengths[j] * (theta[i] - theta[j]).cos();
            }
        }
    }

    /// Generalized forces (right-hand side of `M theta'' = rhs`) into `out`.
    pub fn forces(&self, theta: &[f64], omega: &[f64], out: &mut [f64]) {
        let n = self.links();
        for i in 0..n {
            let mut r = -self.g * self.carried(i) * self.lengths[i] * theta[i].sin();
            for j in 0..n {
                let mu = self.carried(i.max(j));
                r -= mu
                    * self.lengths[i]
                    * self.lengths[j]
                    * (theta[i] - theta[j]).sin()
                    * omega[j]
                    * omega[j];
            }
            out[i] = r;
        }
    }

    /// Angular accelerations `theta''` (uses the scratch `work`).
    pub fn accelerations(
        &self,
        theta: &[f64],
        omega: &[f64],
        work: &mut ChainWork,
        out: &mut [f64],
    ) {
        self.mass_matrix(theta, &mut work.matrix);
        self.forces(theta, omega, out);
        // M is symmetric positive definite for positive masses and lengths, so the
        // factorisation cannot fail; a failure would mean NaN angles, passed through.
        if work.lu.factor(&work.matrix, &work.ones).is_err() {
            out.fill(f64::NAN);
            return;
        }
        work.lu.solve(out);
    }

    /// First-order form `y = [theta, omega]`, `y' = [omega, theta'']`.
    pub fn derivative(&self, y: &[f64], work: &mut ChainWork, dy: &mut [f64]) {
        let n = self.links();
        let (theta, omega) = y.split_at(n);
        let (dtheta, domega) = dy.split_at_mut(n);
        dtheta.copy_from_slice(omega);
        self.accelerations(theta, omega, work, domega);
    }

    /// Total energy `T + V` of `y = [theta, omega]`.
    pub fn energy(&self, y: &[f64]) -> f64 {
        let n = self.links();
        let (theta, omega) = y.split_at(n);
        let mut m = vec![0.0; n * n];
        self.mass_matrix(theta, &mut m);
        let mut t = 0.0;
        for i in 0..n {
            for j in 0..n {
                t += 0.5 * omega[i] * m[i * n + j] * omega[j];
            }
        }
        let v: f64 = (0..n)
            .map(|i| -self.g * self.carried(i) * self.lengths[i] * theta[i].cos())
            .sum();
        t + v
    }

    /// Cartesian state in the layout of the DAE stand-in and of docs/language.md: per
    /// particle `[x_k, y_k, vx_k, vy_k]` (so `4 N` values).
    pub fn cartesian(&self, y: &[f64]) -> Vec<f64> {
        let n = self.links();
        let (theta, omega) = y.split_at(n);
        let mut out = vec![0.0; 4 * n];
        let (mut px, mut py, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..n {
            let (s, c) = theta[k].sin_cos();
            let l = self.lengths[k];
            px += l * s;
            py -= l * c;
            vx += l * c * omega[k];
            vy += l * s * omega[k];
            out[4 * k..4 * k + 4].copy_from_slice(&[px, py, vx, vy]);
        }
        out
    }

    /// Link tensions of the motion at `y = [theta, omega]`, in the convention of the
    /// Cartesian models (a positive `z_k` pulls particle `k` towards particle `k - 1`):
    /// from the angular accelerations, each particle's acceleration `a_k`, and Newton's
    /// law from the outermost particle inwards,
    /// `z_k = -(m_k (a_k - g) - z_{k+1} u_{k+1}) . u_k` with `u_k` the unit vector of
    /// link `k` (from particle `k - 1` to `k`) and `g = (0, -g)`.
    pub fn tensions(&self, y: &[f64]) -> Vec<f64> {
        let n = self.links();
        let (theta, omega) = y.split_at(n);
        let mut alpha = vec![0.0; n];
        self.accelerations(theta, omega, &mut ChainWork::new(n), &mut alpha);
        let mut acc = Vec::with_capacity(n);
        let (mut ax, mut ay) = (0.0, 0.0);
        for k in 0..n {
            let (s, c) = theta[k].sin_cos();
            let l = self.lengths[k];
            // x_k = sum L sin theta, y_k = -sum L cos theta, differentiated twice.
            ax += l * (alpha[k] * c - omega[k] * omega[k] * s);
            ay += l * (alpha[k] * s + omega[k] * omega[k] * c);
            acc.push([ax, ay]);
        }
        let unit = |k: usize| {
            let (s, c) = theta[k].sin_cos();
            [s, -c]
        };
        let mut z = vec![0.0; n];
        let mut outer = [0.0, 0.0];
        for k in (0..n).rev() {
            let m = self.masses[k];
            let f = [
                m * acc[k][0] - outer[0],
                m * (acc[k][1] + self.g) - outer[1],
            ];
            let u = unit(k);
            z[k] = -(f[0] * u[0] + f[1] * u[1]);
            outer = [z[k] * u[0], z[k] * u[1]];
        }
        z
    }

    /// Positions only, `[x_0, y_0, x_1, y_1, ...]`.
    pub fn positions(&self, y: &[f64]) -> Vec<f64> {
        let c = self.cartesian(y);
        c.chunks(4).flat_map(|p| [p[0], p[1]]).collect()
    }
}

/// Scratch space for [`PlanarChain::accelerations`] (no allocation per evaluation):
/// the row-major mass matrix and the runtime's dense LU on the full `n x n` pattern.
#[derive(Debug, Clone)]
pub struct ChainWork {
    matrix: Vec<f64>,
    ones: Vec<f64>,
    lu: Solver,
}

impl ChainWork {
    /// Scratch for a chain of `n` links.
    pub fn new(n: usize) -> Self {
        let full: Vec<(usize, usize)> = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).collect();
        Self {
            matrix: vec![0.0; n * n],
            ones: vec![1.0; n],
            lu: Solver::new(n, &full, SolverChoice::Dense).expect("a full square pattern"),
        }
    }
}

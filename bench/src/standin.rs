//! DEVELOPMENT STAND-IN: a hand-written planar N-link chain in Cartesian coordinates
//! implementing [`dae_runtime::Model`], used until the compiler generates the same
//! models. For two links it is the planar `DoublePendulum` of docs/language.md.
//!
//! Particle `k` (end of link `k`, link 0 pinned at the origin) has the states
//! `x_k, y_k, vx_k, vy_k` (in that order, particle after particle), the algebraic
//! unknown `z_k` is the force along link `k`, and
//!
//! ```text
//! m_k a_k = -z_k u_k + z_{k+1} u_{k+1} - m_k g e_y,   0 = |R_k - R_{k-1}| - L_k
//! ```
//!
//! with `u_k` the unit vector along link `k` (from particle `k-1`, or the origin, to
//! particle `k`). Every constraint has index 3. With `d = R_k - R_{k-1}`,
//! `e = V_k - V_{k-1}`, `l = |d|`, `u = d / l`, `p = u.e`, `q = e.e` and
//! `b = a_k - a_{k-1}`:
//!
//! ```text
//! w = l - L,  w' = p,  w'' = (q - p^2) / l + u.b
//! J_Omega: (k, k) = -1/m_k - 1/m_{k-1} (no second term for k = 0),
//!          (k, k+1) = u_k.u_{k+1} / m_k,  (k, k-1) = u_k.u_{k-1} / m_{k-1}
//! beta = d/dt w'' with z held
//!      = (2 e.b - 2 p p') / l - (q - p^2) p / l^2 + u'.b + u.b'
//! with p' = (q - p^2) / l + u.b, u' = (e - p u) / l,
//!      a_k' = (-z_k u_k' + z_{k+1} u_{k+1}') / m_k.
//! ```
//!
//! All of this is checked against finite differences in the tests.

use dae_runtime::{Model, ModelInfo};

use crate::truth::{PlanarChain, TruthError};

/// Largest chain the stand-in supports (its per-call scratch lives on the stack).
pub const MAX_LINKS: usize = 32;

/// DEVELOPMENT STAND-IN for a generated model: a planar N-link chain in Cartesian
/// coordinates (see the module docs).
#[derive(Debug, Clone)]
pub struct PlanarChainDae {
    masses: Vec<f64>,
    lengths: Vec<f64>,
    g: f64,
    /// Initial state returned by [`Model::initial_state`].
    pub x0: Vec<f64>,
    /// Initial guess returned by [`Model::initial_alg`].
    pub z0: Vec<f64>,
    info: ModelInfo,
    pattern: Vec<(usize, usize)>,
}

#[derive(Clone, Copy, Default)]
struct Link {
    e: [f64; 2],
    l: f64,
    u: [f64; 2],
    p: f64,
    q: f64,
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

impl PlanarChainDae {
    /// The Cartesian DAE of `chain`, starting stretched out horizontally to the left
    /// (on the constraint manifold, at rest) with `z = 0` as the initial guess.
    ///
    /// Chains of more than [`MAX_LINKS`] links are refused.
    pub fn new(chain: &PlanarChain) -> Result<Self, TruthError> {
        let n = chain.links();
        if !(1..=MAX_LINKS).contains(&n) {
            return Err(TruthError::InvalidChain(format!(
                "{n} links; the stand-in supports 1..={MAX_LINKS}"
            )));
        }
        let mut x0 = vec![0.0; 4 * n];
        let mut px = 0.0;
        for k in 0..n {
            px -= chain.lengths[k];
            x0[4 * k] = px;
        }
        let mut state_names = Vec::new();
        for k in 1..=n {
            for s in ["x", "y", "vx", "vy"] {
                state_names.push(format!("{s}{k}"));
            }
        }
        let mut pattern = Vec::new();
        for k in 0..n {
            for j in k.saturating_sub(1)..(k + 2).min(n) {
                pattern.push((k, j));
            }
        }
        Ok(Self {
            masses: chain.masses.clone(),
            lengths: chain.lengths.clone(),
            g: chain.g,
            x0,
            z0: vec![0.0; n],
            info: ModelInfo {
                name: format!("planar_chain_{n}"),
                states: state_names,
                algs: (1..=n).map(|k| format!("z{k}")).collect(),
                constraints: (1..=n).map(|k| format!("link{k}")).collect(),
                params: Vec::new(),
                indices: vec![3; n],
            },
            pattern,
        })
    }

    fn links(&self) -> usize {
        self.masses.len()
    }

    fn geometry(&self, x: &[f64], out: &mut [Link; MAX_LINKS]) {
        let (mut pr, mut pv) = ([0.0; 2], [0.0; 2]);
        for (k, link) in out.iter_mut().enumerate().take(self.links()) {
            let r = [x[4 * k], x[4 * k + 1]];
            let v = [x[4 * k + 2], x[4 * k + 3]];
            let d = [r[0] - pr[0], r[1] - pr[1]];
            let e = [v[0] - pv[0], v[1] - pv[1]];
            let l = dot(d, d).sqrt();
            let u = [d[0] / l, d[1] / l];
            *link = Link {
                e,
                l,
                u,
                p: dot(u, e),
                q: dot(e, e),
            };
            pr = r;
            pv = v;
        }
    }

    fn accel(&self, links: &[Link; MAX_LINKS], z: &[f64], out: &mut [[f64; 2]; MAX_LINKS]) {
        let n = self.links();
        for k in 0..n {
            let m = self.masses[k];
            let mut a = [
                -z[k] * links[k].u[0] / m,
                -z[k] * links[k].u[1] / m - self.g,
            ];
            if k + 1 < n {
                a[0] += z[k + 1] * links[k + 1].u[0] / m;
                a[1] += z[k + 1] * links[k + 1].u[1] / m;
            }
            out[k] = a;
        }
    }

    /// Relative acceleration `b_k = a_k - a_{k-1}` (the origin does not move).
    fn rel(a: &[[f64; 2]; MAX_LINKS], k: usize) -> [f64; 2] {
        if k == 0 {
            a[0]
        } else {
            [a[k][0] - a[k - 1][0], a[k][1] - a[k - 1][1]]
        }
    }
}

impl Model for PlanarChainDae {
    fn info(&self) -> &ModelInfo {
        &self.info
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.x0);
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.copy_from_slice(&self.z0);
    }
    fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        let mut links = [Link::default(); MAX_LINKS];
        let mut a = [[0.0; 2]; MAX_LINKS];
        self.geometry(x, &mut links);
        self.accel(&links, z, &mut a);
        for k in 0..self.links() {
            dx[4 * k] = x[4 * k + 2];
            dx[4 * k + 1] = x[4 * k + 3];
            dx[4 * k + 2] = a[k][0];
            dx[4 * k + 3] = a[k][1];
        }
    }
    fn sliding(
        &self,
        _: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        let mut links = [Link::default(); MAX_LINKS];
        let mut a = [[0.0; 2]; MAX_LINKS];
        self.geometry(x, &mut links);
        self.accel(&links, z, &mut a);
        for k in 0..self.links() {
            let lk = &links[k];
            let w0 = lk.l - self.lengths[k];
            let w1 = lk.p;
            let w2 = (lk.q - lk.p * lk.p) / lk.l + dot(lk.u, Self::rel(&a, k));
            w[3 * k] = w0;
            w[3 * k + 1] = w1;
            w[3 * k + 2] = w2;
            s[k] = mu[k] * mu[k] * w2 + 2.0 * mu[k] * w1 + w0;
            ah[k] = w1 + 2.0 * mu[k] * w2;
        }
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.pattern
    }
    fn jacobian(&self, _: f64, x: &[f64], _: &[f64], values: &mut [f64]) {
        let mut links = [Link::default(); MAX_LINKS];
        self.geometry(x, &mut links);
        for (v, &(k, j)) in values.iter_mut().zip(&self.pattern) {
            *v = if j == k {
                let up = if k > 0 { 1.0 / self.masses[k - 1] } else { 0.0 };
                -1.0 / self.masses[k] - up
            } else if j == k + 1 {
                dot(links[k].u, links[j].u) / self.masses[k]
            } else {
                dot(links[k].u, links[j].u) / self.masses[j]
            };
        }
    }
    fn beta(&self, _: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        let n = self.links();
        let mut links = [Link::default(); MAX_LINKS];
        let mut a = [[0.0; 2]; MAX_LINKS];
        let mut ud = [[0.0; 2]; MAX_LINKS];
        let mut ad = [[0.0; 2]; MAX_LINKS];
        self.geometry(x, &mut links);
        self.accel(&links, z, &mut a);
        for k in 0..n {
            let lk = &links[k];
            ud[k] = [
                (lk.e[0] - lk.p * lk.u[0]) / lk.l,
                (lk.e[1] - lk.p * lk.u[1]) / lk.l,
            ];
        }
        for k in 0..n {
            let m = self.masses[k];
            let mut v = [-z[k] * ud[k][0] / m, -z[k] * ud[k][1] / m];
            if k + 1 < n {
                v[0] += z[k + 1] * ud[k + 1][0] / m;
                v[1] += z[k + 1] * ud[k + 1][1] / m;
            }
            ad[k] = v;
        }
        for k in 0..n {
            let lk = &links[k];
            let b = Self::rel(&a, k);
            let bd = Self::rel(&ad, k);
            let qp = lk.q - lk.p * lk.p;
            let pd = qp / lk.l + dot(lk.u, b);
            let term1 = (2.0 * dot(lk.e, b) - 2.0 * lk.p * pd) / lk.l - qp * lk.p / (lk.l * lk.l);
            beta[k] = term1 + dot(ud[k], b) + dot(lk.u, bd);
        }
    }
}

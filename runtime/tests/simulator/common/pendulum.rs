//! The 3-D double pendulum of docs/method.md section 8, written by hand.
//!
//! States `x = [R1, R2, V1, V2]` (12), algebraic unknowns `z = [z1, z2]` (link
//! tensions), constraints `w1 = |R1| - L1`, `w2 = |R2 - R1| - L2`, both of index 3.
//! `w'`, `w''` and `J_Omega` are written out analytically. `beta = dw''/dt` along the
//! flow with `z` held is computed as a central finite difference of `w''` along
//! `x +- delta f(x, z)` (second order in `delta`): acceptable here because this model is
//! only a test oracle for the simulator, not a production model.

use std::sync::LazyLock;

use dae_runtime::{Model, ModelInfo};

pub struct Pendulum {
    pub m1: f64,
    pub m2: f64,
    pub l1: f64,
    pub l2: f64,
    pub g: f64,
    /// Give `Omega'` ([`Model::omega_rate`]) as `beta + J_Omega zdot`, summed in the
    /// order the simulator sums `J_Omega v` (off by default: the simulator then
    /// composes it itself).
    pub composed_rate: bool,
}

impl Default for Pendulum {
    fn default() -> Self {
        Self {
            m1: 0.1,
            m2: 0.1,
            l1: 2.0,
            l2: 2.0,
            g: 9.8,
            composed_rate: false,
        }
    }
}

fn v3(x: &[f64], i: usize) -> [f64; 3] {
    [x[3 * i], x[3 * i + 1], x[3 * i + 2]]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn scale(a: [f64; 3], c: f64) -> [f64; 3] {
    [a[0] * c, a[1] * c, a[2] * c]
}

/// Quantities shared by `f`, the w-derivatives and `J_Omega`.
struct Geometry {
    u1: [f64; 3],
    n1: f64,
    u12: [f64; 3],
    n12: f64,
    v1: [f64; 3],
    e: [f64; 3],
}

impl Pendulum {
    fn geometry(x: &[f64]) -> Geometry {
        let r1 = v3(x, 0);
        let d = sub(v3(x, 1), r1);
        let n1 = dot(r1, r1).sqrt();
        let n12 = dot(d, d).sqrt();
        let v1 = v3(x, 2);
        Geometry {
            u1: scale(r1, 1.0 / n1),
            n1,
            u12: scale(d, 1.0 / n12),
            n12,
            v1,
            e: sub(v3(x, 3), v1),
        }
    }

    /// Accelerations of the two particles.
    fn accel(&self, g: &Geometry, z: &[f64]) -> ([f64; 3], [f64; 3]) {
        let mut a1 = [0.0; 3];
        let mut a2 = [0.0; 3];
        for k in 0..3 {
            a1[k] = (-z[0] * g.u1[k] + z[1] * g.u12[k]) / self.m1;
            a2[k] = -z[1] * g.u12[k] / self.m2;
        }
        a1[2] -= self.g;
        a2[2] -= self.g;
        (a1, a2)
    }

    /// `[w1, w1', w1'', w2, w2', w2'']`.
    pub fn derivatives(&self, x: &[f64], z: &[f64]) -> [f64; 6] {
        let g = Self::geometry(x);
        let (a1, a2) = self.accel(&g, z);
        let w1d = dot(g.u1, g.v1);
        let w2d = dot(g.u12, g.e);
        let w1dd = (dot(g.v1, g.v1) - w1d * w1d) / g.n1 + dot(g.u1, a1);
        let w2dd = (dot(g.e, g.e) - w2d * w2d) / g.n12 + dot(g.u12, sub(a2, a1));
        [g.n1 - self.l1, w1d, w1dd, g.n12 - self.l2, w2d, w2dd]
    }

    /// `Omega = (w1'', w2'')`.
    pub fn omega(&self, x: &[f64], z: &[f64]) -> [f64; 2] {
        let d = self.derivatives(x, z);
        [d[2], d[5]]
    }

    /// `J_Omega` as a dense row-major 2 x 2.
    pub fn j_omega(&self, x: &[f64]) -> [f64; 4] {
        let g = Self::geometry(x);
        let c = dot(g.u1, g.u12) / self.m1;
        [-1.0 / self.m1, c, c, -(1.0 / self.m1 + 1.0 / self.m2)]
    }
}

impl Model for Pendulum {
    fn info(&self) -> &ModelInfo {
        static INFO: LazyLock<ModelInfo> = LazyLock::new(|| {
            ModelInfo::new(
                "double_pendulum_3d",
                &[
                    "R1x", "R1y", "R1z", "R2x", "R2y", "R2z", "V1x", "V1y", "V1z", "V2x", "V2y",
                    "V2z",
                ],
                &["z1", "z2"],
                &["link1", "link2"],
                &[],
                &[3, 3],
            )
        });
        &INFO
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x.fill(0.0);
        x[0] = -1.0;
        x[3] = -5.0;
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.fill(0.0);
    }
    fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        let g = Self::geometry(x);
        let (a1, a2) = self.accel(&g, z);
        dx[..6].copy_from_slice(&x[6..]);
        dx[6..9].copy_from_slice(&a1);
        dx[9..].copy_from_slice(&a2);
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
        w.copy_from_slice(&self.derivatives(x, z));
        for i in 0..2 {
            let (w0, w1, w2) = (w[3 * i], w[3 * i + 1], w[3 * i + 2]);
            s[i] = mu[i] * mu[i] * w2 + 2.0 * mu[i] * w1 + w0;
            ah[i] = w1 + 2.0 * mu[i] * w2;
        }
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &[(0, 0), (0, 1), (1, 0), (1, 1)]
    }
    fn jacobian(&self, _: f64, x: &[f64], _: &[f64], j: &mut [f64]) {
        j.copy_from_slice(&self.j_omega(x));
    }
    fn beta(&self, _: f64, x: &[f64], z: &[f64], b: &mut [f64]) {
        const DELTA: f64 = 1e-5;
        let mut f = [0.0; 12];
        self.rhs(0.0, x, z, &mut f);
        let mut xp = [0.0; 12];
        let mut xm = [0.0; 12];
        for k in 0..12 {
            xp[k] = x[k] + DELTA * f[k];
            xm[k] = x[k] - DELTA * f[k];
        }
        let (op, om) = (self.omega(&xp, z), self.omega(&xm, z));
        for i in 0..2 {
            b[i] = (op[i] - om[i]) / (2.0 * DELTA);
        }
    }
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        if !self.composed_rate {
            return false;
        }
        self.beta(t, x, z, rate);
        let j = self.j_omega(x);
        for (&(i, k), a) in self.jacobian_pattern().iter().zip(j) {
            rate[i] += a * zdot[k];
        }
        true
    }
}

//! Vertex Block Descent (Chen, Liu, Yang, Yuksel, SIGGRAPH 2024), written from the
//! paper, with the links as stiff springs.
//!
//! One substep of length `h` is implicit Euler written as the minimisation of
//!
//! ```text
//! G(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 + sum_j E_j(x),    y = x + h v + h^2 g,
//! E_j  = k_j / 2 (l_j - L_j)^2,   l_j = |x_b - x_a|,   k_j = stiffness / L_j,
//! ```
//!
//! by Gauss-Seidel over the vertices: each iteration sweeps the vertices colour by
//! colour (a greedy vertex colouring, no two vertices of a colour share a link; run
//! sequentially here) and moves each free vertex by one Newton step of its own 3 x 3
//! problem, the others held:
//!
//! ```text
//! f_i = -m_i / h^2 (x_i - y_i) - sum_j k_j (l_j - L_j) n_j
//! H_i =  m_i / h^2 I + sum_j [k_j n_j n_j^T + k_j max(0, 1 - L_j / l_j) (I - n_j n_j^T)]
//! x_i += H_i^-1 f_i                   (skipped if det H_i is tiny)
//! ```
//!
//! with `n_j` the unit vector from the link's other end to `x_i`. The second Hessian
//! term is the spring's exact one clamped at 0 for a compressed link (`l < L`), which
//! keeps `H_i` positive definite. After the iterations `v = (x - x_prev) / h`. No
//! damping, no line search, no Chebyshev acceleration.
//!
//! **Initial guess** ([`VbdOptions::adaptive_init`], on by default): the paper's
//! adaptive initialisation (Sec. 3.7), `x = x_prev + h v + h^2 a~`, where `a~` is the
//! component along `g` of the particle's acceleration over the previous substep, clamped
//! to `[0, |g|]`; on the very first substep (no previous acceleration) it is `y`. Off:
//! `y` always.
//!
//! **Stiffness** ([`VbdOptions::stiffness`]): an axial stiffness `EA` in N, so that a
//! link under tension `T` stretches by the strain `T / EA` whatever its length. The
//! default [`DEFAULT_STIFFNESS`] = 1e8 N is chosen against the scenes' loads: the C1
//! chain with a 1 kg end (ratio 1e2) pulls at most a few times `m g` (3 `m g` = 30 N at
//! the bottom of a pendulum's swing from horizontal), a strain of 3e-7; even the 100 kg
//! end of ratio 1e4 stays near 3e-5. These are the converged (static) strains: with few
//! iterations VBD leaves far more, which is what the benchmark measures.

use dae_particles::System;

use super::vertex_blocks::{Mat3, Vertices, direction, solve3, vertex_block_backend};

/// The default axial stiffness `EA` of a link (N; module docs).
pub const DEFAULT_STIFFNESS: f64 = 1e8;

/// VBD's knobs besides the substeps and iterations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VbdOptions {
    /// Axial stiffness `EA` of every link (N): link `j` is a spring of `EA / L_j` N/m.
    /// Default [`DEFAULT_STIFFNESS`].
    pub stiffness: f64,
    /// The paper's adaptive initialisation (module docs); default `true`. Off: start
    /// each substep's iterations at the inertia target `y`.
    pub adaptive_init: bool,
}

impl Default for VbdOptions {
    fn default() -> Self {
        Self {
            stiffness: DEFAULT_STIFFNESS,
            adaptive_init: true,
        }
    }
}

impl VbdOptions {
    /// These options with the axial stiffness `stiffness` (N).
    pub fn stiffness(mut self, stiffness: f64) -> Self {
        self.stiffness = stiffness;
        self
    }
    /// These options with the adaptive initialisation on or off.
    pub fn adaptive_init(mut self, on: bool) -> Self {
        self.adaptive_init = on;
        self
    }
}

/// Vertex Block Descent on stiff springs (module docs): `substeps` per frame of 1/60 s,
/// each with `iterations` coloured sweeps over the vertices.
#[derive(Debug, Clone)]
pub struct Vbd {
    substeps: u32,
    iterations: u32,
    options: VbdOptions,
    /// `k_j = EA / L_j` of every link.
    spring: Vec<f64>,
    state: Vertices,
}

impl Vbd {
    /// VBD on `system` with `substeps` per frame and `iterations` per substep (both at
    /// least 1) and the default [`VbdOptions`].
    pub fn new(system: &System, substeps: u32, iterations: u32) -> Result<Self, String> {
        Self::with_options(system, substeps, iterations, VbdOptions::default())
    }

    /// [`Vbd::new`] with `options`; the stiffness must be finite and positive.
    pub fn with_options(
        system: &System,
        substeps: u32,
        iterations: u32,
        options: VbdOptions,
    ) -> Result<Self, String> {
        if substeps == 0 || iterations == 0 {
            return Err(format!(
                "vbd needs substeps >= 1 and iterations >= 1, got {substeps} and {iterations}"
            ));
        }
        if !(options.stiffness.is_finite() && options.stiffness > 0.0) {
            return Err(format!(
                "vbd needs a finite stiffness > 0 (N), got {}",
                options.stiffness
            ));
        }
        let state = Vertices::new(system);
        let spring = state
            .links
            .iter()
            .map(|&(_, _, rest)| options.stiffness / rest)
            .collect();
        Ok(Self {
            substeps,
            iterations,
            options,
            spring,
            state,
        })
    }

    /// The options this run uses.
    pub fn options(&self) -> VbdOptions {
        self.options
    }

    fn substep(&mut self, h: f64) {
        self.state.begin_substep(h, self.options.adaptive_init);
        let inv_h2 = 1.0 / (h * h);
        let s = &mut self.state;
        for _ in 0..self.iterations {
            for &i in &s.order {
                if s.pins[i].is_some() {
                    continue;
                }
                let m = s.mass[i] * inv_h2;
                let xi = s.x[i];
                let mut f = [0.0; 3];
                let mut hess: Mat3 = [[0.0; 3]; 3];
                for c in 0..3 {
                    f[c] = -m * (xi[c] - s.y[i][c]);
                    hess[c][c] = m;
                }
                for inc in &s.adj[s.start[i]..s.start[i + 1]] {
                    let Some((n, len)) = direction(xi, s.x[inc.other]) else {
                        continue;
                    };
                    let (rest, k) = (s.links[inc.link].2, self.spring[inc.link]);
                    let tension = k * (len - rest);
                    let transverse = k * (1.0 - rest / len).max(0.0);
                    for r in 0..3 {
                        f[r] -= tension * n[r];
                        for c in 0..3 {
                            let eye = if r == c { 1.0 } else { 0.0 };
                            hess[r][c] += k * n[r] * n[c] + transverse * (eye - n[r] * n[c]);
                        }
                    }
                }
                if let Some(dx) = solve3(&hess, f) {
                    for (x, d) in s.x[i].iter_mut().zip(dx) {
                        *x += d;
                    }
                }
            }
        }
        self.state.end_substep(h, self.iterations);
    }
}

vertex_block_backend!(Vbd, "vbd");

#[cfg(test)]
mod tests {
    use super::*;
    use dae_particles::Backend;

    /// One free vertex and one spring: a converged substep solves the local problem
    /// exactly, so the gradient of `G` vanishes there.
    #[test]
    fn converged_iterations_zero_the_gradient_of_the_substep_s_energy() {
        let sys = dae_particles::chain(1, 1.0).unwrap();
        let mut vbd = Vbd::with_options(&sys, 1, 30, VbdOptions::default().stiffness(1e4)).unwrap();
        vbd.advance_to(1.0 / 60.0).unwrap();
        let h = 1.0 / 60.0;
        let s = &vbd.state;
        let (n, len) = direction(s.x[1], s.x[0]).unwrap();
        let k = vbd.spring[0];
        for (c, n_c) in n.iter().enumerate() {
            let grad = s.mass[1] / (h * h) * (s.x[1][c] - s.y[1][c]) + k * (len - 1.0) * n_c;
            assert!(grad.abs() < 1e-9, "dG/dx[{c}] = {grad:e}");
        }
        assert_eq!(vbd.counters().iterations, 30);
        assert_eq!(vbd.counters().steps, 1);
    }
}

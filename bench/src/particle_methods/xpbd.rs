//! XPBD with zero compliance (Macklin, Mueller, Chentanez 2016), written from the
//! paper, in its two usual settings: "small steps" (`k` substeps of one Gauss-Seidel
//! iteration each, Macklin et al. 2019) and one step of `n` iterations.
//!
//! Per substep of length `h` (the frame split into `k` equal substeps):
//!
//! ```text
//! v += h g,  x_prev = x,  x += h v           (free particles; pinned: x = pin(t + h))
//! n times, for each link (a, b) in order:     C = |x_b - x_a| - L0,  n = (x_b - x_a)/|.|
//!     dlambda = (-C - alpha~ lambda) / (w_a + w_b + alpha~)     with alpha~ = alpha / h^2 = 0
//!     x_a -= w_a dlambda n,   x_b += w_b dlambda n               (w = inverse mass, 0 pinned)
//! v = (x - x_prev) / h
//! ```
//!
//! With zero compliance `alpha~ = 0` and the multiplier `lambda` drops out of the
//! update (XPBD reduces to PBD's projection); it is not stored. No damping, no
//! velocity pass.
//!
//! "In order" is a [`SweepOrder`]: the system's (a chain root to tip, a grid particle
//! by particle) or by colour. The order is part of the method, not a detail: one sweep
//! per substep in the grid builder's order (each particle's `x` link, then its `y`
//! link, row by row) gains energy without bound on the 64 x 64 cloth (worst strain
//! 1e13-1e21 at k <= 64 over 5 s), where by colour the energy only falls; on a chain
//! the system's order leaves about half the strain per substep, and the coloured one
//! costs 1.5-2.5x less per substep (its consecutive links are independent, so the
//! processor overlaps them).

use dae_particles::{Backend, BackendError, Counters, Kinematics, Pin, System};

use super::substeps;

/// The order of the links in a Gauss-Seidel sweep (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepOrder {
    /// The system's order of links.
    System,
    /// By colour: a greedy colouring in the system's order (no two links of a colour
    /// share a particle), then colour by colour, each colour in the system's order; the
    /// order of parallel XPBD implementations, which sweep a colour at a time.
    Coloured,
}

/// The links of `system` as `(a, b, rest)` in `order`.
fn sweep_links(system: &System, order: SweepOrder) -> Vec<(usize, usize, f64)> {
    let links = system.links().iter().map(|l| (l.a, l.b, l.rest));
    if order == SweepOrder::System {
        return links.collect();
    }
    // Colours taken at each particle, as bits (greedy colouring of links meeting at
    // most d at a particle needs at most 2d - 1 colours; the scenes' particles have at
    // most 4 links). Past 128 colours the rest share the last one: the sweep still
    // takes every link once, only that colour's links may share a particle.
    let mut taken: Vec<u128> = vec![0; system.n_particles()];
    let mut tagged: Vec<(u32, usize, (usize, usize, f64))> = links
        .enumerate()
        .map(|(i, (a, b, rest))| {
            let colour = (!(taken[a] | taken[b])).trailing_zeros().min(127);
            taken[a] |= 1 << colour;
            taken[b] |= 1 << colour;
            (colour, i, (a, b, rest))
        })
        .collect();
    tagged.sort_unstable_by_key(|&(colour, i, _)| (colour, i));
    tagged.into_iter().map(|(_, _, l)| l).collect()
}

/// XPBD with zero compliance (module docs): `substeps` per frame of 1/60 s, each with
/// `iterations` Gauss-Seidel sweeps over the links in a [`SweepOrder`].
#[derive(Debug, Clone)]
pub struct Xpbd {
    substeps: u32,
    iterations: u32,
    order: SweepOrder,
    t: f64,
    x: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    x_prev: Vec<[f64; 3]>,
    /// Velocity before the last substep, for the acceleration a grab continues.
    v_prev: Vec<[f64; 3]>,
    h_last: f64,
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    pins: Vec<Option<Pin>>,
    links: Vec<(usize, usize, f64)>,
    gravity: [f64; 3],
    counters: Counters,
}

impl Xpbd {
    /// XPBD on `system` with `substeps` per frame and `iterations` per substep (both
    /// at least 1), sweeping the links in `order`.
    pub fn new(
        system: &System,
        substeps: u32,
        iterations: u32,
        order: SweepOrder,
    ) -> Result<Self, String> {
        if substeps == 0 || iterations == 0 {
            return Err(format!(
                "xpbd needs substeps >= 1 and iterations >= 1, got {substeps} and {iterations}"
            ));
        }
        let n = system.n_particles();
        Ok(Self {
            substeps,
            iterations,
            order,
            t: 0.0,
            x: system.positions().to_vec(),
            v: system.velocities().to_vec(),
            x_prev: system.positions().to_vec(),
            v_prev: system.velocities().to_vec(),
            h_last: 0.0,
            mass: system.masses().to_vec(),
            inv_mass: (0..n)
                .map(|k| {
                    if system.pins()[k].is_some() {
                        0.0
                    } else {
                        1.0 / system.masses()[k]
                    }
                })
                .collect(),
            pins: system.pins().to_vec(),
            links: sweep_links(system, order),
            gravity: system.gravity(),
            counters: Counters::default(),
        })
    }

    fn substep(&mut self, h: f64) {
        let t1 = self.t + h;
        self.v_prev.copy_from_slice(&self.v);
        for k in 0..self.x.len() {
            self.x_prev[k] = self.x[k];
            match &self.pins[k] {
                Some(pin) => self.x[k] = pin.at(t1).pos,
                None => {
                    for i in 0..3 {
                        self.v[k][i] += h * self.gravity[i];
                        self.x[k][i] += h * self.v[k][i];
                    }
                }
            }
        }
        for _ in 0..self.iterations {
            for &(a, b, rest) in &self.links {
                let (wa, wb) = (self.inv_mass[a], self.inv_mass[b]);
                let w = wa + wb;
                if w == 0.0 {
                    continue;
                }
                let (pa, pb) = (self.x[a], self.x[b]);
                let d = [pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]];
                let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if len == 0.0 {
                    continue;
                }
                // dlambda = -C / (w_a + w_b); the step along n = d / len.
                let s = (len - rest) / (w * len);
                for (i, di) in d.iter().enumerate() {
                    self.x[a][i] += wa * s * di;
                    self.x[b][i] -= wb * s * di;
                }
            }
        }
        let inv_h = 1.0 / h;
        for k in 0..self.x.len() {
            for i in 0..3 {
                self.v[k][i] = (self.x[k][i] - self.x_prev[k][i]) * inv_h;
            }
        }
        self.t = t1;
        self.h_last = h;
        self.counters.steps += 1;
        self.counters.iterations += self.iterations as u64;
    }
}

impl Backend for Xpbd {
    fn name(&self) -> String {
        let order = match self.order {
            SweepOrder::System => "",
            SweepOrder::Coloured => " coloured",
        };
        format!("xpbd k={} n={}{order}", self.substeps, self.iterations)
    }
    fn n_particles(&self) -> usize {
        self.x.len()
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        let (n, h) = substeps::split(t - self.t, self.substeps);
        for _ in 0..n {
            self.substep(h);
        }
        self.t = t;
        substeps::check_finite(self.name(), t, &self.x)
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        out.copy_from_slice(&self.x);
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        out.copy_from_slice(&self.v);
    }
    fn particle(&self, k: usize) -> Kinematics {
        substeps::kinematics(k, &self.x, &self.v, &self.v_prev, self.h_last)
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        substeps::check_particle(self.name(), self.t, k, self.x.len())?;
        self.inv_mass[k] = if pin.is_some() {
            0.0
        } else {
            1.0 / self.mass[k]
        };
        self.pins[k] = pin;
        Ok(())
    }
    fn counters(&self) -> Counters {
        self.counters
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coloured_sweep_is_the_system_s_links_with_no_two_of_a_colour_sharing_a_particle() {
        let sys = dae_particles::grid(6, dae_particles::GridPins::Corners, false).unwrap();
        let ours = sweep_links(&sys, SweepOrder::Coloured);
        let mut a: Vec<_> = ours.iter().map(|&(a, b, _)| (a, b)).collect();
        let mut b: Vec<_> = sys.links().iter().map(|l| (l.a, l.b)).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b, "a permutation of the links");
        // Split the sweep into its colours (runs of links that share no particle): a
        // grid's links take 4 colours greedily, so there are at most 4 runs.
        let mut runs = 1;
        let mut seen = std::collections::HashSet::new();
        for &(a, b, _) in &ours {
            if seen.contains(&a) || seen.contains(&b) {
                runs += 1;
                seen.clear();
            }
            seen.insert(a);
            seen.insert(b);
        }
        assert!(runs <= 4, "{runs} colours");
        // A chain in order alternates: even links, then odd ones.
        let chain = dae_particles::chain(5, 1.0).unwrap();
        let order: Vec<usize> = sweep_links(&chain, SweepOrder::Coloured)
            .iter()
            .map(|&(a, _, _)| a)
            .collect();
        assert_eq!(order, [0, 2, 4, 1, 3]);
    }
}

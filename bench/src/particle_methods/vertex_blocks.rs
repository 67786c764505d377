//! What VBD and AVBD share: the particles' state and its bookkeeping behind
//! [`Backend`](dae_particles::Backend), each vertex's links, a greedy vertex colouring
//! (the sweep order), the inertia target with the adaptive initialisation, and the
//! 3 x 3 solve of a vertex's Newton step.

use dae_particles::{BackendError, Counters, Kinematics, Pin, System};

use super::substeps;

/// A symmetric 3 x 3 matrix as its rows.
pub(crate) type Mat3 = [[f64; 3]; 3];

/// `H^-1 f` for a symmetric `H`, by cofactors; `None` when `det H` is tiny next to the
/// product of its diagonal (or not finite).
pub(crate) fn solve3(h: &Mat3, f: [f64; 3]) -> Option<[f64; 3]> {
    let c00 = h[1][1] * h[2][2] - h[1][2] * h[2][1];
    let c01 = h[1][2] * h[2][0] - h[1][0] * h[2][2];
    let c02 = h[1][0] * h[2][1] - h[1][1] * h[2][0];
    let det = h[0][0] * c00 + h[0][1] * c01 + h[0][2] * c02;
    let scale = (h[0][0] * h[1][1] * h[2][2]).abs();
    if !det.is_finite() || det.abs() <= 1e-14 * scale || det == 0.0 {
        return None;
    }
    let c10 = h[0][2] * h[2][1] - h[0][1] * h[2][2];
    let c11 = h[0][0] * h[2][2] - h[0][2] * h[2][0];
    let c12 = h[0][1] * h[2][0] - h[0][0] * h[2][1];
    let c20 = h[0][1] * h[1][2] - h[0][2] * h[1][1];
    let c21 = h[0][2] * h[1][0] - h[0][0] * h[1][2];
    let c22 = h[0][0] * h[1][1] - h[0][1] * h[1][0];
    // The inverse is the transposed cofactor matrix over det.
    let inv = 1.0 / det;
    Some([
        (c00 * f[0] + c10 * f[1] + c20 * f[2]) * inv,
        (c01 * f[0] + c11 * f[1] + c21 * f[2]) * inv,
        (c02 * f[0] + c12 * f[1] + c22 * f[2]) * inv,
    ])
}

/// A link seen from one of its vertices: the link's index and the vertex at its other
/// end.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Incident {
    pub link: usize,
    pub other: usize,
}

/// A greedy vertex colouring in index order (each vertex takes the smallest colour none
/// of its linked neighbours took before it), returned as the vertices sorted by colour,
/// each colour in index order, with each vertex's colour.
pub(crate) fn colour_order(
    n: usize,
    start: &[usize],
    adj: &[Incident],
) -> (Vec<usize>, Vec<usize>) {
    let mut colour = vec![usize::MAX; n];
    let mut used = Vec::new();
    for v in 0..n {
        used.clear();
        for inc in &adj[start[v]..start[v + 1]] {
            if colour[inc.other] != usize::MAX {
                used.push(colour[inc.other]);
            }
        }
        colour[v] = (0..).find(|c| !used.contains(c)).unwrap_or(0);
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&v| (colour[v], v));
    (order, colour)
}

/// The state and bookkeeping of a vertex block descent method: positions, velocities,
/// masses, pins, the links seen from each vertex (`adj[start[v]..start[v + 1]]`), the
/// coloured sweep order, and the counters.
#[derive(Debug, Clone)]
pub(crate) struct Vertices {
    pub t: f64,
    pub x: Vec<[f64; 3]>,
    pub v: Vec<[f64; 3]>,
    /// Positions at the start of the substep (`x_prev`, also AVBD's `x^-`).
    pub x_prev: Vec<[f64; 3]>,
    /// Velocity before the last substep, for the acceleration ([`Self::particle`] and
    /// the adaptive initialisation).
    pub v_prev: Vec<[f64; 3]>,
    /// The inertia targets `y = x + h v + h^2 g` of the substep (pinned: the pin).
    pub y: Vec<[f64; 3]>,
    pub h_last: f64,
    pub mass: Vec<f64>,
    pub pins: Vec<Option<Pin>>,
    /// The system's links as `(a, b, rest)`.
    pub links: Vec<(usize, usize, f64)>,
    pub start: Vec<usize>,
    pub adj: Vec<Incident>,
    /// The vertices by colour (module docs of `vbd`).
    pub order: Vec<usize>,
    pub gravity: [f64; 3],
    pub counters: Counters,
}

impl Vertices {
    pub fn new(system: &System) -> Self {
        let n = system.n_particles();
        let links: Vec<(usize, usize, f64)> =
            system.links().iter().map(|l| (l.a, l.b, l.rest)).collect();
        let mut degree = vec![0usize; n + 1];
        for &(a, b, _) in &links {
            degree[a] += 1;
            degree[b] += 1;
        }
        let mut start = vec![0usize; n + 1];
        for v in 0..n {
            start[v + 1] = start[v] + degree[v];
        }
        let mut fill = start.clone();
        let mut adj = vec![Incident { link: 0, other: 0 }; 2 * links.len()];
        for (l, &(a, b, _)) in links.iter().enumerate() {
            adj[fill[a]] = Incident { link: l, other: b };
            fill[a] += 1;
            adj[fill[b]] = Incident { link: l, other: a };
            fill[b] += 1;
        }
        let (order, _) = colour_order(n, &start, &adj);
        Self {
            t: 0.0,
            x: system.positions().to_vec(),
            v: system.velocities().to_vec(),
            x_prev: system.positions().to_vec(),
            v_prev: system.velocities().to_vec(),
            y: system.positions().to_vec(),
            h_last: 0.0,
            mass: system.masses().to_vec(),
            pins: system.pins().to_vec(),
            links,
            start,
            adj,
            order,
            gravity: system.gravity(),
            counters: Counters::default(),
        }
    }

    /// The substeps that take the state to `t`: as many of `1/(60 k)` s as fit (at
    /// least one), as `(count, length)` (the split of XPBD).
    pub fn split(&self, t: f64, substeps: u32) -> (u64, f64) {
        substeps::split(t - self.t, substeps)
    }

    /// The start of a substep of length `h`: `x_prev = x`, the inertia targets `y`, the
    /// pinned particles put on their pins at `t + h`, and the free ones at the initial
    /// guess: with `adaptive`, VBD's adaptive initialisation `x + h v + h^2 a~`, `a~`
    /// the component of the previous substep's acceleration along `g`, clamped to
    /// `[0, |g|]` (Chen et al. 2024, Sec. 3.7; `y` on the first substep, before any
    /// acceleration is known); without, `y`.
    pub fn begin_substep(&mut self, h: f64, adaptive: bool) {
        let t1 = self.t + h;
        let g = self.gravity;
        let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        for k in 0..self.x.len() {
            self.x_prev[k] = self.x[k];
            match &self.pins[k] {
                Some(pin) => {
                    self.x[k] = pin.at(t1).pos;
                    self.y[k] = self.x[k];
                }
                None => {
                    let (x, v) = (self.x[k], self.v[k]);
                    let mut weight = 1.0;
                    if adaptive && self.h_last > 0.0 && g_norm > 0.0 {
                        let along: f64 = (0..3)
                            .map(|i| (v[i] - self.v_prev[k][i]) / self.h_last * g[i] / g_norm)
                            .sum();
                        weight = (along / g_norm).clamp(0.0, 1.0);
                    }
                    for i in 0..3 {
                        self.y[k][i] = x[i] + h * v[i] + h * h * g[i];
                        self.x[k][i] = x[i] + h * v[i] + h * h * g[i] * weight;
                    }
                }
            }
        }
        self.v_prev.copy_from_slice(&self.v);
    }

    /// The end of a substep of length `h`: `v = (x - x_prev) / h`, the clock and the
    /// counters (`iterations` sweeps).
    pub fn end_substep(&mut self, h: f64, iterations: u32) {
        let inv_h = 1.0 / h;
        for k in 0..self.x.len() {
            for i in 0..3 {
                self.v[k][i] = (self.x[k][i] - self.x_prev[k][i]) * inv_h;
            }
        }
        self.t += h;
        self.h_last = h;
        self.counters.steps += 1;
        self.counters.iterations += iterations as u64;
    }

    /// After a frame ending at `t`: the clock set to `t`, and an error if a position is
    /// not finite.
    pub fn finish(&mut self, method: String, t: f64) -> Result<(), BackendError> {
        self.t = t;
        substeps::check_finite(method, t, &self.x)
    }

    pub fn particle(&self, k: usize) -> Kinematics {
        substeps::kinematics(k, &self.x, &self.v, &self.v_prev, self.h_last)
    }

    pub fn set_pin(
        &mut self,
        method: String,
        k: usize,
        pin: Option<Pin>,
    ) -> Result<(), BackendError> {
        substeps::check_particle(method, self.t, k, self.x.len())?;
        self.pins[k] = pin;
        Ok(())
    }
}

/// `Backend` for a block descent method `$ty` named `$name`, with fields `state:
/// Vertices`, `substeps`, `iterations` and a method `substep(h)`: the seam is the
/// same for VBD and AVBD, only the substep differs.
macro_rules! vertex_block_backend {
    ($ty:ty, $name:literal) => {
        impl dae_particles::Backend for $ty {
            fn name(&self) -> String {
                format!(concat!($name, " k={} n={}"), self.substeps, self.iterations)
            }
            fn n_particles(&self) -> usize {
                self.state.x.len()
            }
            fn time(&self) -> f64 {
                self.state.t
            }
            fn advance_to(&mut self, t: f64) -> Result<(), dae_particles::BackendError> {
                let (n, h) = self.state.split(t, self.substeps);
                for _ in 0..n {
                    self.substep(h);
                }
                let name = self.name();
                self.state.finish(name, t)
            }
            fn positions(&self, out: &mut [[f64; 3]]) {
                out.copy_from_slice(&self.state.x);
            }
            fn velocities(&self, out: &mut [[f64; 3]]) {
                out.copy_from_slice(&self.state.v);
            }
            fn particle(&self, k: usize) -> dae_particles::Kinematics {
                self.state.particle(k)
            }
            fn set_pin(
                &mut self,
                k: usize,
                pin: Option<dae_particles::Pin>,
            ) -> Result<(), dae_particles::BackendError> {
                let name = self.name();
                self.state.set_pin(name, k, pin)
            }
            fn counters(&self) -> dae_particles::Counters {
                self.state.counters
            }
        }
    };
}
pub(crate) use vertex_block_backend;

/// The unit vector from `q` to `p` and the distance, or `None` if they coincide.
pub(crate) fn direction(p: [f64; 3], q: [f64; 3]) -> Option<([f64; 3], f64)> {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        Some(([d[0] / len, d[1] / len, d[2] / len], len))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solve3_inverts_a_symmetric_matrix_and_refuses_a_singular_one() {
        let h = [[4.0, 1.0, 0.5], [1.0, 3.0, -0.25], [0.5, -0.25, 2.0]];
        let x = [0.3, -1.2, 2.5];
        let f = [0, 1, 2].map(|r| (0..3).map(|c| h[r][c] * x[c]).sum::<f64>());
        let got = solve3(&h, f).unwrap();
        for i in 0..3 {
            assert!((got[i] - x[i]).abs() < 1e-14, "{got:?} against {x:?}");
        }
        let singular = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [3.0, 6.0, 10.0]];
        assert!(solve3(&singular, [1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn the_colouring_gives_no_two_linked_vertices_one_colour() {
        let sys = dae_particles::grid(6, dae_particles::GridPins::Corners, true).unwrap();
        let v = Vertices::new(&sys);
        let (order, colour) = colour_order(sys.n_particles(), &v.start, &v.adj);
        assert_eq!(order, v.order);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..sys.n_particles()).collect::<Vec<_>>());
        assert!(
            order.windows(2).all(|w| colour[w[0]] <= colour[w[1]]),
            "by colour"
        );
        let colours = colour.iter().max().unwrap() + 1;
        for l in sys.links() {
            assert_ne!(colour[l.a], colour[l.b], "link {l:?}");
        }
        // A grid with diagonals needs 4 colours greedily; a chain alternates.
        assert!(colours <= 4, "{colours} colours");
        let chain = Vertices::new(&dae_particles::chain(5, 1.0).unwrap());
        assert_eq!(chain.order, [0, 2, 4, 1, 3, 5]);
    }
}

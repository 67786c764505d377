//! The hand-written DBSMC model of a particle system (docs/method.md section 7): a
//! [`dae_runtime::Model`] whose states are the particles' positions and velocities,
//! whose algebraic unknowns are the link tensions, and whose constraints
//! `w_l = |R_b - R_a| - L0_l` all have index 3.
//!
//! With `d = R_b - R_a`, `e = V_b - V_a`, `l = |d|`, `u = d / l`, `p = u.e`, `q = e.e`
//! for link `(a, b)` and `A_k` the acceleration of particle `k`:
//!
//! ```text
//! m_k A_k = sum_{links j at k} z_j rhat_kj + m_k g      (free particle)
//! A_k     = the pin's acceleration                       (pinned particle, 1/m_k = 0)
//! w = l - L0,   w' = p,   w'' = (q - p^2) / l + u.(A_b - A_a)        (Omega = w'')
//! J_Omega[l, l] = -(1/m_a + 1/m_b),   J_Omega[l, k] = -(rhat_cl . rhat_ck) / m_c
//! beta = (2 e.b - 2 p w'') / l - (q - p^2) p / l^2 + u'.b + u.b'
//!        b = A_b - A_a,  u' = (e - p u) / l,  A_k' = sum_j z_j rhat_kj' / m_k (free)
//!        or the pin's jerk (pinned)
//! ```
//!
//! `rhat_kj` is the unit vector from particle `k` along link `j` and `z_j > 0` pulls
//! the two ends together. With the tensions moving at `z'`, the jerks gain
//! `sum_j z_j' rhat_kj / m_k`, and the same passes give `Omega' = beta + J_Omega z'`
//! ([`Model::omega_rate`]): the simulator reads `s'` at the end of every step from it
//! and evaluates `J_Omega` (an entry per pair of links sharing a particle) only at the
//! updates. Everything is evaluated in `O(links + particles)` per call into buffers
//! allocated once: the tests check `J_Omega`, `beta`, `Omega'` and the w-derivatives
//! against finite differences and the generated scalar chain.

use std::cell::RefCell;

use dae_runtime::{Model, ModelInfo, solve::LinearSolver, solve::Solver, solve::SolverChoice};

use crate::motion::Pin;
use crate::system::System;

/// Why a particle model could not be built or a pin not be changed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The system has no link with a free end: nothing to constrain.
    #[error("no link has a free end: nothing to simulate")]
    NoConstraint,
    /// `J_Omega` is singular at the start (dependent links, e.g. a closed loop of
    /// collinear links), so no consistent tensions exist.
    #[error(
        "J_Omega is singular at the start ({0}): remove redundant links; a straight run of links between two pinned particles at its full length (a taut edge between pinned corners) is dependent too: give it slack"
    )]
    Singular(String),
    /// The model cannot make this change (e.g. a generated model whose pins are
    /// driven through its own inputs).
    #[error("{0}")]
    Unsupported(String),
    /// A particle index is out of range.
    #[error("particle {particle} does not exist ({particles} particles)")]
    NoSuchParticle {
        /// The particle.
        particle: usize,
        /// The number of particles.
        particles: usize,
    },
    /// The pin change would leave a link with both ends pinned (its constraint would
    /// have no unknown), or release a particle whose link to another pinned particle
    /// was dropped when the model was built.
    #[error("link {link} between particles {a} and {b}: {reason}")]
    PinnedLink {
        /// The system's link index.
        link: usize,
        /// One end.
        a: usize,
        /// The other.
        b: usize,
        /// What would go wrong.
        reason: &'static str,
    },
}

/// A DAE model that simulates a particle system: what the particle backends need
/// beyond [`Model`]. Implemented by [`ParticleModel`] and, with the feature `families`,
/// by `FamilyParticles` for any family model written over particles and links.
pub trait ParticleDae: Model {
    /// Number of particles.
    fn n_particles(&self) -> usize;
    /// Index of the state holding the `x` component of particle `k`'s position and of
    /// its velocity (`y` and `z` follow each).
    fn state_slots(&self, k: usize) -> (usize, usize);
    /// The constraint of the system's link `l`, `None` if the model has none (a link
    /// between two particles pinned when the model was built).
    fn constraint_of_link(&self, l: usize) -> Option<usize>;
    /// Rest length of constraint `i`'s link (m).
    fn rest_length(&self, i: usize) -> f64;
    /// Pin particle `k` to `pin` from now on (`None`: release it). The pin takes over
    /// from the particle's current state: its motion should start there.
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), ModelError>;
}

#[derive(Debug, Clone, Copy, Default)]
struct Geo {
    u: [f64; 3],
    l: f64,
    /// `1 / l`: one division per link and call, the other quotients are products (the
    /// divider, not the multiplier, limits these loops).
    inv_l: f64,
    e: [f64; 3],
    p: f64,
    q: f64,
}

#[derive(Debug, Clone)]
struct Scratch {
    geo: Vec<Geo>,
    acc: Vec<[f64; 3]>,
    jerk: Vec<[f64; 3]>,
    /// The point whose geometry and accelerations (with the relative velocity terms)
    /// `geo` and `acc` hold, if they hold one: the simulator asks for `s` and then for
    /// `Omega'` (or `beta`) at the same point, at the end of every step and at every
    /// located crossing, and the second call reads them instead of computing them
    /// again. Compared bit for bit, so a hit gives what a computation would.
    at: Point,
    /// Whether `at` is that point (the buffers are sized at construction either way).
    holding: bool,
}

/// Whether `bits` are the bits of `v`.
fn same_bits(bits: &[u64], v: &[f64]) -> bool {
    bits.len() == v.len() && bits.iter().zip(v).all(|(a, b)| *a == b.to_bits())
}

/// `(t, x, z)` as bits.
#[derive(Debug, Clone)]
struct Point {
    t: u64,
    x: Vec<u64>,
    z: Vec<u64>,
}

impl Scratch {
    /// Whether `geo` and `acc` hold `(t, x, z)`'s.
    fn holds(&self, t: f64, x: &[f64], z: &[f64]) -> bool {
        self.holds_positions(x) && self.at.t == t.to_bits() && same_bits(&self.at.z, z)
    }

    /// Whether `geo` holds the geometry of the states `x` (its unit vectors and lengths
    /// depend on the positions only).
    fn holds_positions(&self, x: &[f64]) -> bool {
        self.holding && same_bits(&self.at.x, x)
    }

    /// Record that `geo` and `acc` hold `(t, x, z)`'s (reusing the buffers).
    fn remember(&mut self, t: f64, x: &[f64], z: &[f64]) {
        let p = &mut self.at;
        p.t = t.to_bits();
        p.x.clear();
        p.x.extend(x.iter().map(|v| v.to_bits()));
        p.z.clear();
        p.z.extend(z.iter().map(|v| v.to_bits()));
        self.holding = true;
    }
}

/// The hand-written DBSMC model of a particle system (module docs). Built from a
/// [`System`]: links with both ends pinned are dropped (their length is prescribed).
#[derive(Debug)]
pub struct ParticleModel {
    /// Name, sizes and the names of the particles' coordinates, tensions and links.
    info: ModelInfo,
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    pins: Vec<Option<Pin>>,
    /// Particles with a pin, for the per-call evaluation of the pins' acceleration and
    /// jerk.
    pinned: Vec<usize>,
    gravity: [f64; 3],
    /// Constraint links `(a, b)` and their rest lengths.
    ends: Vec<(usize, usize)>,
    rest: Vec<f64>,
    /// The system's links (all of them) and each one's constraint.
    system_links: Vec<(usize, usize)>,
    constraint: Vec<Option<usize>>,
    pattern: Vec<(usize, usize)>,
    /// For each pattern entry: the shared particle and the sign of
    /// `rhat_cl . rhat_ck = sign * u_l . u_k` (`usize::MAX` on the diagonal).
    entry: Vec<(usize, f64)>,
    x0: Vec<f64>,
    z0: Vec<f64>,
    scratch: RefCell<Scratch>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// The six states of particle `k` (position, velocity): one index check for the six.
fn states(x: &[f64], k: usize) -> &[f64; 6] {
    x[6 * k..6 * k + 6].try_into().expect("a range of six")
}
/// `b - a` over the three coordinates from `at` of two particles' states (0: positions,
/// 3: velocities).
fn diff3(a: &[f64; 6], b: &[f64; 6], at: usize) -> [f64; 3] {
    [b[at] - a[at], b[at + 1] - a[at + 1], b[at + 2] - a[at + 2]]
}
fn states_mut(x: &mut [f64], k: usize) -> &mut [f64; 6] {
    (&mut x[6 * k..6 * k + 6])
        .try_into()
        .expect("a range of six")
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl ParticleModel {
    /// The model of `system`, starting from its positions and velocities with the
    /// consistent tensions (`w'' = 0` solved for `z` at `t = 0`).
    pub fn new(system: &System) -> Result<Self, ModelError> {
        let n = system.n_particles();
        let pins = system.pins().to_vec();
        let mut ends = Vec::new();
        let mut rest = Vec::new();
        let mut constraint = Vec::with_capacity(system.links().len());
        for link in system.links() {
            if pins[link.a].is_some() && pins[link.b].is_some() {
                constraint.push(None);
            } else {
                constraint.push(Some(ends.len()));
                ends.push((link.a, link.b));
                rest.push(link.rest);
            }
        }
        let m = ends.len();
        if m == 0 {
            return Err(ModelError::NoConstraint);
        }
        // Links at each particle, then every pair of links sharing a particle. Pinned
        // particles keep their entries (value 0) so that a grab or release changes
        // values, never the pattern.
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (l, &(a, b)) in ends.iter().enumerate() {
            at[a].push(l);
            at[b].push(l);
        }
        let side = |l: usize, c: usize| if ends[l].0 == c { 1.0 } else { -1.0 };
        let mut entries: Vec<((usize, usize), (usize, f64))> =
            (0..m).map(|l| ((l, l), (usize::MAX, 0.0))).collect();
        for (c, ls) in at.iter().enumerate() {
            for &l in ls {
                for &k in ls {
                    if l != k {
                        entries.push(((l, k), (c, side(l, c) * side(k, c))));
                    }
                }
            }
        }
        entries.sort_unstable_by_key(|e| e.0);
        let mut state_names = Vec::with_capacity(6 * n);
        for k in 0..n {
            for c in ["x", "y", "z", "vx", "vy", "vz"] {
                state_names.push(format!("{c}[{k}]"));
            }
        }
        let mut x0 = vec![0.0; 6 * n];
        for k in 0..n {
            x0[6 * k..6 * k + 3].copy_from_slice(&system.positions()[k]);
            x0[6 * k + 3..6 * k + 6].copy_from_slice(&system.velocities()[k]);
        }
        let inv_mass = (0..n)
            .map(|k| {
                if pins[k].is_some() {
                    0.0
                } else {
                    1.0 / system.masses()[k]
                }
            })
            .collect();
        let mut model = Self {
            info: ModelInfo {
                name: format!("particles_{n}p_{m}l"),
                states: state_names,
                algs: (0..m).map(|l| format!("tension[{l}]")).collect(),
                constraints: (0..m).map(|l| format!("link[{l}]")).collect(),
                params: Vec::new(),
                indices: vec![3; m],
            },
            mass: system.masses().to_vec(),
            inv_mass,
            pinned: (0..n).filter(|&k| pins[k].is_some()).collect(),
            pins,
            gravity: system.gravity(),
            system_links: system.links().iter().map(|l| (l.a, l.b)).collect(),
            constraint,
            ends,
            rest,
            pattern: entries.iter().map(|e| e.0).collect(),
            entry: entries.iter().map(|e| e.1).collect(),
            x0,
            z0: vec![0.0; m],
            scratch: RefCell::new(Scratch {
                geo: vec![Geo::default(); m],
                acc: vec![[0.0; 3]; n],
                jerk: vec![[0.0; 3]; n],
                at: Point {
                    t: 0,
                    x: Vec::with_capacity(6 * n),
                    z: Vec::with_capacity(m),
                },
                holding: false,
            }),
        };
        let x0 = model.x0.clone();
        model.z0 = model.consistent_tensions(0.0, &x0)?;
        Ok(model)
    }

    /// The tensions that make `w'' = 0` on every link at `(t, x)`: one solve with
    /// `J_Omega` (exact, since `w''` is affine in `z`).
    pub fn consistent_tensions(&self, t: f64, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        let m = self.ends.len();
        let mut solver = Solver::new(m, &self.pattern, SolverChoice::Auto)
            .map_err(|e| ModelError::Singular(e.to_string()))?;
        let mut vals = vec![0.0; self.pattern.len()];
        self.jacobian(t, x, &[], &mut vals);
        solver
            .factor(&vals, &vec![1.0; m])
            .map_err(|e| ModelError::Singular(e.to_string()))?;
        let zero = vec![0.0; m];
        let (mut w, mut s, mut ah) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
        self.sliding(t, x, &zero, &vec![1.0; m], &mut w, &mut s, &mut ah);
        let mut z: Vec<f64> = (0..m).map(|l| -w[3 * l + 2]).collect();
        solver.solve(&mut z);
        Ok(z)
    }

    /// Number of particles.
    pub fn n_particles(&self) -> usize {
        self.mass.len()
    }
    /// Masses (of every particle, pinned or not).
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }
    /// Gravity.
    pub fn gravity(&self) -> [f64; 3] {
        self.gravity
    }
    /// Constraint links `(a, b)`.
    pub fn ends(&self) -> &[(usize, usize)] {
        &self.ends
    }
    /// Rest lengths of the constraint links.
    pub fn rest_lengths(&self) -> &[f64] {
        &self.rest
    }
    /// Whether particle `k` is pinned.
    pub fn is_pinned(&self, k: usize) -> bool {
        self.pins[k].is_some()
    }

    /// Accelerations of every particle into `acc`; for the links' geometry, unit
    /// vectors and lengths into `geo` (and with `full` the relative velocity terms).
    fn accelerations(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        geo: &mut [Geo],
        acc: &mut [[f64; 3]],
        full: bool,
    ) {
        for (k, a) in acc.iter_mut().enumerate() {
            *a = if self.inv_mass[k] > 0.0 {
                self.gravity
            } else {
                [0.0; 3]
            };
        }
        for ((l, &(a, b)), g) in self.ends.iter().enumerate().zip(geo.iter_mut()) {
            let (pa, pb) = (states(x, a), states(x, b));
            let d = diff3(pa, pb, 0);
            let len = dot(d, d).sqrt();
            let inv = 1.0 / len;
            let u = [d[0] * inv, d[1] * inv, d[2] * inv];
            g.u = u;
            g.l = len;
            g.inv_l = inv;
            if full {
                let e = diff3(pa, pb, 3);
                g.e = e;
                g.p = dot(u, e);
                g.q = dot(e, e);
            }
            if !z.is_empty() {
                let (fa, fb) = (z[l] * self.inv_mass[a], z[l] * self.inv_mass[b]);
                for i in 0..3 {
                    acc[a][i] += fa * u[i];
                    acc[b][i] -= fb * u[i];
                }
            }
        }
        for &k in &self.pinned {
            acc[k] = self.pins[k].as_ref().map_or([0.0; 3], |p| p.at(t).acc);
        }
    }

    /// [`Self::accelerations`] with the relative velocity terms at `(t, x, z)` into
    /// `sc`, unless it holds that point's already ([`Scratch::holds`]).
    fn accelerations_at(&self, sc: &mut Scratch, t: f64, x: &[f64], z: &[f64]) {
        if !sc.holds(t, x, z) {
            self.accelerations(t, x, z, &mut sc.geo, &mut sc.acc, true);
            sc.remember(t, x, z);
        }
    }

    /// The rate of `w''` along the motion into `out`: `beta` (the tensions held) when
    /// `zdot` is `None`, `beta + J_Omega zdot` (the tensions moving at `zdot`) otherwise.
    /// One pass over the links for the accelerations, one for the jerks, one for the
    /// rates: `zdot` adds `zdot_l u_l / m` to the jerks, which is `J_Omega zdot` without
    /// `J_Omega`'s entry per pair of links sharing a particle.
    fn omega_derivative(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        zdot: Option<&[f64]>,
        out: &mut [f64],
    ) {
        let mut sc = self.scratch.borrow_mut();
        self.accelerations_at(&mut sc, t, x, z);
        let Scratch { geo, acc, jerk, .. } = &mut *sc;
        jerk.fill([0.0; 3]);
        for (l, &(a, b)) in self.ends.iter().enumerate() {
            let g = &geo[l];
            let (fa, fb) = (
                z[l] * self.inv_mass[a] * g.inv_l,
                z[l] * self.inv_mass[b] * g.inv_l,
            );
            // u' = (e - p u) / l; A_a gains z u'/m_a, A_b loses z u'/m_b.
            let du = [
                g.e[0] - g.p * g.u[0],
                g.e[1] - g.p * g.u[1],
                g.e[2] - g.p * g.u[2],
            ];
            for (i, d) in du.iter().enumerate() {
                jerk[a][i] += fa * d;
                jerk[b][i] -= fb * d;
            }
            if let Some(zdot) = zdot {
                // A_a gains z' u/m_a, A_b loses z' u/m_b.
                let (ra, rb) = (zdot[l] * self.inv_mass[a], zdot[l] * self.inv_mass[b]);
                for (i, u) in g.u.iter().enumerate() {
                    jerk[a][i] += ra * u;
                    jerk[b][i] -= rb * u;
                }
            }
        }
        for &k in &self.pinned {
            jerk[k] = self.pins[k].as_ref().map_or([0.0; 3], |p| p.at(t).jerk);
        }
        for (l, &(a, b)) in self.ends.iter().enumerate() {
            let g = &geo[l];
            let bb = sub(acc[b], acc[a]);
            let bd = sub(jerk[b], jerk[a]);
            let qp = g.q - g.p * g.p;
            let il = g.inv_l;
            let w2 = qp * il + dot(g.u, bb);
            let ud = [
                (g.e[0] - g.p * g.u[0]) * il,
                (g.e[1] - g.p * g.u[1]) * il,
                (g.e[2] - g.p * g.u[2]) * il,
            ];
            out[l] = (2.0 * dot(g.e, bb) - 2.0 * g.p * w2) * il - qp * g.p * (il * il)
                + dot(ud, bb)
                + dot(g.u, bd);
        }
    }
}

impl Model for ParticleModel {
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

    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        // The accelerations accumulate directly in dx: no scratch on the hot path. A
        // particle's six states are one array: one index check per particle, not per
        // coordinate.
        let n = 6 * self.mass.len();
        debug_assert_eq!(z.len(), self.ends.len(), "one tension per link");
        let particles = dx[..n].chunks_exact_mut(6).zip(x[..n].chunks_exact(6));
        for ((dk, xk), &inv_mass) in particles.zip(&self.inv_mass) {
            let g = if inv_mass > 0.0 {
                self.gravity
            } else {
                [0.0; 3]
            };
            dk.copy_from_slice(&[xk[3], xk[4], xk[5], g[0], g[1], g[2]]);
        }
        for (&(a, b), &zl) in self.ends.iter().zip(z) {
            let (pa, pb) = (states(x, a), states(x, b));
            let d = diff3(pa, pb, 0);
            let c = zl / dot(d, d).sqrt();
            let (fa, fb) = (c * self.inv_mass[a], c * self.inv_mass[b]);
            let da = states_mut(dx, a);
            for i in 0..3 {
                da[3 + i] += fa * d[i];
            }
            let db = states_mut(dx, b);
            for i in 0..3 {
                db[3 + i] -= fb * d[i];
            }
        }
        for &k in &self.pinned {
            if let Some(p) = &self.pins[k] {
                dx[6 * k + 3..6 * k + 6].copy_from_slice(&p.at(t).acc);
            }
        }
    }

    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        let mut sc = self.scratch.borrow_mut();
        self.accelerations_at(&mut sc, t, x, z);
        let Scratch { geo, acc, .. } = &*sc;
        for (l, &(a, b)) in self.ends.iter().enumerate() {
            let g = &geo[l];
            let w0 = g.l - self.rest[l];
            let w1 = g.p;
            let w2 = (g.q - g.p * g.p) * g.inv_l + dot(g.u, sub(acc[b], acc[a]));
            w[3 * l] = w0;
            w[3 * l + 1] = w1;
            w[3 * l + 2] = w2;
            s[l] = mu[l] * mu[l] * w2 + 2.0 * mu[l] * w1 + w0;
            ah[l] = w1 + 2.0 * mu[l] * w2;
        }
    }

    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.pattern
    }

    fn jacobian(&self, _: f64, x: &[f64], _: &[f64], values: &mut [f64]) {
        let mut sc = self.scratch.borrow_mut();
        // At an update the simulator asks for `J_Omega` where it just evaluated `s`:
        // the remembered point's unit vectors are these positions' (the same formula,
        // the same bits), and `beta` after it reads that point's accelerations. At
        // other positions the unit vectors overwrite the point's, which is forgotten.
        if !sc.holds_positions(x) {
            sc.holding = false;
            for (&(a, b), g) in self.ends.iter().zip(sc.geo.iter_mut()) {
                let (pa, pb) = (states(x, a), states(x, b));
                let d = diff3(pa, pb, 0);
                let inv = 1.0 / dot(d, d).sqrt();
                g.u = [d[0] * inv, d[1] * inv, d[2] * inv];
            }
        }
        for ((v, &(l, k)), &(c, sign)) in values.iter_mut().zip(&self.pattern).zip(&self.entry) {
            *v = if c == usize::MAX {
                let (a, b) = self.ends[l];
                -(self.inv_mass[a] + self.inv_mass[b])
            } else {
                -sign * dot(sc.geo[l].u, sc.geo[k].u) * self.inv_mass[c]
            };
        }
    }

    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.omega_derivative(t, x, z, None, beta);
    }

    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        self.omega_derivative(t, x, z, Some(zdot), rate);
        true
    }
}

/// Whether particle `k` may be pinned (`pinning`) or freed, for a model of the links
/// `links` (particle pairs) whose particles are pinned as `pins` and whose link `l` is
/// constraint `link_constraint[l]` (`None`: left out because both its ends were pinned
/// when the model was built): a link keeps a free end, and a left-out link stays so.
/// The check every [`ParticleDae::set_pin`] makes before changing anything.
pub fn check_pin_change(
    links: &[(usize, usize)],
    pins: &[Option<Pin>],
    link_constraint: &[Option<usize>],
    k: usize,
    pinning: bool,
) -> Result<(), ModelError> {
    let n = pins.len();
    if k >= n {
        return Err(ModelError::NoSuchParticle {
            particle: k,
            particles: n,
        });
    }
    for (l, &(a, b)) in links.iter().enumerate() {
        if a != k && b != k {
            continue;
        }
        let other = if a == k { b } else { a };
        if pinning && pins[other].is_some() {
            return Err(ModelError::PinnedLink {
                link: l,
                a,
                b,
                reason: "both ends would be pinned; a link needs one free end",
            });
        }
        if !pinning && link_constraint[l].is_none() {
            return Err(ModelError::PinnedLink {
                link: l,
                a,
                b,
                reason: "was dropped when the model was built (both ends pinned); build the model with this particle free",
            });
        }
    }
    Ok(())
}

impl ParticleDae for ParticleModel {
    fn n_particles(&self) -> usize {
        self.mass.len()
    }
    fn state_slots(&self, k: usize) -> (usize, usize) {
        (6 * k, 6 * k + 3)
    }
    fn constraint_of_link(&self, l: usize) -> Option<usize> {
        self.constraint.get(l).copied().flatten()
    }
    fn rest_length(&self, i: usize) -> f64 {
        self.rest[i]
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), ModelError> {
        check_pin_change(
            &self.system_links,
            &self.pins,
            &self.constraint,
            k,
            pin.is_some(),
        )?;
        self.inv_mass[k] = if pin.is_some() {
            0.0
        } else {
            1.0 / self.mass[k]
        };
        self.pins[k] = pin;
        self.pinned = (0..self.mass.len())
            .filter(|&j| self.pins[j].is_some())
            .collect();
        // The accelerations depend on the pins.
        self.scratch.get_mut().holding = false;
        Ok(())
    }
}

#[cfg(test)]
mod tests;

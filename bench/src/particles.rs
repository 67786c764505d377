//! Particle-system Jacobians built by hand (method.md section 6), the test and
//! benchmark matrices of the runtime's solvers: chains pinned at one end (optionally
//! with a heavy end particle), square cloth with structural links and pinned corners,
//! and random particle trees.
//!
//! For links `l` and `k` sharing the particle `c`,
//! `J_Omega[l, k] = -(rhat_cl . rhat_ck) / m_c` with `rhat_cl` the unit vector from `c`
//! along link `l`; the diagonal is `-(1/m_a + 1/m_b)`. A pinned particle (prescribed
//! motion) has `1/m = 0`: it adds nothing to the diagonal and couples no links.

/// Particles (positions, inverse masses; 0 for pinned) and the links between them.
#[derive(Debug, Clone, PartialEq)]
pub struct Particles {
    /// Positions.
    pub positions: Vec<[f64; 3]>,
    /// `1 / m_k`, zero for a pinned particle.
    pub inv_mass: Vec<f64>,
    /// Links as pairs of particle indices.
    pub links: Vec<(usize, usize)>,
}

/// A small deterministic generator (64-bit LCG), so that scenes are reproducible.
#[derive(Debug, Clone)]
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[-1, 1)`: `2 uniform - 1`, the same draw.
    pub fn signed(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }
    /// Uniform index in `0..n`.
    pub fn index(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }
}

impl Particles {
    /// A chain of `links` links hanging from a pinned particle at the origin, unit
    /// masses and lengths. `bend` is the angle (radians) between consecutive links (0:
    /// a straight chain, whose `J_Omega` is only weakly diagonally dominant); `end_mass`
    /// the mass of the last particle (1 for a uniform chain).
    pub fn chain(links: usize, bend: f64, end_mass: f64) -> Self {
        let mut positions = vec![[0.0; 3]];
        let mut angle = 0.0f64;
        for k in 0..links {
            let [x, y, _] = positions[k];
            positions.push([x + angle.sin(), y - angle.cos(), 0.0]);
            angle = if k % 2 == 0 { bend } else { 0.0 };
        }
        let mut inv_mass = vec![1.0; links + 1];
        inv_mass[0] = 0.0;
        inv_mass[links] = 1.0 / end_mass;
        Self {
            positions,
            inv_mass,
            links: (0..links).map(|k| (k, k + 1)).collect(),
        }
    }

    /// A `w x w` cloth: unit spacing in a plane with positions jittered by up to
    /// `jitter` (seeded), structural links between horizontal and vertical neighbours
    /// (`2 w (w - 1)` links), the two top corners pinned, unit masses.
    pub fn cloth(w: usize, jitter: f64, seed: u64) -> Self {
        let mut rng = Lcg(seed);
        let mut positions = Vec::with_capacity(w * w);
        for r in 0..w {
            for c in 0..w {
                let mut j = || jitter * (2.0 * rng.uniform() - 1.0);
                positions.push([c as f64 + j(), -(r as f64) + j(), j()]);
            }
        }
        let mut links = Vec::with_capacity(2 * w * (w - 1));
        for r in 0..w {
            for c in 0..w {
                let i = r * w + c;
                if c + 1 < w {
                    links.push((i, i + 1));
                }
                if r + 1 < w {
                    links.push((i, i + w));
                }
            }
        }
        let mut inv_mass = vec![1.0; w * w];
        inv_mass[0] = 0.0;
        inv_mass[w - 1] = 0.0;
        Self {
            positions,
            inv_mass,
            links,
        }
    }

    /// A random particle tree with `links` links: particle 0 pinned, each new particle
    /// hangs from a random earlier one in a random direction, masses in `[0.5, 2)`.
    /// Its link graph is chordal (the links at a particle form a clique) but not a
    /// forest once a particle has three or more links.
    pub fn random_tree(links: usize, seed: u64) -> Self {
        let mut rng = Lcg(seed);
        let mut positions = vec![[0.0; 3]];
        let mut inv_mass = vec![0.0];
        let mut pairs = Vec::with_capacity(links);
        for k in 1..=links {
            let parent = rng.index(k);
            let (th, ph) = (
                std::f64::consts::PI * rng.uniform(),
                std::f64::consts::TAU * rng.uniform(),
            );
            let p = positions[parent];
            positions.push([
                p[0] + th.sin() * ph.cos(),
                p[1] + th.sin() * ph.sin(),
                p[2] + th.cos(),
            ]);
            inv_mass.push(1.0 / (0.5 + 1.5 * rng.uniform()));
            pairs.push((parent, k));
        }
        Self {
            positions,
            inv_mass,
            links: pairs,
        }
    }

    /// Add a second link between the particles of link `l`: a redundant constraint
    /// (its `J_Omega` row equals link `l`'s, so the matrix is singular).
    pub fn with_duplicate_link(mut self, l: usize) -> Self {
        self.links.push(self.links[l]);
        self
    }

    /// Unit vector from particle `c` along link `l` (towards its other particle).
    fn direction(&self, l: usize, c: usize) -> [f64; 3] {
        let (a, b) = self.links[l];
        let other = if a == c { b } else { a };
        let (p, q) = (self.positions[c], self.positions[other]);
        let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        [d[0] / n, d[1] / n, d[2] / n]
    }

    /// `J_Omega` as a row-major sorted pattern and its values (method.md section 6).
    pub fn jacobian(&self) -> (Vec<(usize, usize)>, Vec<f64>) {
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); self.positions.len()];
        for (l, &(a, b)) in self.links.iter().enumerate() {
            at[a].push(l);
            at[b].push(l);
        }
        let mut entries: Vec<((usize, usize), f64)> = Vec::new();
        for (l, &(a, b)) in self.links.iter().enumerate() {
            entries.push(((l, l), -(self.inv_mass[a] + self.inv_mass[b])));
        }
        for (c, ls) in at.iter().enumerate() {
            if self.inv_mass[c] == 0.0 {
                continue;
            }
            for &l in ls {
                for &k in ls {
                    if l != k {
                        let (u, v) = (self.direction(l, c), self.direction(k, c));
                        let dot = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
                        entries.push(((l, k), -dot * self.inv_mass[c]));
                    }
                }
            }
        }
        // Two links between the same particles share both: sum their contributions.
        entries.sort_by_key(|e| e.0);
        let mut pattern: Vec<(usize, usize)> = Vec::with_capacity(entries.len());
        let mut values: Vec<f64> = Vec::with_capacity(entries.len());
        for (ij, v) in entries {
            if pattern.last() == Some(&ij) {
                *values.last_mut().expect("same length") += v;
            } else {
                pattern.push(ij);
                values.push(v);
            }
        }
        (pattern, values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Independent oracle: `-G M^-1 G^T` with `G` the constraint gradients
    /// (`d|R_b - R_a| / dR_b = rhat_ab`) assembled densely.
    fn dense_oracle(p: &Particles) -> Vec<f64> {
        let (n, m) = (p.positions.len(), p.links.len());
        let mut g = vec![0.0; m * 3 * n];
        for (l, &(a, b)) in p.links.iter().enumerate() {
            let u = p.direction(l, a);
            for k in 0..3 {
                g[l * 3 * n + 3 * b + k] += u[k];
                g[l * 3 * n + 3 * a + k] -= u[k];
            }
        }
        let mut j = vec![0.0; m * m];
        for l in 0..m {
            for k in 0..m {
                let mut s = 0.0;
                for q in 0..3 * n {
                    s += g[l * 3 * n + q] * p.inv_mass[q / 3] * g[k * 3 * n + q];
                }
                j[l * m + k] = -s;
            }
        }
        j
    }

    #[test]
    fn jacobians_match_minus_g_minv_gt() {
        for p in [
            Particles::chain(6, 0.3, 10.0),
            Particles::cloth(4, 0.1, 1),
            Particles::random_tree(12, 5),
        ] {
            let m = p.links.len();
            let (pat, vals) = p.jacobian();
            let mut dense = vec![0.0; m * m];
            for (&(i, j), v) in pat.iter().zip(&vals) {
                dense[i * m + j] = *v;
            }
            let oracle = dense_oracle(&p);
            for (a, b) in dense.iter().zip(&oracle) {
                assert!((a - b).abs() < 1e-12, "{a} vs {b}");
            }
        }
    }

    #[test]
    fn the_64_by_64_cloth_has_8064_links() {
        assert_eq!(Particles::cloth(64, 0.0, 0).links.len(), 8064);
    }
}

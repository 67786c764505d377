//! The description of a particle system: particles (positions, velocities, masses),
//! rigid links with rest lengths, pins, gravity. Built by the scene builders or from an
//! edge list; checked on construction.

use crate::motion::Pin;

/// A rigid link between particles `a` and `b` with rest length `rest`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    /// First particle.
    pub a: usize,
    /// Second particle.
    pub b: usize,
    /// Rest length `L0 > 0` (m).
    pub rest: f64,
}

/// Why a system description was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SystemError {
    /// A per-particle list has the wrong length.
    #[error("{what} has {got} entries for {expected} particles")]
    Length {
        /// The list (`masses`, `velocities`).
        what: &'static str,
        /// Its length.
        got: usize,
        /// The number of particles.
        expected: usize,
    },
    /// A mass is not finite and positive.
    #[error("particle {particle}: mass {mass} must be finite and > 0")]
    Mass {
        /// The particle.
        particle: usize,
        /// Its mass.
        mass: f64,
    },
    /// A position or velocity is not finite.
    #[error("particle {particle}: {what} {value:?} is not finite")]
    NotFinite {
        /// The particle.
        particle: usize,
        /// `position` or `velocity`.
        what: &'static str,
        /// The value.
        value: [f64; 3],
    },
    /// A link names a particle that does not exist.
    #[error(
        "link {link} names particle {particle}, but there are only {particles} (0..{particles})"
    )]
    NoSuchParticle {
        /// The link.
        link: usize,
        /// The missing particle.
        particle: usize,
        /// The number of particles.
        particles: usize,
    },
    /// A link joins a particle to itself.
    #[error("link {link} joins particle {particle} to itself")]
    SelfLink {
        /// The link.
        link: usize,
        /// The particle.
        particle: usize,
    },
    /// Two links join the same two particles (their constraints would be dependent).
    #[error(
        "link {link} joins particles {a} and {b}, like link {first}: remove one (two rigid links between the same particles are redundant)"
    )]
    DuplicateLink {
        /// The second link.
        link: usize,
        /// The first link between the same particles.
        first: usize,
        /// One particle.
        a: usize,
        /// The other.
        b: usize,
    },
    /// A rest length is not finite and positive (e.g. two particles at the same place).
    #[error(
        "link {link}: rest length {rest} must be finite and > 0 (are particles {a} and {b} at the same place?)"
    )]
    RestLength {
        /// The link.
        link: usize,
        /// One particle.
        a: usize,
        /// The other.
        b: usize,
        /// The rest length.
        rest: f64,
    },
    /// A pin names a particle that does not exist.
    #[error("pin on particle {particle}, but there are only {particles}")]
    PinOutOfRange {
        /// The particle.
        particle: usize,
        /// The number of particles.
        particles: usize,
    },
    /// A builder was given an impossible size or ratio.
    #[error("{what} = {value}: must be {need}")]
    Invalid {
        /// The argument.
        what: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        need: &'static str,
    },
    /// A line of an edge list could not be read.
    #[error(
        "edge list line {line}: {reason} in `{text}` (expected two particle indices, `a b`, optionally followed by a rest length)"
    )]
    Parse {
        /// 1-based line number.
        line: usize,
        /// The line.
        text: String,
        /// What is wrong.
        reason: String,
    },
}

/// One edge of an edge list: two particles and an optional rest length (default: their
/// distance in the initial positions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// First particle.
    pub a: usize,
    /// Second particle.
    pub b: usize,
    /// Rest length, if given.
    pub rest: Option<f64>,
}

impl From<(usize, usize)> for Edge {
    fn from((a, b): (usize, usize)) -> Self {
        Edge { a, b, rest: None }
    }
}

/// Parse an edge list: one link per line, `a b` or `a b rest`, whitespace or commas
/// between the fields, `#` starts a comment, blank lines are skipped.
pub fn parse_edge_list(text: &str) -> Result<Vec<Edge>, SystemError> {
    let mut edges = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = |reason: String| SystemError::Parse {
            line: i + 1,
            text: raw.to_string(),
            reason,
        };
        let fields: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|f| !f.is_empty())
            .collect();
        if !(2..=3).contains(&fields.len()) {
            return Err(bad(format!("{} fields", fields.len())));
        }
        let index = |f: &str| {
            f.parse::<usize>()
                .map_err(|_| bad(format!("`{f}` is not a particle index")))
        };
        let rest = match fields.get(2) {
            Some(f) => Some(
                f.parse::<f64>()
                    .map_err(|_| bad(format!("`{f}` is not a length")))?,
            ),
            None => None,
        };
        edges.push(Edge {
            a: index(fields[0])?,
            b: index(fields[1])?,
            rest,
        });
    }
    Ok(edges)
}

/// A particle system: particles with positions, velocities and masses, rigid links,
/// pinned particles, and gravity. Every constructor checks its input
/// ([`SystemError`] says where and what).
#[derive(Debug, Clone)]
pub struct System {
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    masses: Vec<f64>,
    links: Vec<Link>,
    pins: Vec<Option<Pin>>,
    gravity: [f64; 3],
}

/// Gravity of every scene: 9.81 m/s^2 along `-z`.
pub const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

fn finite3(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Distance between two points.
pub fn distance(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

impl System {
    /// Particles at `positions` with `masses`, at rest, linked by `edges` (rest lengths
    /// from the edge, or the initial distance), nothing pinned, gravity [`GRAVITY`].
    pub fn from_edges<E: Into<Edge> + Copy>(
        positions: Vec<[f64; 3]>,
        masses: Vec<f64>,
        edges: &[E],
    ) -> Result<Self, SystemError> {
        let n = positions.len();
        if masses.len() != n {
            return Err(SystemError::Length {
                what: "masses",
                got: masses.len(),
                expected: n,
            });
        }
        for (k, (p, &m)) in positions.iter().zip(&masses).enumerate() {
            if !finite3(p) {
                return Err(SystemError::NotFinite {
                    particle: k,
                    what: "position",
                    value: *p,
                });
            }
            if !(m.is_finite() && m > 0.0) {
                return Err(SystemError::Mass {
                    particle: k,
                    mass: m,
                });
            }
        }
        let mut links = Vec::with_capacity(edges.len());
        let mut seen = std::collections::HashMap::with_capacity(edges.len());
        for (l, e) in edges.iter().enumerate() {
            let Edge { a, b, rest } = (*e).into();
            for particle in [a, b] {
                if particle >= n {
                    return Err(SystemError::NoSuchParticle {
                        link: l,
                        particle,
                        particles: n,
                    });
                }
            }
            if a == b {
                return Err(SystemError::SelfLink {
                    link: l,
                    particle: a,
                });
            }
            if let Some(&first) = seen.get(&(a.min(b), a.max(b))) {
                return Err(SystemError::DuplicateLink {
                    link: l,
                    first,
                    a,
                    b,
                });
            }
            seen.insert((a.min(b), a.max(b)), l);
            let rest = rest.unwrap_or_else(|| distance(positions[a], positions[b]));
            if !(rest.is_finite() && rest > 0.0) {
                return Err(SystemError::RestLength {
                    link: l,
                    a,
                    b,
                    rest,
                });
            }
            links.push(Link { a, b, rest });
        }
        Ok(Self {
            velocities: vec![[0.0; 3]; n],
            pins: vec![None; n],
            positions,
            masses,
            links,
            gravity: GRAVITY,
        })
    }

    /// Pin particle `particle` (fixed or moving); its mass then plays no role until it
    /// is released.
    pub fn with_pin(mut self, particle: usize, pin: Pin) -> Result<Self, SystemError> {
        let particles = self.positions.len();
        let slot = self
            .pins
            .get_mut(particle)
            .ok_or(SystemError::PinOutOfRange {
                particle,
                particles,
            })?;
        *slot = Some(pin);
        Ok(self)
    }

    /// Pin particle `particle` where it is.
    pub fn with_fixed(self, particle: usize) -> Result<Self, SystemError> {
        let p = *self
            .positions
            .get(particle)
            .ok_or(SystemError::PinOutOfRange {
                particle,
                particles: self.positions.len(),
            })?;
        self.with_pin(particle, Pin::Fixed(p))
    }

    /// Set the initial velocities.
    pub fn with_velocities(mut self, velocities: Vec<[f64; 3]>) -> Result<Self, SystemError> {
        if velocities.len() != self.positions.len() {
            return Err(SystemError::Length {
                what: "velocities",
                got: velocities.len(),
                expected: self.positions.len(),
            });
        }
        if let Some(k) = velocities.iter().position(|v| !finite3(v)) {
            return Err(SystemError::NotFinite {
                particle: k,
                what: "velocity",
                value: velocities[k],
            });
        }
        self.velocities = velocities;
        Ok(self)
    }

    /// Set the gravity vector (default [`GRAVITY`]).
    pub fn with_gravity(mut self, gravity: [f64; 3]) -> Self {
        self.gravity = gravity;
        self
    }

    /// Change the mass of one particle (e.g. a heavy end).
    pub fn with_mass(mut self, particle: usize, mass: f64) -> Result<Self, SystemError> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(SystemError::Mass { particle, mass });
        }
        let particles = self.positions.len();
        *self
            .masses
            .get_mut(particle)
            .ok_or(SystemError::PinOutOfRange {
                particle,
                particles,
            })? = mass;
        Ok(self)
    }

    /// Number of particles.
    pub fn n_particles(&self) -> usize {
        self.positions.len()
    }
    /// Initial positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    /// Initial velocities.
    pub fn velocities(&self) -> &[[f64; 3]] {
        &self.velocities
    }
    /// Masses.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }
    /// Links.
    pub fn links(&self) -> &[Link] {
        &self.links
    }
    /// The pin of each particle (`None`: free).
    pub fn pins(&self) -> &[Option<Pin>] {
        &self.pins
    }
    /// Gravity.
    pub fn gravity(&self) -> [f64; 3] {
        self.gravity
    }
    /// Total mass of the free particles.
    pub fn free_mass(&self) -> f64 {
        self.masses
            .iter()
            .zip(&self.pins)
            .filter(|(_, p)| p.is_none())
            .map(|(m, _)| m)
            .sum()
    }

    /// Kinetic plus gravitational potential energy `sum m (v.v / 2 - g.x)` of the
    /// particles this system leaves free, at the given positions and velocities.
    pub fn energy(&self, positions: &[[f64; 3]], velocities: &[[f64; 3]]) -> f64 {
        let g = self.gravity;
        let mut e = 0.0;
        for k in 0..self.masses.len() {
            if self.pins[k].is_none() {
                let (x, v) = (positions[k], velocities[k]);
                e += self.masses[k]
                    * (0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                        - (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]));
            }
        }
        e
    }

    /// The largest relative strain `|L - L0| / L0` over the links at `positions`, and
    /// the link where it occurs (see [`worst_strain`]).
    pub fn worst_strain(&self, positions: &[[f64; 3]]) -> (f64, usize) {
        worst_strain(&self.links, positions)
    }
}

/// The largest relative strain `|L - L0| / L0` over `links` at `positions`, and the
/// link where it occurs (`(0.0, 0)` without links; a NaN length wins).
pub fn worst_strain(links: &[Link], positions: &[[f64; 3]]) -> (f64, usize) {
    let mut worst = (0.0, 0);
    for (l, link) in links.iter().enumerate() {
        let e = (distance(positions[link.a], positions[link.b]) - link.rest).abs() / link.rest;
        if e.is_nan() || e > worst.0 {
            worst = (e, l);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_lists_parse_with_comments_and_rest_lengths() {
        let e = parse_edge_list("# cloth\n0 1\n1, 2 0.5 # short\n\n").unwrap();
        assert_eq!(
            e,
            vec![
                Edge {
                    a: 0,
                    b: 1,
                    rest: None
                },
                Edge {
                    a: 1,
                    b: 2,
                    rest: Some(0.5)
                }
            ]
        );
        let err = parse_edge_list("0 1\n0 x\n").unwrap_err();
        assert!(matches!(err, SystemError::Parse { line: 2, .. }), "{err}");
        assert!(err.to_string().contains("`x` is not a particle index"));
        let err = parse_edge_list("0 1 2 3").unwrap_err();
        assert!(err.to_string().contains("4 fields"), "{err}");
    }

    #[test]
    fn bad_systems_are_named() {
        let p = vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let m = vec![1.0; 3];
        let e = |edges: &[(usize, usize)]| System::from_edges(p.clone(), m.clone(), edges);
        assert!(matches!(
            e(&[(0, 3)]),
            Err(SystemError::NoSuchParticle {
                link: 0,
                particle: 3,
                ..
            })
        ));
        assert!(matches!(e(&[(1, 1)]), Err(SystemError::SelfLink { .. })));
        assert!(matches!(
            e(&[(0, 1), (1, 0)]),
            Err(SystemError::DuplicateLink {
                link: 1,
                first: 0,
                ..
            })
        ));
        assert!(matches!(
            e(&[(1, 2)]),
            Err(SystemError::RestLength { link: 0, .. })
        ));
        assert!(matches!(
            System::from_edges(p.clone(), vec![1.0, 0.0, 1.0], &[(0, 1)]),
            Err(SystemError::Mass { particle: 1, .. })
        ));
        let s = e(&[(0, 1)]).unwrap();
        assert!(matches!(
            s.clone().with_fixed(7),
            Err(SystemError::PinOutOfRange { particle: 7, .. })
        ));
        assert!(matches!(
            s.with_velocities(vec![[0.0; 3]; 2]),
            Err(SystemError::Length {
                what: "velocities",
                ..
            })
        ));
    }

    #[test]
    fn worst_strain_finds_the_most_stretched_link() {
        let s = System::from_edges(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            vec![1.0; 3],
            &[(0, 1), (1, 2)],
        )
        .unwrap();
        let (e, l) = s.worst_strain(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.02]]);
        assert_eq!(l, 1);
        assert!((e - (1.0f64 + 4e-4).sqrt() + 1.0).abs() < 1e-15);
    }
}

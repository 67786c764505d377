//! Prescribed motions of pinned particles: a position as a function of time with its
//! first three derivatives (an index-3 link constraint differentiates the position of
//! its ends three times: `w'''` contains the jerk of a driven end).

use std::fmt;
use std::sync::Arc;

/// Position, velocity, acceleration and jerk of a point at one time.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Kinematics {
    /// Position (m).
    pub pos: [f64; 3],
    /// Velocity (m/s).
    pub vel: [f64; 3],
    /// Acceleration (m/s^2).
    pub acc: [f64; 3],
    /// Jerk (m/s^3).
    pub jerk: [f64; 3],
}

impl Kinematics {
    /// A point at rest at `pos`.
    pub fn at_rest(pos: [f64; 3]) -> Self {
        Self {
            pos,
            ..Self::default()
        }
    }
}

/// A prescribed motion: the kinematics of a point as a function of time. It must be
/// three times continuously differentiable wherever a DBSMC run is to keep its bound
/// (the derivatives enter `s`, `alpha_hat` and `beta` of the links at the point).
pub trait Motion: Send + Sync + fmt::Debug {
    /// Position and its first three derivatives at time `t`.
    fn at(&self, t: f64) -> Kinematics;
}

/// How a particle is held.
#[derive(Debug, Clone)]
pub enum Pin {
    /// At rest at this position.
    Fixed([f64; 3]),
    /// Following a motion.
    Moving(Arc<dyn Motion>),
}

impl Pin {
    /// A pin following `motion`.
    pub fn moving(motion: impl Motion + 'static) -> Self {
        Pin::Moving(Arc::new(motion))
    }
    /// The pinned point's kinematics at `t`.
    pub fn at(&self, t: f64) -> Kinematics {
        match self {
            Pin::Fixed(p) => Kinematics::at_rest(*p),
            Pin::Moving(m) => m.at(t),
        }
    }
}

/// `base + d (1 - cos(2 pi f t)) / 2`: starts at `base` at rest, travels the vector `d`
/// and back once per period (a head swaying `|d|` along `d` at frequency `f`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sway {
    /// Position at `t = 0`.
    pub base: [f64; 3],
    /// The excursion (full travel).
    pub travel: [f64; 3],
    /// Frequency (Hz).
    pub frequency: f64,
}

impl Motion for Sway {
    fn at(&self, t: f64) -> Kinematics {
        let w = std::f64::consts::TAU * self.frequency;
        let (s, c) = (w * t).sin_cos();
        let half = |i: usize| 0.5 * self.travel[i];
        let mut k = Kinematics::default();
        for i in 0..3 {
            k.pos[i] = self.base[i] + half(i) * (1.0 - c);
            k.vel[i] = half(i) * w * s;
            k.acc[i] = half(i) * w * w * c;
            k.jerk[i] = -half(i) * w * w * w * s;
        }
        k
    }
}

/// The septic smoothstep `S(u) = 35u^4 - 84u^5 + 70u^6 - 20u^7` and its first three
/// derivatives in `u`, clamped to `S = 0` before 0 and `S = 1` after 1. `S'`, `S''` and
/// `S'''` vanish at both ends, so a blend by `S` is three times continuously
/// differentiable.
pub fn smoothstep7(u: f64) -> [f64; 4] {
    if u <= 0.0 {
        return [0.0; 4];
    }
    if u >= 1.0 {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let v = 1.0 - u;
    let u2 = u * u;
    let s = u2 * u2 * (35.0 - 84.0 * u + 70.0 * u2 - 20.0 * u2 * u);
    let d1 = 140.0 * u2 * u * v * v * v;
    let d2 = 420.0 * u2 * v * v * (1.0 - 2.0 * u);
    let d3 = 840.0 * u * v * (1.0 - 5.0 * u + 5.0 * u2);
    [s, d1, d2, d3]
}

/// A grab: from time `t0`, where a particle was at `p0` with velocity `v0` and
/// acceleration `a0`, move it to `p0 + offset` within `duration` and hold it there.
///
/// `p(t) = P(tau) (1 - S(tau / T)) + (p0 + offset) S(tau / T)`, `tau = t - t0`, with
/// `P(tau) = p0 + v0 tau + a0 tau^2 / 2` the particle's own motion continued and `S` the
/// [`smoothstep7`]: the path starts with position `p0`, velocity `v0` and acceleration
/// `a0`, is three times continuously differentiable, and arrives at rest.
/// [`Scene::grab`](crate::Scene::grab) starts it with the particle's position and
/// velocity and `a0 = 0` (the hand's own acceleration; see there why not the particle's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrabPath {
    /// Time of the grab.
    pub t0: f64,
    /// Position at the grab.
    pub p0: [f64; 3],
    /// Velocity at the grab.
    pub v0: [f64; 3],
    /// Acceleration at the grab.
    pub a0: [f64; 3],
    /// Displacement from `p0` to the held position.
    pub offset: [f64; 3],
    /// Duration of the move (> 0).
    pub duration: f64,
}

impl Motion for GrabPath {
    fn at(&self, t: f64) -> Kinematics {
        let tau = t - self.t0;
        let inv_t = 1.0 / self.duration;
        let [s, s1, s2, s3] = smoothstep7(tau * inv_t);
        let (s1, s2, s3) = (s1 * inv_t, s2 * inv_t * inv_t, s3 * inv_t * inv_t * inv_t);
        let mut k = Kinematics::default();
        if tau >= self.duration {
            for i in 0..3 {
                k.pos[i] = self.p0[i] + self.offset[i];
            }
            return k;
        }
        for i in 0..3 {
            // The continued own motion P and its derivatives (P''' = 0).
            let p = self.p0[i] + self.v0[i] * tau + 0.5 * self.a0[i] * tau * tau;
            let p1 = self.v0[i] + self.a0[i] * tau;
            let p2 = self.a0[i];
            let gap = self.p0[i] + self.offset[i] - p;
            k.pos[i] = p + gap * s;
            k.vel[i] = p1 * (1.0 - s) + gap * s1;
            k.acc[i] = p2 * (1.0 - s) - 2.0 * p1 * s1 + gap * s2;
            k.jerk[i] = -3.0 * p2 * s1 - 3.0 * p1 * s2 + gap * s3;
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `pos`, `vel` and `acc` against `vel`, `acc` and `jerk`.
    fn check_derivatives(m: &dyn Motion, t: f64) {
        let h = 1e-5;
        let (a, b, k) = (m.at(t - h), m.at(t + h), m.at(t));
        for i in 0..3 {
            let fd = |p: f64, q: f64| (q - p) / (2.0 * h);
            for (what, d, exact) in [
                ("vel", fd(a.pos[i], b.pos[i]), k.vel[i]),
                ("acc", fd(a.vel[i], b.vel[i]), k.acc[i]),
                ("jerk", fd(a.acc[i], b.acc[i]), k.jerk[i]),
            ] {
                assert!(
                    (d - exact).abs() <= 1e-5 * (1.0 + exact.abs()),
                    "{what}[{i}] at t = {t}: finite difference {d} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn smoothstep_derivatives_match_finite_differences_and_vanish_at_the_ends() {
        let h = 1e-6;
        for u in [0.1, 0.3, 0.5, 0.77, 0.95] {
            let (a, b, s) = (smoothstep7(u - h), smoothstep7(u + h), smoothstep7(u));
            for d in 0..3 {
                let fd = (b[d] - a[d]) / (2.0 * h);
                assert!(
                    (fd - s[d + 1]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "S^({d}) at {u}"
                );
            }
        }
        assert_eq!(smoothstep7(0.0), [0.0; 4]);
        assert_eq!(smoothstep7(1.0), [1.0, 0.0, 0.0, 0.0]);
        // Just inside both ends the derivatives are already tiny (continuity).
        for u in [1e-4, 1.0 - 1e-4] {
            let s = smoothstep7(u);
            assert!(
                s[1].abs() < 1e-9 && s[2].abs() < 1e-5 && s[3].abs() < 0.1,
                "{s:?}"
            );
        }
    }

    #[test]
    fn sway_derivatives_match_finite_differences() {
        let m = Sway {
            base: [0.1, 0.0, 0.05],
            travel: [0.2, 0.0, 0.0],
            frequency: 1.0,
        };
        for t in [0.1, 0.4, 0.9, 2.3] {
            check_derivatives(&m, t);
        }
        assert_eq!(m.at(0.0).vel, [0.0; 3]);
        assert!((m.at(0.5).pos[0] - 0.3).abs() < 1e-15);
    }

    #[test]
    fn grab_path_is_continuous_with_the_particle_and_three_times_differentiable() {
        let g = GrabPath {
            t0: 1.0,
            p0: [0.5, 0.0, -0.2],
            v0: [0.1, -0.3, -1.0],
            a0: [0.0, 2.0, -9.81],
            offset: [0.3, 0.0, 0.3],
            duration: 0.5,
        };
        // At the grab: position, velocity, acceleration of the particle; jerk 0.
        let k = g.at(1.0);
        assert_eq!((k.pos, k.vel, k.acc, k.jerk), (g.p0, g.v0, g.a0, [0.0; 3]));
        for t in [1.01, 1.1, 1.25, 1.4, 1.49] {
            check_derivatives(&g, t);
        }
        // Arrives and holds at rest at p0 + offset.
        for t in [1.5, 2.0] {
            let k = g.at(t);
            let target = [0.8, 0.0, 0.1];
            for (i, want) in target.iter().enumerate() {
                assert!((k.pos[i] - want).abs() < 1e-12);
                assert!(k.vel[i].abs() < 1e-12 && k.acc[i].abs() < 1e-12);
            }
        }
        // Continuity across both ends of the move: values on either side agree.
        for t in [1.0, 1.5] {
            let (a, b) = (g.at(t - 1e-9), g.at(t + 1e-9));
            for i in 0..3 {
                assert!((a.pos[i] - b.pos[i]).abs() < 1e-8);
                assert!((a.vel[i] - b.vel[i]).abs() < 1e-7);
                assert!((a.acc[i] - b.acc[i]).abs() < 1e-6);
                assert!((a.jerk[i] - b.jerk[i]).abs() < 1e-3, "jerk at {t}");
            }
        }
    }
}

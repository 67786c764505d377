//! The scenes' builders: a chain (C1), hair strands on a swaying head (C2), a cloth grid
//! pinned three ways (C3, and C4's cloth), and a rope of any links, masses and start
//! direction (C5-C7: the heavy-end pendulums of the peers' papers). Every builder starts at rest, on the
//! constraint manifold (every link at its rest length), with [`GRAVITY`].

use crate::motion::{Pin, Sway};
use crate::system::{GRAVITY, System, SystemError};

fn need(what: &'static str, value: f64, ok: bool, need: &'static str) -> Result<(), SystemError> {
    if ok {
        Ok(())
    } else {
        Err(SystemError::Invalid { what, value, need })
    }
}

/// C1: a chain of `links` links, total length 1 m, particle mass `0.1 / links` kg, the
/// top particle (0) pinned at the origin, released horizontal (along `+x`) at rest; the
/// end particle (`links`) is `end_mass_ratio` times heavier than the others.
pub fn chain(links: usize, end_mass_ratio: f64) -> Result<System, SystemError> {
    need("links", links as f64, links >= 1, ">= 1")?;
    need(
        "end_mass_ratio",
        end_mass_ratio,
        end_mass_ratio.is_finite() && end_mass_ratio > 0.0,
        "finite and > 0",
    )?;
    let len = 1.0 / links as f64;
    let m = 0.1 / links as f64;
    let positions = (0..=links).map(|k| [k as f64 * len, 0.0, 0.0]).collect();
    let mut masses = vec![m; links + 1];
    masses[links] = m * end_mass_ratio;
    let edges: Vec<(usize, usize)> = (0..links).map(|k| (k, k + 1)).collect();
    System::from_edges(positions, masses, &edges)?.with_fixed(0)
}

/// A rope (scenes C5-C7): `links` equal links of `link_length` m hanging from particle
/// 0, pinned at the origin, the others of `particle_mass` kg except the free end,
/// `end_mass_ratio` times heavier, released at rest along `direction` (any non-zero
/// vector; it is normalised): `[1, 0, 0]` starts horizontal, `[sin a, 0, -cos a]`
/// at `a` rad from the downward vertical.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rope {
    /// Links.
    pub links: usize,
    /// Length of each link (m).
    pub link_length: f64,
    /// Mass of each particle but the end (kg).
    pub particle_mass: f64,
    /// The end particle's mass over `particle_mass`.
    pub end_mass_ratio: f64,
    /// Direction of the rope at the start.
    pub direction: [f64; 3],
}

/// The system of a [`Rope`]; the arguments are checked ([`SystemError::Invalid`] names
/// the one that is not usable).
pub fn rope(r: &Rope) -> Result<System, SystemError> {
    need("links", r.links as f64, r.links >= 1, ">= 1")?;
    let positive = |x: f64| x.is_finite() && x > 0.0;
    need(
        "link_length",
        r.link_length,
        positive(r.link_length),
        "finite and > 0",
    )?;
    need(
        "particle_mass",
        r.particle_mass,
        positive(r.particle_mass),
        "finite and > 0",
    )?;
    need(
        "end_mass_ratio",
        r.end_mass_ratio,
        positive(r.end_mass_ratio),
        "finite and > 0",
    )?;
    let norm = r.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
    need(
        "direction (its length)",
        norm,
        positive(norm),
        "finite and > 0",
    )?;
    let u = r.direction.map(|x| x / norm);
    let positions = (0..=r.links)
        .map(|k| u.map(|c| c * k as f64 * r.link_length))
        .collect();
    let mut masses = vec![r.particle_mass; r.links + 1];
    masses[r.links] = r.particle_mass * r.end_mass_ratio;
    let edges: Vec<(usize, usize)> = (0..r.links).map(|k| (k, k + 1)).collect();
    System::from_edges(positions, masses, &edges)?.with_fixed(0)
}

/// Radius of C2's head (m).
pub const HEAD_RADIUS: f64 = 0.1;
/// Length of a C2 strand (m).
pub const STRAND_LENGTH: f64 = 0.3;
/// Mass of a C2 strand particle (kg). With equal masses along a strand and gravity the
/// only force, the motion does not depend on it.
pub const STRAND_PARTICLE_MASS: f64 = 1e-3;

/// C2: `strands` strands of `links` links, [`STRAND_LENGTH`] each, rooted on a head
/// (sphere of [`HEAD_RADIUS`] centred at the origin) that sways 0.2 m along `x` at 1 Hz
/// ([`Sway`]: `x = 0.1 (1 - cos 2 pi t)`, starting at rest).
///
/// Roots are spread evenly (a Fibonacci spiral) over the cap within 100 degrees of the
/// top; each strand starts straight along the outward normal at its root, at rest.
/// Particle `s (links + 1) + j` is particle `j` of strand `s` (`j = 0`: the root,
/// pinned to the head).
pub fn strands(strands: usize, links: usize) -> Result<System, SystemError> {
    need("strands", strands as f64, strands >= 1, ">= 1")?;
    need("links", links as f64, links >= 1, ">= 1")?;
    let per = links + 1;
    let cos_max = 100f64.to_radians().cos();
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut positions = Vec::with_capacity(strands * per);
    let mut roots = Vec::with_capacity(strands);
    for s in 0..strands {
        let z = 1.0 - (1.0 - cos_max) * (s as f64 + 0.5) / strands as f64;
        let rho = (1.0 - z * z).max(0.0).sqrt();
        let phi = golden * s as f64;
        let n = [rho * phi.cos(), rho * phi.sin(), z];
        roots.push(positions.len());
        for j in 0..per {
            let r = HEAD_RADIUS + STRAND_LENGTH * j as f64 / links as f64;
            positions.push([r * n[0], r * n[1], r * n[2]]);
        }
    }
    let edges: Vec<(usize, usize)> = (0..strands)
        .flat_map(|s| (0..links).map(move |j| (s * per + j, s * per + j + 1)))
        .collect();
    let mut sys = System::from_edges(positions, vec![STRAND_PARTICLE_MASS; strands * per], &edges)?;
    for root in roots {
        let base = sys.positions()[root];
        sys = sys.with_pin(
            root,
            Pin::moving(Sway {
                base,
                travel: [0.2, 0.0, 0.0],
                frequency: 1.0,
            }),
        )?;
    }
    Ok(sys.with_gravity(GRAVITY))
}

/// How a C3 cloth is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridPins {
    /// (a) the two far corners (`y = 1`).
    Corners,
    /// (b) the whole far edge.
    Edge,
    /// (c) as (a), with the near corner at the origin 100 times heavier.
    CornersHeavy,
}

/// Index of the grid particle at column `ix` (along `x`) and row `iy` (along `y`).
pub fn grid_index(w: usize, ix: usize, iy: usize) -> usize {
    iy * w + ix
}

/// Slack of the far edge between two pinned corners ([`GridPins::Corners`] and
/// [`GridPins::CornersHeavy`]): its arc is this much (2 %) longer than the 1 m between
/// the corners.
///
/// Without it the edge is a straight run of rigid links between two fixed points: its
/// `w - 1` links have `w - 2` free particles between them, so their rows of `J_Omega`
/// are dependent (the tension along a taut straight line is undetermined) and no
/// transverse load can be carried without infinite tension. Every method that solves
/// for the tensions (DBSMC, the index-1 method) rejects that configuration; with this
/// slack the edge starts as a circular arc sagging 8.7 cm below the plane (`R (1 - cos
/// phi)` with `phi / sin(phi) = 1.02`).
///
/// Why 2 % and not less: a bounded method holds each link only within its layer, and
/// links shortened by the slack make the edge straight again. The slack must exceed
/// the largest layer a scene runs with (1 % of a link): with 0.1 % the edge can come
/// straight within the layers, `J_Omega` comes near singular there, and its links set
/// the whole cloth's update rate (docs/particles.md,
/// "The far edge's slack").
pub const FAR_EDGE_SLACK: f64 = 0.02;

/// C3: a `w x w` cloth on `[0, 1]^2` at `z = 0`, total mass 0.5 kg, structural links
/// between neighbours along `x` and along `y` (`2 w (w - 1)` links), with `shear` the
/// two diagonals of every cell as well (`2 (w - 1)^2` more, listed after the structural
/// ones), held as `pins` says. Particle [`grid_index`]`(w, ix, iy)` starts at
/// `(ix, iy) / (w - 1)`, except that with two pinned corners the far edge (`iy = w - 1`)
/// sags on an arc [`FAR_EDGE_SLACK`] longer than the distance between them (the rest
/// lengths are the initial distances, so the start is on the constraint manifold).
pub fn grid(w: usize, pins: GridPins, shear: bool) -> Result<System, SystemError> {
    grid_with_slack(w, pins, shear, FAR_EDGE_SLACK)
}

/// [`grid`] with the far edge's `slack` chosen (`0 < slack <= 0.5`; unused when the
/// whole far edge is pinned). A bounded method holds each link only within its layer:
/// links shortened by `slack` make the far edge straight, where `J_Omega` is singular,
/// so a slack smaller than the layers' strain lets the edge come straight within them.
pub fn grid_with_slack(
    w: usize,
    pins: GridPins,
    shear: bool,
    slack: f64,
) -> Result<System, SystemError> {
    need("w", w as f64, w >= 2, ">= 2")?;
    need("slack", slack, slack > 0.0 && slack <= 0.5, "in (0, 0.5]")?;
    let h = 1.0 / (w - 1) as f64;
    let mut positions = Vec::with_capacity(w * w);
    for iy in 0..w {
        for ix in 0..w {
            positions.push([ix as f64 * h, iy as f64 * h, 0.0]);
        }
    }
    if pins != GridPins::Edge {
        // Half-angle phi of the arc: phi / sin(phi) = 1 + slack, by Newton from the
        // small-angle value.
        let target = 1.0 + slack;
        let mut phi = (6.0 * slack).sqrt();
        for _ in 0..20 {
            let f = phi / phi.sin() - target;
            let df = (phi.sin() - phi * phi.cos()) / (phi.sin() * phi.sin());
            phi -= f / df;
        }
        let radius = 0.5 / phi.sin();
        for ix in 0..w {
            let theta = -phi + 2.0 * phi * ix as f64 / (w - 1) as f64;
            let p = &mut positions[grid_index(w, ix, w - 1)];
            p[0] = 0.5 + radius * theta.sin();
            p[2] = -radius * (theta.cos() - phi.cos());
        }
    }
    let at = |ix, iy| grid_index(w, ix, iy);
    let mut edges =
        Vec::with_capacity(2 * w * (w - 1) + if shear { 2 * (w - 1) * (w - 1) } else { 0 });
    for iy in 0..w {
        for ix in 0..w {
            if ix + 1 < w {
                edges.push((at(ix, iy), at(ix + 1, iy)));
            }
            if iy + 1 < w {
                edges.push((at(ix, iy), at(ix, iy + 1)));
            }
        }
    }
    if shear {
        for iy in 0..w - 1 {
            for ix in 0..w - 1 {
                edges.push((at(ix, iy), at(ix + 1, iy + 1)));
                edges.push((at(ix + 1, iy), at(ix, iy + 1)));
            }
        }
    }
    let m = 0.5 / (w * w) as f64;
    let mut sys = System::from_edges(positions, vec![m; w * w], &edges)?;
    let far = w - 1;
    match pins {
        GridPins::Corners | GridPins::CornersHeavy => {
            sys = sys.with_fixed(at(0, far))?.with_fixed(at(far, far))?;
        }
        GridPins::Edge => {
            for ix in 0..w {
                sys = sys.with_fixed(at(ix, far))?;
            }
        }
    }
    if pins == GridPins::CornersHeavy {
        sys = sys.with_mass(at(0, 0), 100.0 * m)?;
    }
    Ok(sys)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::distance;

    fn rest_lengths_hold(s: &System) {
        for l in s.links() {
            let d = distance(s.positions()[l.a], s.positions()[l.b]);
            assert!((d - l.rest).abs() < 1e-14, "{l:?}: {d}");
        }
    }

    #[test]
    fn chain_counts_masses_pins_and_rest_lengths() {
        for (n, ratio) in [(10, 1.0), (100, 1e2), (1000, 1e4)] {
            let s = chain(n, ratio).unwrap();
            assert_eq!((s.n_particles(), s.links().len()), (n + 1, n));
            let m = 0.1 / n as f64;
            assert!(s.masses()[1..n].iter().all(|&x| x == m));
            assert_eq!(s.masses()[n], m * ratio);
            assert!(s.pins()[0].is_some() && s.pins()[1..].iter().all(|p| p.is_none()));
            assert_eq!(s.pins()[0].as_ref().unwrap().at(3.0).pos, [0.0; 3]);
            let total: f64 = s.links().iter().map(|l| l.rest).sum();
            assert!((total - 1.0).abs() < 1e-12);
            assert_eq!(s.positions()[n], [1.0 * (n as f64) / n as f64, 0.0, 0.0]);
            rest_lengths_hold(&s);
        }
        assert!(chain(0, 1.0).is_err() && chain(3, 0.0).is_err());
    }

    #[test]
    fn a_rope_has_its_links_masses_direction_and_pin() {
        let (a, n) = (0.5f64, 50);
        let r = Rope {
            links: n,
            link_length: 0.02,
            particle_mass: 2e-3,
            end_mass_ratio: 200.0,
            direction: [2.0 * a.sin(), 0.0, -2.0 * a.cos()],
        };
        let s = rope(&r).unwrap();
        assert_eq!((s.n_particles(), s.links().len()), (n + 1, n));
        assert!(s.masses()[..n].iter().all(|&m| m == 2e-3));
        assert_eq!(s.masses()[n], 2e-3 * 200.0);
        assert!(s.pins()[0].is_some() && s.pins()[1..].iter().all(|p| p.is_none()));
        let end = s.positions()[n];
        // One metre along the direction, at `a` from the downward vertical.
        assert!((distance(end, [0.0; 3]) - 1.0).abs() < 1e-12, "{end:?}");
        assert!((end[0].atan2(-end[2]) - a).abs() < 1e-12, "{end:?}");
        rest_lengths_hold(&s);
        for bad in [
            Rope { links: 0, ..r },
            Rope {
                link_length: -1.0,
                ..r
            },
            Rope {
                particle_mass: f64::NAN,
                ..r
            },
            Rope {
                end_mass_ratio: 0.0,
                ..r
            },
            Rope {
                direction: [0.0; 3],
                ..r
            },
        ] {
            assert!(
                matches!(rope(&bad), Err(SystemError::Invalid { .. })),
                "{bad:?}"
            );
        }
    }

    #[test]
    fn strands_hang_from_roots_on_the_head_that_sway() {
        let s = strands(100, 32).unwrap();
        assert_eq!((s.n_particles(), s.links().len()), (3300, 3200));
        let pins: Vec<usize> = (0..s.n_particles())
            .filter(|&k| s.pins()[k].is_some())
            .collect();
        assert_eq!(pins, (0..100).map(|i| 33 * i).collect::<Vec<_>>());
        for &r in &pins {
            let p = s.positions()[r];
            assert!((distance(p, [0.0; 3]) - HEAD_RADIUS).abs() < 1e-14);
            assert!(p[2] >= 100f64.to_radians().cos() * HEAD_RADIUS - 1e-12);
            let k = s.pins()[r].as_ref().unwrap().at(0.5);
            assert!(
                (k.pos[0] - p[0] - 0.2).abs() < 1e-12,
                "half a period: +0.2 m in x"
            );
        }
        for strand in 0..100 {
            let len: f64 = s.links()[32 * strand..32 * (strand + 1)]
                .iter()
                .map(|l| l.rest)
                .sum();
            assert!((len - STRAND_LENGTH).abs() < 1e-12);
        }
        rest_lengths_hold(&s);
    }

    /// The length of the far edge (`iy = w - 1`) of a `w x w` grid, link by link.
    fn far_edge_length(s: &System, w: usize) -> f64 {
        (0..w - 1)
            .map(|ix| {
                distance(
                    s.positions()[grid_index(w, ix, w - 1)],
                    s.positions()[grid_index(w, ix + 1, w - 1)],
                )
            })
            .sum()
    }

    #[test]
    fn the_far_edge_between_pinned_corners_has_its_slack() {
        let w = 16;
        let s = grid(w, GridPins::Corners, false).unwrap();
        let edge = far_edge_length(&s, w);
        // 15 chords of an arc of half-angle 0.344 rad: 9e-5 shorter than the arc.
        assert!((edge - 1.0 - FAR_EDGE_SLACK).abs() < 2e-4, "{edge}");
        // The arc's sag R (1 - cos phi) = 8.69 cm, by phi / sin(phi) = 1.02.
        let mid = s.positions()[grid_index(w, w / 2, w - 1)];
        assert!((mid[2] + 0.0869).abs() < 2e-3, "{mid:?}");
        assert_eq!(s.positions()[grid_index(w, w - 1, w - 1)], [1.0, 1.0, 0.0]);
    }

    #[test]
    fn a_chosen_slack_gives_the_far_edge_its_length_and_sag() {
        let w = 16;
        let s = grid_with_slack(w, GridPins::Corners, false, 1e-3).unwrap();
        let edge = far_edge_length(&s, w);
        // The chords of a flat arc are within 1e-5 of the arc itself.
        assert!((edge - 1.001).abs() < 1e-5, "{edge}");
        // The sag of a flat arc: sqrt(3 slack / 8) = 1.94 cm.
        let mid = s.positions()[grid_index(w, w / 2, w - 1)];
        assert!((mid[2] + 0.0194).abs() < 1e-3, "{mid:?}");
        rest_lengths_hold(&s);
        for bad in [0.0, -0.01, 0.6, f64::NAN] {
            assert!(
                grid_with_slack(w, GridPins::Corners, false, bad).is_err(),
                "{bad}"
            );
        }
    }

    #[test]
    fn grids_have_the_stated_links_mass_and_pins() {
        let s = grid(64, GridPins::Corners, false).unwrap();
        assert_eq!(s.links().len(), 8064);
        let total: f64 = s.masses().iter().sum();
        assert!((total - 0.5).abs() < 1e-12);
        let pinned: Vec<usize> = (0..s.n_particles())
            .filter(|&k| s.pins()[k].is_some())
            .collect();
        assert_eq!(pinned, vec![grid_index(64, 0, 63), grid_index(64, 63, 63)]);
        let corner = s.positions()[grid_index(64, 63, 63)];
        assert!(distance(corner, [1.0, 1.0, 0.0]) < 1e-12, "{corner:?}");
        rest_lengths_hold(&s);

        let e = grid(32, GridPins::Edge, false).unwrap();
        let pinned: Vec<usize> = (0..e.n_particles())
            .filter(|&k| e.pins()[k].is_some())
            .collect();
        assert_eq!(
            pinned,
            (0..32).map(|ix| grid_index(32, ix, 31)).collect::<Vec<_>>()
        );

        let c = grid(32, GridPins::CornersHeavy, true).unwrap();
        assert_eq!(c.links().len(), 2 * 32 * 31 + 2 * 31 * 31);
        assert_eq!(c.masses()[0], 100.0 * c.masses()[1]);
        rest_lengths_hold(&c);
        assert!(grid(1, GridPins::Edge, false).is_err());
    }
}

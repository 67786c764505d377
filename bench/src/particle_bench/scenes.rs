//! The scenes of the particle benchmark (C1-C4): a system, a duration, an optional
//! grab, and what can be measured on it.

use dae_particles::{
    FAR_EDGE_SLACK, GridPins, Rope, System, SystemError, chain, grid_index, grid_with_slack, rope,
    strands,
};

/// A grab during a run (C4): at `at` the particle is grabbed where it is, moved by
/// `offset` over `duration` on a smooth path, held, and released at `release`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grab {
    /// The particle.
    pub particle: usize,
    /// Time of the grab (s, on a frame boundary).
    pub at: f64,
    /// Displacement of the move (m).
    pub offset: [f64; 3],
    /// Duration of the move (s).
    pub duration: f64,
    /// Time of the release (s, on a frame boundary).
    pub release: f64,
}

/// How a scene's system was built: the builder of `dae_particles` and its arguments
/// (the sizes its generated family model is built at).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SceneShape {
    /// [`chain`]`(links, end_mass_ratio)`.
    Chain {
        /// Links.
        links: usize,
        /// End-mass ratio.
        end_mass_ratio: f64,
    },
    /// [`strands`]`(strands, links)`.
    Strands {
        /// Strands.
        strands: usize,
        /// Links per strand.
        links: usize,
    },
    /// [`grid_with_slack`]`(w, pins, shear, slack)`.
    Grid {
        /// Particles per side.
        w: usize,
        /// How it is held.
        pins: GridPins,
        /// Rigid diagonals.
        shear: bool,
        /// The far edge's slack (with two pinned corners).
        slack: f64,
    },
    /// [`rope`]`(rope)`: no generated family model (`chain.dae` is 1 m, 0.1 kg and
    /// horizontal).
    Rope(Rope),
}

/// One scene of the benchmark.
#[derive(Debug, Clone)]
pub struct ParticleScene {
    /// `C1` ... `C4`.
    pub id: &'static str,
    /// The variant, e.g. `N=100 r=1e2` or `W=32 (a)`.
    pub variant: String,
    /// The system.
    pub system: System,
    /// How the system was built.
    pub shape: SceneShape,
    /// Simulated duration (s).
    pub duration: f64,
    /// The grab, if any.
    pub grab: Option<Grab>,
    /// Whether energy is conserved by the exact motion (no driven pin, no grab).
    pub conservative: bool,
    /// The particle whose position is compared with a reference (the free end or
    /// corner).
    pub tracked: usize,
    /// The scene's parameter for charts (C1: end-mass ratio; NaN otherwise).
    pub param: f64,
}

impl ParticleScene {
    /// Number of links.
    pub fn size(&self) -> usize {
        self.system.links().len()
    }
    /// Whether the scene has a generated family model (C1-C4 and C6; not the ropes of
    /// other lengths, masses or start directions).
    pub fn has_generated_model(&self) -> bool {
        !matches!(self.shape, SceneShape::Rope(_))
    }
    /// Whether the scene is one chain hanging from a pin (C1, C5-C7).
    pub fn is_chain(&self) -> bool {
        matches!(self.shape, SceneShape::Chain { .. } | SceneShape::Rope(_))
    }
    /// `id` and variant, e.g. `C1 N=100 r=1e2`.
    pub fn title(&self) -> String {
        format!("{} {}", self.id, self.variant)
    }
    /// A file-name stem, e.g. `c1_n100_r1e2`.
    pub fn stem(&self) -> String {
        let mut s = format!("{}_{}", self.id, self.variant).to_lowercase();
        s.retain(|c| c.is_ascii_alphanumeric() || c == '_' || c == ' ');
        s.replace(' ', "_")
    }
}

fn ratio_label(r: f64) -> String {
    if r == 1.0 {
        "1".into()
    } else {
        format!("1e{}", r.log10().round())
    }
}

/// C1: chain of `n` links with end-mass ratio `ratio`, 5 s.
pub fn c1(n: usize, ratio: f64) -> Result<ParticleScene, SystemError> {
    Ok(ParticleScene {
        id: "C1",
        variant: format!("N={n} r={}", ratio_label(ratio)),
        system: chain(n, ratio)?,
        shape: SceneShape::Chain {
            links: n,
            end_mass_ratio: ratio,
        },
        duration: 5.0,
        grab: None,
        conservative: true,
        tracked: n,
        param: ratio,
    })
}

/// A rope scene of 5 s from rest, its end particle tracked.
fn rope_scene(id: &'static str, variant: &str, r: Rope) -> Result<ParticleScene, SystemError> {
    Ok(ParticleScene {
        id,
        variant: variant.into(),
        system: rope(&r)?,
        shape: SceneShape::Rope(r),
        duration: 5.0,
        grab: None,
        conservative: true,
        tracked: r.links,
        param: r.end_mass_ratio,
    })
}

/// C5: Mueller's 4-pendulum ("Small steps in physics simulation", Macklin et al. 2019):
/// 4 links of 0.3 m, bobs of 0.1, 0.1, 0.1 and 10 kg, released horizontal.
pub fn c5() -> Result<ParticleScene, SystemError> {
    let r = Rope {
        links: 4,
        link_length: 0.3,
        particle_mass: 0.1,
        end_mass_ratio: 100.0,
        direction: [1.0, 0.0, 0.0],
    };
    rope_scene("C5", "4-pendulum r=1e2", r)
}

/// C6: the heavy rope of AVBD (Giles, Diaz, Yuksel 2025): 20 links, the end 1800 times
/// heavier, released horizontal; built as C1 (1 m, 0.1 kg), so it has C1's generated
/// model.
pub fn c6() -> Result<ParticleScene, SystemError> {
    let mut s = c1(20, 1800.0)?;
    s.id = "C6";
    s.variant = "N=20 r=1800".into();
    Ok(s)
}

/// C7: the hanging rope of AVBD: 50 links of 2 cm (1 m, 2 g particles), the end 200
/// times heavier, released from 0.5 rad off the vertical.
pub fn c7() -> Result<ParticleScene, SystemError> {
    let a = 0.5f64;
    let r = Rope {
        links: 50,
        link_length: 0.02,
        particle_mass: 2e-3,
        end_mass_ratio: 200.0,
        direction: [a.sin(), 0.0, -a.cos()],
    };
    rope_scene("C7", "N=50 r=200 0.5 rad", r)
}

/// C2: `s` strands of `n` links on the swaying head, 5 s.
pub fn c2(s: usize, n: usize) -> Result<ParticleScene, SystemError> {
    Ok(ParticleScene {
        id: "C2",
        variant: format!("{s}x{n}"),
        system: strands(s, n)?,
        shape: SceneShape::Strands {
            strands: s,
            links: n,
        },
        duration: 5.0,
        grab: None,
        conservative: false,
        tracked: n,
        param: f64::NAN,
    })
}

/// C3: a `w x w` cloth pinned as `pins` says (with shear diagonals if `shear`), 5 s;
/// with two pinned corners the far edge has [`FAR_EDGE_SLACK`].
pub fn c3(w: usize, pins: GridPins, shear: bool) -> Result<ParticleScene, SystemError> {
    c3_with_slack(w, pins, shear, FAR_EDGE_SLACK)
}

/// [`c3`] with the far edge's `slack` chosen ([`grid_with_slack`]); a slack other than
/// [`FAR_EDGE_SLACK`] is named in the variant (`W=32 (a) slack=0.02`).
pub fn c3_with_slack(
    w: usize,
    pins: GridPins,
    shear: bool,
    slack: f64,
) -> Result<ParticleScene, SystemError> {
    let tag = match pins {
        GridPins::Corners => "a",
        GridPins::Edge => "b",
        GridPins::CornersHeavy => "c",
    };
    Ok(ParticleScene {
        id: "C3",
        variant: format!(
            "W={w} ({tag}){}{}",
            if shear { " shear" } else { "" },
            slack_tag(pins, slack)
        ),
        system: grid_with_slack(w, pins, shear, slack)?,
        shape: SceneShape::Grid {
            w,
            pins,
            shear,
            slack,
        },
        duration: 5.0,
        grab: None,
        conservative: true,
        tracked: grid_index(w, 0, 0),
        param: f64::NAN,
    })
}

/// C4: C3(a) at `w`, the middle particle of the near edge grabbed at 1 s, moved 0.3 m
/// along `+x` and `+z` over 0.5 s, held, released at 2.5 s; 5 s.
pub fn c4(w: usize) -> Result<ParticleScene, SystemError> {
    c4_with_slack(w, FAR_EDGE_SLACK)
}

/// [`c4`] on the cloth of [`c3_with_slack`].
pub fn c4_with_slack(w: usize, slack: f64) -> Result<ParticleScene, SystemError> {
    let mut s = c3_with_slack(w, GridPins::Corners, false, slack)?;
    s.id = "C4";
    s.variant = format!("W={w}{}", slack_tag(GridPins::Corners, slack));
    s.conservative = false;
    s.grab = Some(Grab {
        particle: grid_index(w, w / 2, 0),
        at: 1.0,
        offset: [0.3, 0.0, 0.3],
        duration: 0.5,
        release: 2.5,
    });
    s.tracked = grid_index(w, w / 2, 0);
    Ok(s)
}

/// ` slack=S` in a variant whose far edge has a slack other than [`FAR_EDGE_SLACK`].
fn slack_tag(pins: GridPins, slack: f64) -> String {
    if pins == GridPins::Edge || slack == FAR_EDGE_SLACK {
        String::new()
    } else {
        format!(" slack={slack}")
    }
}

/// A scene from the command line's spelling: `c1:N:RATIO` (C1, `N` links, end-mass
/// ratio `RATIO`) or `c3:W` (C3 (a), `W` x `W`), as the study examples take it.
pub fn scene_of_spec(spec: &str) -> Result<ParticleScene, String> {
    let parts: Vec<&str> = spec.split(':').collect();
    let num = |s: &str| -> Result<f64, String> {
        s.parse()
            .map_err(|_| format!("`{s}` in `{spec}` is not a number"))
    };
    let size = |s: &str| -> Result<usize, String> {
        s.parse()
            .map_err(|_| format!("`{s}` in `{spec}` is not a size"))
    };
    match parts.as_slice() {
        ["c1", n, r] => c1(size(n)?, num(r)?).map_err(|e| e.to_string()),
        ["c3", w] => c3(size(w)?, GridPins::Corners, false).map_err(|e| e.to_string()),
        _ => Err(format!("`{spec}`: a scene is c1:N:RATIO or c3:W")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_heavy_end_scenes_are_the_papers_ropes() {
        let s5 = c5().unwrap();
        assert_eq!((s5.size(), s5.system.masses()[4]), (4, 10.0));
        assert_eq!(s5.system.masses()[1..4], [0.1; 3]);
        assert_eq!(s5.system.positions()[4][0], 1.2);
        let s6 = c6().unwrap();
        assert_eq!((s6.title().as_str(), s6.size()), ("C6 N=20 r=1800", 20));
        assert!(s6.has_generated_model() && s6.is_chain());
        let s7 = c7().unwrap();
        let end = s7.system.positions()[50];
        assert!((end[0].atan2(-end[2]) - 0.5).abs() < 1e-12, "{end:?}");
        assert_eq!(s7.system.masses()[50] / s7.system.masses()[1], 200.0);
        assert!(!s7.has_generated_model() && s7.is_chain());
        assert_eq!(s7.stem(), "c7_n50_r200_05_rad");
    }

    #[test]
    fn a_scene_spec_names_a_chain_or_a_cloth_or_says_what_is_wrong() {
        let chain = scene_of_spec("c1:10:1e2").expect("a chain");
        assert_eq!(
            (chain.title().as_str(), chain.size()),
            ("C1 N=10 r=1e2", 10)
        );
        let cloth = scene_of_spec("c3:8").expect("a cloth");
        assert_eq!(cloth.title(), "C3 W=8 (a)");
        let Err(bad) = scene_of_spec("c1:ten:1") else {
            panic!("`ten` is not a size")
        };
        assert!(bad.contains("`ten` in `c1:ten:1` is not a size"), "{bad}");
        let Err(bad) = scene_of_spec("c2:3") else {
            panic!("c2 is not a scene of the study examples")
        };
        assert!(bad.contains("c1:N:RATIO or c3:W"), "{bad}");
    }
}

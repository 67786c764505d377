//! One run of one method on one scene: frames through the scene runner, the scene's
//! grab, the metrics of docs/particles.md (worst strain, cost per frame, counts,
//! position error, energy drift), a wall-clock budget.

use std::time::{Duration, Instant};

use dae_particles::{
    AdaptiveMu, Backend, BackendError, Components, Counters, Dbsmc, FRAME, Part, ParticleDae,
    ParticleModel, Scene, System,
};
use dae_runtime::settings::Hold;
use dae_runtime::{
    Settings, design::ConstraintSpec, design::GainChoice, design::LayerBound, design::MuSearch,
    design::design, settings::AlphaChoice, settings::Integrator, solve::SolverChoice,
};

use super::scenes::{ParticleScene, SceneShape};
use crate::{
    particle_methods::Avbd, particle_methods::AvbdOptions, particle_methods::IndexOneParticles,
    particle_methods::PilotBounds, particle_methods::SweepOrder, particle_methods::Vbd,
    particle_methods::Xpbd,
};

/// A method and its setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MethodSpec {
    /// DBSMC with layers `eps_rel * L0` per link, designed from pilot bounds.
    Dbsmc {
        /// Relative layer (strain bound).
        eps: f64,
        /// The `J_s` solver.
        solver: SolverChoice,
        /// The integrator of the states between updates.
        integrator: Integrator,
    },
    /// DBSMC designed as [`MethodSpec::Dbsmc`] (automatic solver), run on the scene's
    /// generated family model (C1: `examples/models/chain.dae`, C2:
    /// `bench/models/c2_hair.dae`, C3 and C4: `bench/models/c3_cloth.dae`; see
    /// [`dae_particles::FamilyParticles`]).
    DbsmcGenerated {
        /// Relative layer (strain bound).
        eps: f64,
        /// The integrator of the states between updates.
        integrator: Integrator,
    },
    /// DBSMC with the frame-tied design of [`relaxed_settings`]: no pilot, one `mu` for
    /// every link, gains `k_i = gain eps_i / mu`, Dormand-Prince.
    DbsmcRelaxed {
        /// Relative layer (strain bound).
        eps: f64,
        /// The gain in units of `eps_i / mu` (4 is the drift-free part of T 4.4).
        gain: f64,
    },
    /// The frame-tied design of [`relaxed_settings`] with `v` ramping between updates
    /// against the drift of `s'` ([`Hold::RampAgainstDrift`]).
    DbsmcRamped {
        /// Relative layer (strain bound).
        eps: f64,
        /// The gain in units of `eps_i / mu`.
        gain: f64,
    },
    /// The frame-tied design with `v` ramped ([`MethodSpec::DbsmcRamped`]) and `mu`
    /// searched for during the run from a quarter of the frame ([`Dbsmc::adapt_mu`],
    /// [`AdaptiveMu::default`]).
    DbsmcAdaptive {
        /// Relative layer (strain bound).
        eps: f64,
        /// The gain in units of `eps_i / mu`.
        gain: f64,
    },
    /// The frame-tied design with `v` ramped ([`MethodSpec::DbsmcRamped`]) on the
    /// scene's generated family model (as [`MethodSpec::DbsmcGenerated`]): the
    /// compiled model with the design that needs no pilot.
    DbsmcRampGenerated {
        /// Relative layer (strain bound).
        eps: f64,
        /// The gain in units of `eps_i / mu`.
        gain: f64,
    },
    /// XPBD small steps: `k` substeps of one iteration per frame, links in the
    /// system's order.
    XpbdSubsteps(u32),
    /// XPBD small steps with the links swept by colour ([`SweepOrder::Coloured`]).
    XpbdColoured(u32),
    /// XPBD: one step of `n` iterations per frame.
    XpbdIterations(u32),
    /// The index-1 method with this many RK4 steps per frame.
    IndexOne(u32),
    /// Vertex Block Descent ([`Vbd`]): `k` substeps per frame of [`VBD_ITERATIONS`]
    /// iterations each.
    Vbd(u32),
    /// Augmented Vertex Block Descent ([`Avbd`]): `k` substeps per frame of
    /// [`AVBD_ITERATIONS`] iterations each.
    Avbd(u32),
    /// AVBD as [`MethodSpec::Avbd`] with the starting penalty raised to
    /// [`AVBD_TUNED_K_START`].
    AvbdTuned(u32),
}

/// Iterations per substep of [`MethodSpec::Vbd`] (its substeps are the knob).
pub const VBD_ITERATIONS: u32 = 10;
/// Iterations per substep of [`MethodSpec::Avbd`] (its substeps are the knob).
pub const AVBD_ITERATIONS: u32 = 10;
/// The starting (and least warm-started) penalty of [`MethodSpec::AvbdTuned`], N/m:
/// with the published `beta = 10` and `k_start = 1e3` the penalty hardly ramps in these
/// scenes' units; over `beta` in 10 ... 1e7 and `k_start` in 1e3 ... 1e7 on the
/// heavy-end scenes, `k_start = 1e7` gave the cheapest setting holding a level in most
/// cells, mostly with `beta = 10` (`examples/avbd_params.rs`, docs/particles.md).
pub const AVBD_TUNED_K_START: f64 = 1e7;

impl MethodSpec {
    /// The method's name in reports.
    pub fn method(&self) -> String {
        match self {
            MethodSpec::Dbsmc {
                solver, integrator, ..
            } => {
                let mut name = String::from("dbsmc");
                match integrator {
                    Integrator::Euler => name += "-euler",
                    Integrator::DormandPrince => name += "-dp",
                    _ => {}
                }
                if *solver != SolverChoice::Auto {
                    name += &format!("-{solver}");
                }
                name
            }
            MethodSpec::DbsmcGenerated { integrator, .. } => match integrator {
                Integrator::DormandPrince => "dbsmc-generated-dp".into(),
                _ => "dbsmc-generated".into(),
            },
            MethodSpec::DbsmcRelaxed { .. } => "dbsmc-relaxed".into(),
            MethodSpec::DbsmcRamped { .. } => "dbsmc-ramp".into(),
            MethodSpec::DbsmcAdaptive { .. } => "dbsmc-adapt".into(),
            MethodSpec::DbsmcRampGenerated { .. } => "dbsmc-ramp-generated".into(),
            MethodSpec::XpbdSubsteps(_) => "xpbd-substeps".into(),
            MethodSpec::XpbdColoured(_) => "xpbd-coloured".into(),
            MethodSpec::XpbdIterations(_) => "xpbd-iterations".into(),
            MethodSpec::IndexOne(_) => "index1-rk4".into(),
            MethodSpec::Vbd(_) => "vbd".into(),
            MethodSpec::Avbd(_) => "avbd".into(),
            MethodSpec::AvbdTuned(_) => "avbd-tuned".into(),
        }
    }
    /// The strain bound of a DBSMC setting (`None` for the methods without one). Every
    /// variant is named, so that a new DBSMC variant cannot fall through to `None`.
    pub fn eps(&self) -> Option<f64> {
        match *self {
            MethodSpec::Dbsmc { eps, .. }
            | MethodSpec::DbsmcGenerated { eps, .. }
            | MethodSpec::DbsmcRelaxed { eps, .. }
            | MethodSpec::DbsmcRamped { eps, .. }
            | MethodSpec::DbsmcAdaptive { eps, .. }
            | MethodSpec::DbsmcRampGenerated { eps, .. } => Some(eps),
            MethodSpec::XpbdSubsteps(_)
            | MethodSpec::XpbdColoured(_)
            | MethodSpec::XpbdIterations(_)
            | MethodSpec::IndexOne(_)
            | MethodSpec::Vbd(_)
            | MethodSpec::Avbd(_)
            | MethodSpec::AvbdTuned(_) => None,
        }
    }
    /// Whether the setting runs the scene's generated family model (which the ropes of
    /// other lengths and masses do not have: [`ParticleScene::has_generated_model`]).
    pub fn generated(&self) -> bool {
        matches!(
            self,
            MethodSpec::DbsmcGenerated { .. } | MethodSpec::DbsmcRampGenerated { .. }
        )
    }
    /// The setting, e.g. `k=20`.
    pub fn knob(&self) -> String {
        match self {
            MethodSpec::Dbsmc { eps, .. } | MethodSpec::DbsmcGenerated { eps, .. } => {
                format!("eps={eps:e}")
            }
            MethodSpec::DbsmcRelaxed { eps, gain }
            | MethodSpec::DbsmcRamped { eps, gain }
            | MethodSpec::DbsmcAdaptive { eps, gain }
            | MethodSpec::DbsmcRampGenerated { eps, gain } => format!("eps={eps:e} c={gain}"),
            MethodSpec::XpbdSubsteps(k)
            | MethodSpec::XpbdColoured(k)
            | MethodSpec::Vbd(k)
            | MethodSpec::Avbd(k)
            | MethodSpec::AvbdTuned(k) => format!("k={k}"),
            MethodSpec::XpbdIterations(n) => format!("n={n}"),
            MethodSpec::IndexOne(s) => format!("steps/frame={s}"),
        }
    }
}

/// One row of `particles.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleRecord {
    /// Scene id (`C1` ... `C4`).
    pub scene: String,
    /// Scene variant.
    pub variant: String,
    /// Number of links.
    pub size: usize,
    /// The scene's parameter (C1: end-mass ratio).
    pub param: f64,
    /// Method name.
    pub method: String,
    /// Method setting.
    pub knob: String,
    /// The strain bound (DBSMC only).
    pub eps: Option<f64>,
    /// Largest `|L - L0| / L0` over all links and frames run.
    pub worst_strain: f64,
    /// Mean and largest wall time per frame (ms).
    pub ms_mean: f64,
    /// Largest wall time of a frame (ms).
    pub ms_max: f64,
    /// Frames run.
    pub frames: u64,
    /// Frames of the scene.
    pub frames_total: u64,
    /// `ok`, `budget` (stopped after the wall-clock budget), `failed: ...`.
    pub status: String,
    /// Work counters.
    pub counters: Counters,
    /// Distance of the tracked particle from the reference at t = 1 s (m), if known.
    pub pos_err: Option<f64>,
    /// `(E(end) - E(0)) / (M g 1 m)` for conservative scenes.
    pub energy_drift: Option<f64>,
    /// The DBSMC design's guaranteed period `T_min` (s).
    pub t_min: Option<f64>,
    /// The DBSMC step (s).
    pub step: Option<f64>,
    /// Timings that `ms_mean` and `ms_max` are the medians of (1: timed once; see
    /// [`timed_repeatedly`](super::timed_repeatedly)).
    pub timings: u32,
}

impl ParticleRecord {
    /// Whether the whole scene ran.
    pub fn complete(&self) -> bool {
        self.status == "ok"
    }
}

/// A run not yet made: no frame, nothing measured (`NaN`), no status.
impl Default for ParticleRecord {
    fn default() -> Self {
        ParticleRecord {
            scene: String::new(),
            variant: String::new(),
            size: 0,
            param: f64::NAN,
            method: String::new(),
            knob: String::new(),
            eps: None,
            worst_strain: f64::NAN,
            ms_mean: f64::NAN,
            ms_max: f64::NAN,
            frames: 0,
            frames_total: 0,
            status: String::new(),
            counters: Counters::default(),
            pos_err: None,
            energy_drift: None,
            t_min: None,
            step: None,
            timings: 1,
        }
    }
}

#[cfg(test)]
impl ParticleRecord {
    /// A run for the tests: `method` at `knob` on C1 N=10 r=1, complete (300 of 300
    /// frames, `ok`) at 1 ms per frame; a test sets what else it looks at.
    pub(crate) fn for_tests(method: &str, knob: &str, eps: Option<f64>, worst_strain: f64) -> Self {
        ParticleRecord {
            scene: "C1".into(),
            variant: "N=10 r=1".into(),
            size: 10,
            param: 1.0,
            method: method.into(),
            knob: knob.into(),
            eps,
            worst_strain,
            ms_mean: 1.0,
            ms_max: 1.0,
            frames: 300,
            frames_total: 300,
            status: "ok".into(),
            ..ParticleRecord::default()
        }
    }
}

/// What [`drive_scene`] observes at each frame: the frame number and positions.
pub type FrameObserver<'a> = &'a mut dyn FnMut(u64, &[[f64; 3]]);

/// Run `backend` on `scene` for its duration, calling `observe` after every frame
/// (outside the timed part). A run stops early (status `budget`, with the frames it
/// ran measured) once it has spent `budget`, or a tenth of it while the projected time
/// of the whole scene exceeds `budget`.
pub fn drive_scene<B: Backend>(
    scene: &ParticleScene,
    spec: &MethodSpec,
    backend: B,
    budget: Duration,
    reference: Option<&[f64; 3]>,
    observe: Option<FrameObserver<'_>>,
) -> ParticleRecord {
    let frames_total = (scene.duration / FRAME).round() as u64;
    let mut rec = blank(scene, spec);
    rec.status = "ok".into();
    let sys = &scene.system;
    let n = sys.n_particles();
    let (mut x, mut v) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    backend.positions(&mut x);
    backend.velocities(&mut v);
    let e0 = sys.energy(&x, &v);
    let mut sc = match Scene::new(sys, backend) {
        Ok(s) => s,
        Err(e) => {
            rec.status = format!("failed: {e}");
            return rec;
        }
    };
    let mut observe = observe;
    if let Some(obs) = observe.as_mut() {
        obs(0, sc.positions());
    }
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    let clock = Instant::now();
    // The budget holds inside a frame too: a DBSMC run whose updates crowd (near a
    // singular J_s, or where the gains cannot hold a layer) can take hours for one.
    sc.backend_mut().set_deadline(Some(clock + budget));
    let grab_frame = scene.grab.map(|g| (g.at / FRAME).round() as u64);
    let release_frame = scene.grab.map(|g| (g.release / FRAME).round() as u64);
    for f in 1..=frames_total {
        if Some(f - 1) == grab_frame {
            let g = scene.grab.expect("grab frame implies a grab");
            if let Err(e) = sc.grab(g.particle, g.offset, g.duration) {
                rec.status = format!("failed: grab: {e}");
                break;
            }
        }
        if Some(f - 1) == release_frame {
            let g = scene.grab.expect("release frame implies a grab");
            if let Err(e) = sc.release(g.particle) {
                rec.status = format!("failed: release: {e}");
                break;
            }
        }
        match sc.step() {
            Ok(frame) => {
                sum += frame.wall;
                max = max.max(frame.wall);
                rec.frames = f;
            }
            Err(dae_particles::SceneError::Backend(e)) if e.deadline => {
                rec.status = "budget".into();
                break;
            }
            Err(e) => {
                rec.status = format!("failed: {e}");
                break;
            }
        }
        if let Some(obs) = observe.as_mut() {
            obs(f, sc.positions());
        }
        if f == 60 {
            if let Some(r) = reference {
                rec.pos_err = Some(dae_particles::distance(sc.positions()[scene.tracked], *r));
            }
        }
        // After a probe of a tenth of the budget, stop a run whose projected total
        // would exceed the budget: it is measured, not completed.
        let spent = clock.elapsed();
        let projected = spent.as_secs_f64() * frames_total as f64 / f as f64;
        if f < frames_total
            && (spent > budget || (spent > budget / 10 && projected > budget.as_secs_f64()))
        {
            rec.status = "budget".into();
            break;
        }
    }
    rec.worst_strain = sc.worst_strain().strain;
    if rec.frames > 0 {
        rec.ms_mean = 1e3 * sum / rec.frames as f64;
        rec.ms_max = 1e3 * max;
    }
    rec.counters = sc.backend().counters();
    if scene.conservative && rec.complete() {
        sc.backend().positions(&mut x);
        sc.backend().velocities(&mut v);
        let scale = sys.free_mass() * 9.81;
        rec.energy_drift = Some((sys.energy(&x, &v) - e0) / scale);
    }
    rec
}

/// The index-1 method on the scene's particle model (errors as a failed record).
pub fn index_one(
    scene: &ParticleScene,
    steps_per_frame: u32,
) -> Result<IndexOneParticles<ParticleModel>, String> {
    let model = ParticleModel::new(&scene.system).map_err(|e| e.to_string())?;
    IndexOneParticles::new(model, steps_per_frame, SolverChoice::Auto)
}

/// Pilot bounds of every constraint from an index-1 run of the scene at
/// `steps_per_frame` (the whole scene, or as much as `budget` allows: the record says
/// how many frames), and that run's record.
pub fn particle_pilot(
    scene: &ParticleScene,
    steps_per_frame: u32,
    budget: Duration,
) -> Result<(PilotBounds, ParticleRecord), String> {
    let spec = MethodSpec::IndexOne(steps_per_frame);
    let mut backend = index_one(scene, steps_per_frame)?.track_bounds();
    let rec = drive_scene(scene, &spec, &mut backend, budget, None, None);
    if !(rec.complete() || rec.status == "budget") {
        return Err(format!("pilot {}: {}", spec.knob(), rec.status));
    }
    let bounds = backend
        .bounds()
        .cloned()
        .ok_or("pilot produced no bounds")?;
    Ok((bounds, rec))
}

/// Safety factor on the pilot bounds before designing.
pub const PILOT_SAFETY: f64 = 2.0;

/// A DBSMC configuration designed from pilot bounds: per link `eps_i = eps L0_i`, the
/// exact `alpha` (one `beta` evaluation per update, so that the gain has no `|beta|` to
/// cover, T 3.17), the sufficient crossing gain `k_i = mu_i^3 M_i / 2 + 4 eps_i / mu_i`
/// (T 4.4) with `mu_i` maximising `T_i^min` (T 3.14), `M_i` the pilot's drift bound
/// (at least a hundredth of the largest) times [`PILOT_SAFETY`], monitoring, and the step `h = 0.2 min_i eps_i / k_i` rounded
/// down to divide the frame (the crossing overshoot `|s'| h` small against the layer).
/// Returns the settings and the design's guaranteed period `T_min`.
pub fn dbsmc_settings<M: ParticleDae>(
    model: &M,
    bounds: &PilotBounds,
    eps: f64,
    solver: SolverChoice,
) -> Result<(Settings, f64), String> {
    let m = model.n_constraints();
    let m_max = bounds.drift.iter().copied().fold(0.0, f64::max);
    let specs: Vec<ConstraintSpec> = (0..m)
        .map(|i| ConstraintSpec {
            r: 3,
            eps: eps * model.rest_length(i),
            // A link whose pilot saw almost no drift (quiet in the piloted frames) gets
            // a hundredth of the largest: without a floor T_min(mu) has no interior
            // maximum, and the link may move later.
            m: PILOT_SAFETY * bounds.drift[i].max(1e-2 * m_max).max(1e-300),
            // The exact alpha leaves no beta for the gain to cover (T 3.17).
            beta_abs: 0.0,
            layer: LayerBound::General,
        })
        .collect();
    let search = MuSearch {
        lo: 1e-9,
        hi: 10.0,
        scan_points: 201,
        ln_tol: 1e-6,
    };
    let d = design(&specs, GainChoice::Sufficient, &search).map_err(|e| format!("design: {e}"))?;
    let mu: Vec<f64> = d.constraints.iter().map(|c| c.mu).collect();
    // A gain of 0 (a link whose pilot saw beta = 0) would leave s adrift: floor it.
    let kmax = d.constraints.iter().map(|c| c.k).fold(0.0, f64::max);
    let k: Vec<f64> = d
        .constraints
        .iter()
        .map(|c| c.k.max(1e-3 * kmax).max(1e-12))
        .collect();
    let h_layer = (0..m)
        .map(|i| 0.2 * specs[i].eps / k[i])
        .fold(f64::INFINITY, f64::min);
    let per_frame = (FRAME / h_layer.min(FRAME)).ceil().max(1.0);
    let settings = Settings::new(specs.iter().map(|s| s.eps).collect(), mu, k)
        .step(FRAME / per_frame)
        .solver(solver)
        .alpha(AlphaChoice::Exact);
    Ok((settings, d.t_min))
}

/// `mu` of the relaxed design as a fraction of the frame: the sliding surface pulls
/// `w` back with both poles at `-1/mu`, four times per frame.
pub const RELAXED_MU_PER_FRAME: f64 = 0.25;

/// The longest Dormand-Prince step of the relaxed design, as a fraction of `mu`: the
/// cubic of `s` that locates the crossings is then fitted over a step no longer than half
/// of the surface's time constant. docs/particles.md ("Methods") has the `count_spread`
/// draws that chose it.
pub const RELAXED_STEP_PER_MU: f64 = 0.5;

/// The state tolerance of the relaxed design's Dormand-Prince steps, as a fraction of the
/// smallest layer: `rtol = atol = RELAXED_TOLERANCE_PER_EPS * min eps_i`, ten times the
/// runtime's default ([`dae_runtime::settings::TOLERANCE_PER_EPS`]). What keeps `s`
/// within its layer is each step's error in `s`
/// ([`dae_runtime::settings::LAYER_ERROR_PER_STEP`]), which does not depend on it; the
/// looser tolerance takes fewer steps for the same updates (docs/particles.md,
/// "Methods").
pub const RELAXED_TOLERANCE_PER_EPS: f64 = 0.1;

/// Safety factor of the relaxed design's gains over the drift of `s'` measured online
/// ([`GainRule::FollowDrift`](dae_runtime::settings::GainRule::FollowDrift)): 1 kept
/// the layer on every scene of `relaxed_design`, 2 cost 1.5-3.8x more per frame there
/// and kept nothing more (one run of
/// `cargo run --release -p dae-bench --example relaxed_design`).
pub const RELAXED_DRIFT_SAFETY: f64 = 1.0;

/// The shortest time between the grazing returns of a relaxed design's gain, as a
/// fraction of `mu` (its `graze`): a gain is raised over its floor only as far
/// as its returns need to stay `mu / 8` apart, not to the gain that sweeps the whole
/// layer. On C1 N=10 r=1e4 at eps = 1e-3 with the floor `4 eps / mu` this made 23
/// updates per frame against 143 with the sweeping gains; `mu / 16` made as many,
/// `mu / 4` 69 (one-off runs of the design with the fraction changed).
pub const RELAXED_GRAZE_PER_MU: f64 = 0.125;

/// The relaxed DBSMC design: no pilot, `mu = RELAXED_MU_PER_FRAME * FRAME` on every
/// link, `eps_i = eps L0_i`, gains at least `gain eps_i / mu` and following the drift
/// (`follow_drift(RELAXED_DRIFT_SAFETY)`) as far as grazing returns `mu / 8` apart need
/// (`graze(RELAXED_GRAZE_PER_MU * mu)`), the rate `-k_i s_i / eps_i` asked of a link
/// inside its layer (`saturate_in_layer`), the exact alpha, monitoring, Dormand-Prince
/// with the state tolerance `RELAXED_TOLERANCE_PER_EPS min eps_i` and steps of at most
/// `RELAXED_STEP_PER_MU * mu` (`mu / 2`).
///
/// The floor is the sufficient gain of T 4.4, `k = mu^3 M / 2 + 4 eps / mu`, for an
/// assumed drift `M_i = 2 (gain - 4) eps_i / mu^4` instead of the pilot's worst one: the
/// thesis's "afterwards smaller gains can be tried" (section 4.3) made into a rule.
/// Where the motion drifts faster, the gain follows the drift measured over the last
/// intervals. Nothing guarantees the crossing when the drift grows faster than that;
/// the runtime's monitor then reports the loss of the layer (`s_layer_lost_at`), which
/// no table counts as held.
///
/// The saturation inside the layer (instead of the method's `sgn`) leaves a link found
/// near the middle of its layer at an update moving slowly, so that the next update is
/// asked for by the links near their boundaries, not by whichever of many links was
/// sent across its layer at the full gain: 1.1-3.2x fewer updates per frame on the five
/// runs of `relaxed_design` (its rows "design with sgn(s)" against "design").
pub fn relaxed_settings<M: ParticleDae>(model: &M, eps: f64, gain: f64) -> Settings {
    relaxed_settings_at(model, eps, gain, RELAXED_MU_PER_FRAME)
}

/// [`relaxed_settings`] with `mu` another fraction of the frame than
/// [`RELAXED_MU_PER_FRAME`] (the gains, the longest step and the grazing return follow
/// `mu`): a study of how the design's cost depends on it (`examples/mu_sweep.rs`).
pub fn relaxed_settings_at<M: ParticleDae>(
    model: &M,
    eps: f64,
    gain: f64,
    mu_per_frame: f64,
) -> Settings {
    let e: Vec<f64> = (0..model.n_constraints())
        .map(|i| eps * model.rest_length(i))
        .collect();
    dae_runtime::design::Online {
        frame: FRAME,
        mu_per_frame,
        floor: gain,
        step_per_mu: RELAXED_STEP_PER_MU,
        tolerance_per_eps: RELAXED_TOLERANCE_PER_EPS,
        drift_safety: RELAXED_DRIFT_SAFETY,
        graze_per_mu: RELAXED_GRAZE_PER_MU,
        search: None,
        search_up_to: 0,
    }
    .settings(e)
    .expect("the frame-tied design's constants and layers are positive")
}

/// `settings` (a DBSMC law, as every frame-tied design is) with `v` ramping against the
/// drift between updates instead of held.
pub fn ramped(mut settings: Settings) -> Settings {
    settings
        .dbsmc_mut()
        .expect("the frame-tied designs use the DBSMC law")
        .hold = Hold::RampAgainstDrift;
    settings
}

/// The frame-tied design ([`relaxed_settings`]) on the hand-written model of each part
/// of `scene` ([`Components`]), its settings changed by `adjust` (fixed gains, another tolerance or longest step),
/// going on after a lost layer to measure what follows (the strain).
pub fn run_relaxed_with(
    scene: &ParticleScene,
    eps: f64,
    gain: f64,
    budget: Duration,
    adjust: impl Fn(Settings) -> Settings,
) -> ParticleRecord {
    run_relaxed_at(scene, eps, gain, RELAXED_MU_PER_FRAME, None, budget, adjust)
}

/// [`run_relaxed_with`] with `mu` at `mu_per_frame` of the frame
/// ([`relaxed_settings_at`]), from there searched for during the run if `search` is
/// given ([`Dbsmc::adapt_mu`]).
pub fn run_relaxed_at(
    scene: &ParticleScene,
    eps: f64,
    gain: f64,
    mu_per_frame: f64,
    search: Option<AdaptiveMu>,
    budget: Duration,
    adjust: impl Fn(Settings) -> Settings,
) -> ParticleRecord {
    let spec = MethodSpec::DbsmcRelaxed { eps, gain };
    let backend = Components::new(&scene.system, |part, _| {
        let model = ParticleModel::new(&part.system).map_err(|e| BackendError {
            method: "relaxed".into(),
            t: 0.0,
            reason: e.to_string(),
            deadline: false,
        })?;
        let settings = adjust(relaxed_settings_at(&model, eps, gain, mu_per_frame));
        Dbsmc::new(model, settings, "relaxed")
            .and_then(|b| searching(b, search))
            .map(Dbsmc::keep_going_after_bound_loss)
    });
    match backend {
        Ok(b) => drive_scene(scene, &spec, b, budget, None, None),
        Err(e) => {
            let mut r = blank(scene, &spec);
            r.status = format!("failed: {e}");
            r
        }
    }
}

/// Build the backend of `spec` for `scene` (DBSMC needs the pilot bounds).
pub fn run_particle_method(
    scene: &ParticleScene,
    spec: &MethodSpec,
    bounds: Option<&PilotBounds>,
    budget: Duration,
    reference: Option<&[f64; 3]>,
    observe: Option<FrameObserver<'_>>,
) -> ParticleRecord {
    let failed = |reason: String| {
        let mut r = blank(scene, spec);
        r.status = format!("failed: {reason}");
        r
    };
    // The pilot-based designs need the bounds; `None` without them.
    let pilot = bounds.map(Design::Pilot);
    let relaxed = |gain, ramp, search| Some(Design::Relaxed { gain, ramp, search });
    let dp = Integrator::DormandPrince;
    // The other methods run here; for DBSMC: the design, the solver and integrator, and
    // whether the model is generated.
    let (design, eps, solver, integrator, generated) = match *spec {
        MethodSpec::XpbdSubsteps(k) => {
            return match Xpbd::new(&scene.system, k, 1, SweepOrder::System) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::XpbdColoured(k) => {
            return match Xpbd::new(&scene.system, k, 1, SweepOrder::Coloured) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::XpbdIterations(n) => {
            return match Xpbd::new(&scene.system, 1, n, SweepOrder::System) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::IndexOne(s) => {
            return match index_one(scene, s) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::Vbd(k) => {
            return match Vbd::new(&scene.system, k, VBD_ITERATIONS) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::Avbd(k) => {
            return match Avbd::new(&scene.system, k, AVBD_ITERATIONS) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::AvbdTuned(k) => {
            let options = AvbdOptions {
                k_start: AVBD_TUNED_K_START,
                ..AvbdOptions::default()
            };
            return match Avbd::with_options(&scene.system, k, AVBD_ITERATIONS, options) {
                Ok(b) => drive_scene(scene, spec, b, budget, reference, observe),
                Err(e) => failed(e),
            };
        }
        MethodSpec::Dbsmc {
            eps,
            solver,
            integrator,
        } => (pilot, eps, solver, integrator, false),
        MethodSpec::DbsmcGenerated { eps, integrator } => {
            (pilot, eps, SolverChoice::Auto, integrator, true)
        }
        MethodSpec::DbsmcRelaxed { eps, gain } => (
            relaxed(gain, false, None),
            eps,
            SolverChoice::Auto,
            dp,
            false,
        ),
        MethodSpec::DbsmcRamped { eps, gain } => (
            relaxed(gain, true, None),
            eps,
            SolverChoice::Auto,
            dp,
            false,
        ),
        MethodSpec::DbsmcAdaptive { eps, gain } => {
            let search = Some(AdaptiveMu::default());
            (
                relaxed(gain, true, search),
                eps,
                SolverChoice::Auto,
                dp,
                false,
            )
        }
        MethodSpec::DbsmcRampGenerated { eps, gain } => {
            (relaxed(gain, true, None), eps, SolverChoice::Auto, dp, true)
        }
    };
    let Some(design) = design else {
        return failed("no pilot bounds for the design".into());
    };
    let run = RunDbsmc {
        scene,
        spec,
        design,
        eps,
        solver,
        integrator,
        budget,
        reference,
        observe,
        whole: false,
    };
    if generated {
        run.with_generated()
    } else {
        run.with(|part| ParticleModel::new(part).map_err(|e| e.to_string()))
    }
}

/// Where a DBSMC run's gains and `mu` come from.
enum Design<'a> {
    /// [`dbsmc_settings`] from these pilot bounds.
    Pilot(&'a PilotBounds),
    /// [`relaxed_settings`] with this gain, `v` ramped against the drift or held, `mu`
    /// searched for during the run ([`Dbsmc::adapt_mu`]) or fixed.
    Relaxed {
        gain: f64,
        ramp: bool,
        search: Option<AdaptiveMu>,
    },
}

/// `backend` with `mu` searched for during the run, if `search` says how.
fn searching<M: ParticleDae>(
    backend: Dbsmc<M>,
    search: Option<AdaptiveMu>,
) -> Result<Dbsmc<M>, BackendError> {
    match search {
        Some(how) => backend.adapt_mu(how),
        None => Ok(backend),
    }
}

/// A DBSMC run of a scene, whichever particle model it is given.
struct RunDbsmc<'a, 'o> {
    scene: &'a ParticleScene,
    spec: &'a MethodSpec,
    design: Design<'a>,
    eps: f64,
    solver: SolverChoice,
    integrator: Integrator,
    budget: Duration,
    reference: Option<&'a [f64; 3]>,
    observe: Option<FrameObserver<'o>>,
    /// Run the scene's system as one part, whatever joins it ([`Components::whole`]).
    whole: bool,
}

impl RunDbsmc<'_, '_> {
    /// The run with the system as one part.
    fn whole(self) -> Self {
        Self {
            whole: true,
            ..self
        }
    }

    /// [`Self::with`] on the scene's generated family model (C1: `chain.dae`, C2:
    /// `c2_hair.dae`, C3 and C4: `c3_cloth.dae`).
    fn with_generated(self) -> ParticleRecord {
        use crate::particle_methods::{generated_chain, generated_grid, generated_strands};
        match self.scene.shape {
            SceneShape::Chain {
                links,
                end_mass_ratio,
            } => self.with(|part| generated_chain(part, links, end_mass_ratio)),
            // `c2_hair.dae` places its strands on the head by their number, so a model
            // of one strand is not a strand of the head: the hair runs as one part.
            SceneShape::Strands { strands, links } => self
                .whole()
                .with(|part| generated_strands(part, strands, links)),
            SceneShape::Grid {
                w,
                pins,
                shear,
                slack,
            } => self.with(|part| generated_grid(part, w, pins, shear, slack)),
            SceneShape::Rope(_) => {
                let mut r = blank(self.scene, self.spec);
                r.status = "failed: the scene has no generated family model".into();
                r
            }
        }
    }

    /// Runs the scene with one DBSMC simulator per part of its system
    /// ([`Components`]: the strands of the hair apart, a connected scene as one part),
    /// each on the model `model` builds for the part and the settings designed for it
    /// (from the pilot bounds of its links, or the frame-tied design). The strain is
    /// measured over the whole run; a lost s-layer is recorded (`s_layer_lost_at`), not
    /// a reason to stop.
    fn with<M: ParticleDae + Send>(
        self,
        model: impl Fn(&System) -> Result<M, String>,
    ) -> ParticleRecord {
        let mut r = blank(self.scene, self.spec);
        let sys = &self.scene.system;
        let constraints = constraints_of_links(sys);
        let name = format!("{} {}", self.spec.method(), self.spec.knob());
        let search = match self.design {
            Design::Relaxed { search, .. } => search,
            Design::Pilot(_) => None,
        };
        // What the parts' designs say: the shortest guaranteed period, the first part's
        // step, and the first failure of a model or a design (reported as it is).
        let (mut t_min, mut step, mut refused) = (None::<f64>, None, None);
        let build = |part: &Part, _: usize| {
            let fail = |reason: String| BackendError {
                method: name.clone(),
                t: 0.0,
                reason,
                deadline: false,
            };
            let designed = model(&part.system).and_then(|m| {
                let of_part: Vec<usize> =
                    part.links.iter().filter_map(|&l| constraints[l]).collect();
                self.settings(&m, &of_part).map(|d| (m, d))
            });
            let (m, (settings, t)) = designed.map_err(|e| {
                refused.get_or_insert_with(|| e.clone());
                fail(e)
            })?;
            t_min = match (t_min, t) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            step.get_or_insert(settings.integration.step);
            Dbsmc::new(m, settings, &name)
                .and_then(|b| searching(b, search))
                .map(Dbsmc::keep_going_after_bound_loss)
        };
        let backend = if self.whole {
            Components::whole(sys, build)
        } else {
            Components::new(sys, build)
        };
        match backend {
            Ok(b) => {
                r = drive_scene(
                    self.scene,
                    self.spec,
                    b,
                    self.budget,
                    self.reference,
                    self.observe,
                );
            }
            Err(e) => match refused {
                Some(reason) => r.status = format!("failed: {reason}"),
                None => r.status = format!("failed: {e}"),
            },
        }
        r.t_min = t_min;
        r.step = step;
        r
    }

    /// The settings of a part's `model` whose constraints are the scene's constraints
    /// `constraints` (for the pilot bounds), and the guaranteed period if the design
    /// has one.
    fn settings<M: ParticleDae>(
        &self,
        model: &M,
        constraints: &[usize],
    ) -> Result<(Settings, Option<f64>), String> {
        match self.design {
            // An error-controlled integrator chooses its own steps (crossings are
            // located inside them): no step tied to the layer, at most a frame.
            Design::Pilot(bounds) => {
                let bounds = bounds.restricted(constraints);
                dbsmc_settings(model, &bounds, self.eps, self.solver).map(|(s, t)| {
                    let s = s.integrator(self.integrator);
                    let s = if self.integrator.is_adaptive() {
                        s.step(FRAME).max_step(FRAME)
                    } else {
                        s
                    };
                    (s, Some(t))
                })
            }
            // No guaranteed period: the design assumes its drift (see relaxed_settings).
            Design::Relaxed { gain, ramp, .. } => {
                let settings = relaxed_settings(model, self.eps, gain);
                Ok((if ramp { ramped(settings) } else { settings }, None))
            }
        }
    }
}

/// For each link of `system`, its constraint in the particle models (which drop the
/// links with both ends pinned), if it has one.
fn constraints_of_links(system: &System) -> Vec<Option<usize>> {
    let pins = system.pins();
    let mut next = 0;
    system
        .links()
        .iter()
        .map(|l| {
            (pins[l.a].is_none() || pins[l.b].is_none()).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect()
}

fn blank(scene: &ParticleScene, spec: &MethodSpec) -> ParticleRecord {
    ParticleRecord {
        scene: scene.id.to_string(),
        variant: scene.variant.clone(),
        size: scene.size(),
        param: scene.param,
        method: spec.method(),
        knob: spec.knob(),
        eps: spec.eps(),
        frames_total: (scene.duration / FRAME).round() as u64,
        ..ParticleRecord::default()
    }
}

//! A family model as the particle model of a [`System`]: the seam ([`ParticleDae`])
//! through which the DBSMC backend runs a model written as a `.dae` family, generated
//! or interpreted, exactly as it runs the hand-written [`ParticleModel`](crate::ParticleModel).
//!
//! The family model must be written over particles and links as the models of
//! `examples/models` and `bench/models` are: states `x[p]`, `v[p]` (`vec3`), one
//! constraint per link with a free end (in the order of the system's links), a
//! parameter `free[p]` (1 free, 0 pinned) and an input `pin[p]: vec3 with 3
//! derivatives` where a pinned particle sits (`X = free x + (1 - free) pin`).
//! [`FamilyParticles::new`] finds these by name and checks the model against the
//! system: where it starts, and `f` and `w` at a perturbed state, so that a model of
//! another scene is refused with the particle or link that differs.
//!
//! **Pins.** A pin of the system, and every pin change during a run
//! ([`ParticleDae::set_pin`]: a grab, a release), becomes `free[p]` and the input
//! `pin[p]`. A fixed pin is one `set_input` (its position, derivatives 0). A moving pin
//! ([`Motion`](crate::Motion)) is evaluated where the hand-written model evaluates it:
//! at the time of every evaluation. An evaluation at a new time first gives each moving
//! pin's input its position and three derivatives there (`set_input(i, t, [x, x', x'',
//! x'''])`), so that `w''` reads the pin's acceleration and `beta` its jerk exactly,
//! RK4 stages included; pins at rest cost nothing per evaluation.
//!
//! **The start.** The model's states start where the system's particles do (checked);
//! its tensions start consistent (`w'' = 0`, one solve with `J_Omega`), as the
//! hand-written model's do, rather than at the model's initial guess 0: the two runs
//! start alike, and a scene whose `J_Omega` is singular at the start is refused alike.
//!
//! **A pinned particle's state.** The family model does not read the state of a
//! pinned particle (it sits at its input) and leaves it alone (`der(v) = free * ... =
//! 0`). The adapter gives it the pin's acceleration instead, as the hand-written model
//! does, so that the state follows the pin: the positions the backend reports are
//! right, and a released particle continues from where its pin was, with the pin's
//! velocity.

use std::cell::{Cell, OnceCell, RefCell};

use dae_runtime::family::{FamilyInstance, InputError, Kernels, UnknownName};
use dae_runtime::{Model, ModelInfo, solve::LinearSolver, solve::Solver, solve::SolverChoice};

use crate::model::{ModelError, ParticleDae, check_pin_change};
use crate::motion::Pin;
use crate::system::{System, distance};

/// Why a family model is not the particle model of a [`System`]
/// ([`FamilyParticles::new`]): what differs, and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FamilyParticlesError {
    /// The model's state count is not 6 per particle of the system.
    #[error(
        "the family model `{model}` has {states} states; the system's {particles} particles need 6 each (x[p], v[p])"
    )]
    States {
        /// The family model's name.
        model: String,
        /// Its state count.
        states: usize,
        /// The system's particle count.
        particles: usize,
    },
    /// A state `x[p]`, `v[p]`, parameter `free[p]` or input `pin[p]` the adapter
    /// needs is not in the model.
    #[error("the family model `{model}`: {source}")]
    Name {
        /// The family model's name.
        model: String,
        /// The lookup that failed.
        source: UnknownName,
    },
    /// The components of a particle's `x` or `v` are not consecutive states.
    #[error("the components of `{family}[{particle}]` are not consecutive states")]
    Components {
        /// `x` or `v`.
        family: &'static str,
        /// The particle.
        particle: usize,
    },
    /// An input `pin[p]` carries fewer than the 3 time derivatives the index-3 links
    /// at a pinned particle read.
    #[error(
        "input `{input}` carries {order} time derivatives; the index-3 links at a pinned particle read 3"
    )]
    PinDerivatives {
        /// The input's name.
        input: String,
        /// The derivatives it carries.
        order: usize,
    },
    /// A particle starts elsewhere (or moving otherwise) in the model than in the system.
    #[error(
        "particle {particle} starts at {:?} with velocity {:?} in the family model, at {:?} with {:?} in the system: is it the model of this scene, at these sizes?",
        model_start.0, model_start.1, system_start.0, system_start.1
    )]
    Start {
        /// The particle.
        particle: usize,
        /// Its position and velocity in the model.
        model_start: ([f64; 3], [f64; 3]),
        /// Its position and velocity in the system.
        system_start: ([f64; 3], [f64; 3]),
    },
    /// The model's constraint count is not the system's count of links with a free end.
    #[error(
        "the family model `{model}` has {constraints} constraints; the system has {links} links with a free end"
    )]
    Constraints {
        /// The family model's name.
        model: String,
        /// Its constraint count.
        constraints: usize,
        /// The system's links with a free end.
        links: usize,
    },
    /// A constraint is not the link of the system it stands for (other ends or rest
    /// length): `w` and `w'` at a perturbed state differ.
    #[error(
        "constraint {constraint} (`{name}`) is not link {link} between particles {} and {} of rest length {rest}: w = {}, w' = {} where the link gives {}, {}",
        ends.0, ends.1, model_w.0, model_w.1, link_w.0, link_w.1
    )]
    Link {
        /// The model's constraint.
        constraint: usize,
        /// Its name.
        name: String,
        /// The system's link.
        link: usize,
        /// The link's particles.
        ends: (usize, usize),
        /// The link's rest length.
        rest: f64,
        /// `w` and `w'` of the constraint.
        model_w: (f64, f64),
        /// `w` and `w'` of the link.
        link_w: (f64, f64),
    },
    /// A particle accelerates otherwise in the model than in the system (another
    /// mass, gravity or pin) at a perturbed state.
    #[error(
        "particle {particle} accelerates at {model_acc:?} in the family model, at {system_acc:?} in the system (mass {mass}, pinned: {pinned}): is it the model of this scene?"
    )]
    Acceleration {
        /// The particle.
        particle: usize,
        /// Its acceleration in the model.
        model_acc: [f64; 3],
        /// Its acceleration in the system.
        system_acc: [f64; 3],
        /// Its mass in the system.
        mass: f64,
        /// Whether it is pinned.
        pinned: bool,
    },
    /// A pin's position could not be given to the model's input (not finite).
    #[error("particle {particle}: {source}")]
    Pin {
        /// The pinned particle.
        particle: usize,
        /// The input's refusal.
        source: InputError,
    },
    /// The scene cannot start as the hand-written model's cannot (a singular `J_Omega`).
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// A family model (any back end `K`: generated kernels or the interpreter) as the
/// particle model of a [`System`] (module docs).
pub struct FamilyParticles<K: Kernels> {
    /// In a `RefCell`: an evaluation (`&self`) at a new time sets the moving pins'
    /// inputs first. The `Model` methods never re-enter, so borrows do not overlap.
    model: RefCell<FamilyInstance<K>>,
    name: String,
    /// Copies of what `Model` lends out by reference (the model sits in a `RefCell`):
    /// the pattern, and the metadata, copied on first use.
    pattern: Vec<(usize, usize)>,
    info: OnceCell<ModelInfo>,
    /// Per particle: the states `x[k].x` and `v[k].x`, the parameter `free[k]`, the
    /// inputs `pin[k].x, .y, .z`.
    slots: Vec<(usize, usize)>,
    free: Vec<usize>,
    pin_inputs: Vec<[usize; 3]>,
    pins: Vec<Option<Pin>>,
    /// The particles with a moving pin, and their accelerations at `refreshed_at`.
    moving: Vec<usize>,
    moving_acc: RefCell<Vec<[f64; 3]>>,
    /// When the moving pins' inputs were last set (NaN: not since the pins changed).
    refreshed_at: Cell<f64>,
    /// A moving pin gave a value `set_input` refused (not finite) at the last refresh:
    /// the evaluations return NaN, which the simulator reports, rather than stale pins.
    bad_pin: Cell<bool>,
    /// The system's links, each one's constraint, and the constraints' rest lengths.
    system_links: Vec<(usize, usize)>,
    link_constraint: Vec<Option<usize>>,
    rest: Vec<f64>,
    /// The consistent tensions at the start (`w'' = 0`), as the hand-written model's.
    z0: Vec<f64>,
}

impl<K: Kernels> std::fmt::Debug for FamilyParticles<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FamilyParticles")
            .field("name", &self.name)
            .field("particles", &self.slots.len())
            .field("links", &self.rest.len())
            .field("moving_pins", &self.moving.len())
            .finish()
    }
}

impl<K: Kernels> FamilyParticles<K> {
    /// `model` as the particle model of `system`: the particles' states, `free` and `pin`
    /// found by name, the system's pins applied, and the model checked against the
    /// system (module docs). The error says what differs, where.
    pub fn new(model: FamilyInstance<K>, system: &System) -> Result<Self, FamilyParticlesError> {
        let n = system.n_particles();
        if model.n_states() != 6 * n {
            return Err(FamilyParticlesError::States {
                model: model.name().to_string(),
                states: model.n_states(),
                particles: n,
            });
        }
        let unknown = |source: UnknownName| FamilyParticlesError::Name {
            model: model.name().to_string(),
            source,
        };
        let state = |family: &'static str, k: usize| -> Result<usize, FamilyParticlesError> {
            let i = model
                .state_index_at(&format!("{family}.x"), k)
                .map_err(unknown)?;
            for (c, axis) in ["y", "z"].iter().enumerate() {
                let next = model
                    .state_index_at(&format!("{family}.{axis}"), k)
                    .map_err(unknown)?;
                if next != i + c + 1 {
                    return Err(FamilyParticlesError::Components {
                        family,
                        particle: k,
                    });
                }
            }
            Ok(i)
        };
        let mut slots = Vec::with_capacity(n);
        let mut free = Vec::with_capacity(n);
        let mut pin_inputs = Vec::with_capacity(n);
        for k in 0..n {
            slots.push((state("x", k)?, state("v", k)?));
            free.push(model.param_index_at("free", k).map_err(unknown)?);
            let mut pin = [0; 3];
            for (c, i) in ["pin.x", "pin.y", "pin.z"].iter().zip(&mut pin) {
                *i = model.input_index_at(c, k).map_err(unknown)?;
                if model.input_order(*i) < 3 {
                    return Err(FamilyParticlesError::PinDerivatives {
                        input: model.input_name(*i).to_string(),
                        order: model.input_order(*i),
                    });
                }
            }
            pin_inputs.push(pin);
        }
        // Where the model starts: the system's positions and velocities.
        let mut x0 = vec![0.0; model.n_states()];
        model.initial_state(&mut x0);
        for (k, &(p, v)) in slots.iter().enumerate() {
            let (pm, vm) = (get3(&x0, p), get3(&x0, v));
            let (ps, vs) = (system.positions()[k], system.velocities()[k]);
            if distance(pm, ps) > 1e-12 * (1.0 + norm(ps)) || distance(vm, vs) > 1e-12 {
                return Err(FamilyParticlesError::Start {
                    particle: k,
                    model_start: (pm, vm),
                    system_start: (ps, vs),
                });
            }
        }
        // The constraints: the system's links with a free end, in order (as the
        // hand-written model numbers them).
        let pinned = |k: usize| system.pins()[k].is_some();
        let mut link_constraint = Vec::with_capacity(system.links().len());
        let mut rest = Vec::new();
        for link in system.links() {
            if pinned(link.a) && pinned(link.b) {
                link_constraint.push(None);
            } else {
                link_constraint.push(Some(rest.len()));
                rest.push(link.rest);
            }
        }
        if rest.len() != model.n_constraints() {
            return Err(FamilyParticlesError::Constraints {
                model: model.name().to_string(),
                constraints: model.n_constraints(),
                links: rest.len(),
            });
        }
        let m = rest.len();
        let mut this = Self {
            name: model.name().to_string(),
            pattern: model.jacobian_pattern().to_vec(),
            model: RefCell::new(model),
            info: OnceCell::new(),
            slots,
            free,
            pin_inputs,
            pins: vec![None; n],
            moving: Vec::new(),
            moving_acc: RefCell::new(Vec::new()),
            refreshed_at: Cell::new(f64::NAN),
            bad_pin: Cell::new(false),
            system_links: system.links().iter().map(|l| (l.a, l.b)).collect(),
            link_constraint,
            rest,
            z0: Vec::new(),
        };
        for k in 0..n {
            this.apply_pin(k, system.pins()[k].clone())?;
        }
        this.check_physics(system, m)?;
        this.z0 = this.consistent_tensions()?;
        Ok(this)
    }

    /// The tensions that make `w'' = 0` on every link at the start: one solve with
    /// `J_Omega` (`w''` is affine in `z`), so that the run starts as the hand-written
    /// model's does (the model's own initial guess is 0).
    fn consistent_tensions(&self) -> Result<Vec<f64>, FamilyParticlesError> {
        let m = self.rest.len();
        // The hand-written model's words for it.
        let singular = |e: String| FamilyParticlesError::Model(ModelError::Singular(e));
        let mut solver = Solver::new(m, &self.pattern, SolverChoice::Auto)
            .map_err(|e| singular(e.to_string()))?;
        let mut x0 = vec![0.0; self.n_states()];
        self.initial_state(&mut x0);
        let zero = vec![0.0; m];
        let mut vals = vec![0.0; self.pattern.len()];
        self.jacobian(0.0, &x0, &zero, &mut vals);
        solver
            .factor(&vals, &vec![1.0; m])
            .map_err(|e| singular(e.to_string()))?;
        let (mut w, mut s, mut ah) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
        self.sliding(0.0, &x0, &zero, &vec![1.0; m], &mut w, &mut s, &mut ah);
        let mut z: Vec<f64> = (0..m).map(|l| -w[3 * l + 2]).collect();
        solver.solve(&mut z);
        Ok(z)
    }

    /// Makes particle `k` free or pinned to `pin` (no checks of the links).
    fn apply_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), FamilyParticlesError> {
        let model = self.model.get_mut();
        model.set_param(self.free[k], if pin.is_some() { 0.0 } else { 1.0 });
        self.moving.retain(|&j| j != k);
        if let Some(Pin::Fixed(p)) = &pin {
            for (c, &i) in self.pin_inputs[k].iter().enumerate() {
                model
                    .set_input(i, 0.0, &[p[c]])
                    .map_err(|source| FamilyParticlesError::Pin {
                        particle: k,
                        source,
                    })?;
            }
        }
        if let Some(Pin::Moving(_)) = &pin {
            self.moving.push(k);
        }
        self.moving_acc
            .get_mut()
            .resize(self.moving.len(), [0.0; 3]);
        self.pins[k] = pin;
        // The moving pins' inputs are set again at the next evaluation.
        self.refreshed_at.set(f64::NAN);
        Ok(())
    }

    /// Gives every moving pin's input its position and three derivatives at `t` (once
    /// per distinct `t`).
    fn refresh(&self, t: f64) {
        if self.moving.is_empty() || self.refreshed_at.get().to_bits() == t.to_bits() {
            return;
        }
        let mut model = self.model.borrow_mut();
        let mut acc = self.moving_acc.borrow_mut();
        let mut ok = true;
        for (j, &k) in self.moving.iter().enumerate() {
            let Some(pin) = &self.pins[k] else { continue };
            let kin = pin.at(t);
            for (c, &i) in self.pin_inputs[k].iter().enumerate() {
                let taylor = [kin.pos[c], kin.vel[c], kin.acc[c], kin.jerk[c]];
                ok &= model.set_input(i, t, &taylor).is_ok();
            }
            acc[j] = kin.acc;
        }
        self.bad_pin.set(!ok);
        self.refreshed_at.set(t);
    }

    /// After an evaluation: NaN out if a moving pin could not be set.
    fn poison(&self, out: &mut [f64]) {
        if self.bad_pin.get() {
            out.fill(f64::NAN);
        }
    }

    /// Checks `f` and `w` of the model against the system's physics at a perturbed
    /// state (off the manifold, moving, with tensions): every link's ends and rest
    /// length, every particle's mass, gravity and pin.
    fn check_physics(&self, system: &System, m: usize) -> Result<(), FamilyParticlesError> {
        let n = self.slots.len();
        let scale = self.rest.iter().copied().fold(f64::INFINITY, f64::min);
        let mut x = vec![0.0; 6 * n];
        let mut pos = vec![[0.0; 3]; n];
        let mut vel = vec![[0.0; 3]; n];
        for (k, &(p, v)) in self.slots.iter().enumerate() {
            let kf = k as f64;
            let wobble = [
                (1.3 * kf + 0.1).sin(),
                (2.1 * kf).cos(),
                (0.7 * kf + 1.0).sin(),
            ];
            for c in 0..3 {
                pos[k][c] = system.positions()[k][c] + 0.1 * scale * wobble[c];
                vel[k][c] = wobble[(c + 1) % 3];
                x[p + c] = pos[k][c];
                x[v + c] = vel[k][c];
            }
            if let Some(pin) = &self.pins[k] {
                let kin = pin.at(0.0);
                (pos[k], vel[k]) = (kin.pos, kin.vel);
            }
        }
        let z: Vec<f64> = (0..m).map(|i| (0.37 * i as f64).sin()).collect();
        let (mut w, mut s, mut ah) = (vec![0.0; 3 * m], vec![0.0; m], vec![0.0; m]);
        self.sliding(0.0, &x, &z, &vec![0.0; m], &mut w, &mut s, &mut ah);
        let mut acc: Vec<[f64; 3]> = (0..n)
            .map(|k| match &self.pins[k] {
                Some(pin) => pin.at(0.0).acc,
                None => system.gravity(),
            })
            .collect();
        for (l, &(a, b)) in self.system_links.iter().enumerate() {
            let Some(i) = self.link_constraint[l] else {
                continue;
            };
            let d = sub(pos[b], pos[a]);
            let len = norm(d);
            let u = [d[0] / len, d[1] / len, d[2] / len];
            let (w0, w1) = (len - self.rest[i], dot(u, sub(vel[b], vel[a])));
            if (w[3 * i] - w0).abs() > 1e-9 * scale || (w[3 * i + 1] - w1).abs() > 1e-9 {
                return Err(FamilyParticlesError::Link {
                    constraint: i,
                    name: self.constraint_name(i).to_string(),
                    link: l,
                    ends: (a, b),
                    rest: self.rest[i],
                    model_w: (w[3 * i], w[3 * i + 1]),
                    link_w: (w0, w1),
                });
            }
            for c in 0..3 {
                if self.pins[a].is_none() {
                    acc[a][c] += z[i] * u[c] / system.masses()[a];
                }
                if self.pins[b].is_none() {
                    acc[b][c] -= z[i] * u[c] / system.masses()[b];
                }
            }
        }
        let mut f = vec![0.0; 6 * n];
        self.rhs(0.0, &x, &z, &mut f);
        for (k, &(_, v)) in self.slots.iter().enumerate() {
            let got = get3(&f, v);
            if distance(got, acc[k]) > 1e-9 * (1.0 + norm(acc[k])) {
                return Err(FamilyParticlesError::Acceleration {
                    particle: k,
                    model_acc: got,
                    system_acc: acc[k],
                    mass: system.masses()[k],
                    pinned: self.pins[k].is_some(),
                });
            }
        }
        Ok(())
    }

    /// The family model (for its names, parameters and inputs).
    pub fn family(&self) -> std::cell::Ref<'_, FamilyInstance<K>> {
        self.model.borrow()
    }
}

fn get3(x: &[f64], i: usize) -> [f64; 3] {
    [x[i], x[i + 1], x[i + 2]]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

impl<K: Kernels> Model for FamilyParticles<K> {
    fn info(&self) -> &ModelInfo {
        self.info.get_or_init(|| self.model.borrow().info().clone())
    }
    fn n_states(&self) -> usize {
        6 * self.slots.len()
    }
    fn n_constraints(&self) -> usize {
        self.rest.len()
    }
    fn n_params(&self) -> usize {
        self.model.borrow().n_params()
    }
    fn param(&self, i: usize) -> f64 {
        self.model.borrow().param(i)
    }
    fn set_param(&mut self, i: usize, value: f64) {
        self.model.get_mut().set_param(i, value)
    }
    fn initial_state(&self, x: &mut [f64]) {
        self.model.borrow().initial_state(x)
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.copy_from_slice(&self.z0)
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.refresh(t);
        self.model.borrow().rhs(t, x, z, dx);
        // A pinned particle's state follows its pin (module docs): at rest, the model's
        // own `der(v) = 0` is that already.
        for (&k, a) in self.moving.iter().zip(self.moving_acc.borrow().iter()) {
            let v = self.slots[k].1;
            dx[v..v + 3].copy_from_slice(a);
        }
        self.poison(dx);
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
        self.refresh(t);
        self.model.borrow().sliding(t, x, z, mu, w, s, ah);
        self.poison(s);
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.pattern
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.refresh(t);
        self.model.borrow().jacobian(t, x, z, values);
        self.poison(values);
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.refresh(t);
        self.model.borrow().beta(t, x, z, beta);
        self.poison(beta);
    }
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        self.refresh(t);
        let given = self.model.borrow().omega_rate(t, x, z, zdot, rate);
        self.poison(rate);
        given
    }
}

impl<K: Kernels> ParticleDae for FamilyParticles<K> {
    fn n_particles(&self) -> usize {
        self.slots.len()
    }
    fn state_slots(&self, k: usize) -> (usize, usize) {
        self.slots[k]
    }
    fn constraint_of_link(&self, l: usize) -> Option<usize> {
        self.link_constraint.get(l).copied().flatten()
    }
    fn rest_length(&self, i: usize) -> f64 {
        self.rest[i]
    }
    /// `free[k]` and the input `pin[k]` (module docs), with the hand-written model's
    /// checks: a link keeps a free end, and a link left out because both its ends were
    /// pinned stays so.
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), ModelError> {
        check_pin_change(
            &self.system_links,
            &self.pins,
            &self.link_constraint,
            k,
            pin.is_some(),
        )?;
        self.apply_pin(k, pin)
            .map_err(|e| ModelError::Unsupported(e.to_string()))
    }
}

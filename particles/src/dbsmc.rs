//! The DBSMC backend: the runtime's [`Simulator`] driving a [`ParticleDae`] model.
//!
//! The simulator of this version of `dae-runtime` runs from start to end in one call
//! ([`Simulator::run`]) and borrows its model. To advance it frame by frame it runs on
//! a thread of its own, and its sink stops at every frame boundary: it hands the
//! positions over and waits for the next command (advance, pin, read a particle).
//! Pin changes reach the model between two steps (the simulator is inside the sink's
//! `record`, no model call is in progress), through a `RefCell` that only that thread
//! touches; the next control update (triggered by the layers, as always) sees them.

use std::cell::{Cell, RefCell};
use std::io;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use dae_runtime::{Layout, Model, Sample, Settings, Simulator, Sink};

use crate::backend::{Backend, BackendError, Counters};
use crate::model::ParticleDae;
use crate::motion::{Kinematics, Pin};
use crate::scene::FRAME;

/// Commands from the backend to the simulating thread.
enum Command {
    Advance(f64),
    SetPin(usize, Option<Pin>),
    Particle(usize),
    Stop,
}

/// Answers of the simulating thread.
enum Reply {
    Frame {
        t: f64,
        x: Vec<f64>,
        counters: Counters,
    },
    Pinned(Result<(), String>),
    Particle(Kinematics),
    Failed {
        t: f64,
        reason: String,
    },
}

/// The model behind a `RefCell` (pins change between steps) with call counters; the
/// names, indices and pattern are copied once (a pin change never alters them).
struct Shared<M> {
    model: RefCell<M>,
    name: String,
    states: Vec<String>,
    algs: Vec<String>,
    constraints: Vec<String>,
    indices: Vec<usize>,
    pattern: Vec<(usize, usize)>,
    rhs_calls: Cell<u64>,
    jacobian_calls: Cell<u64>,
}

impl<M: ParticleDae> Shared<M> {
    fn new(model: M) -> Self {
        Self {
            name: model.name().to_string(),
            states: (0..model.n_states())
                .map(|i| model.state_name(i).to_string())
                .collect(),
            algs: (0..model.n_constraints())
                .map(|i| model.alg_name(i).to_string())
                .collect(),
            constraints: (0..model.n_constraints())
                .map(|i| model.constraint_name(i).to_string())
                .collect(),
            indices: model.indices().to_vec(),
            pattern: model.jacobian_pattern().to_vec(),
            model: RefCell::new(model),
            rhs_calls: Cell::new(0),
            jacobian_calls: Cell::new(0),
        }
    }
}

impl<M: ParticleDae> Model for Shared<M> {
    fn name(&self) -> &str {
        &self.name
    }
    fn n_states(&self) -> usize {
        self.states.len()
    }
    fn n_constraints(&self) -> usize {
        self.algs.len()
    }
    fn n_params(&self) -> usize {
        0
    }
    fn state_name(&self, i: usize) -> &str {
        &self.states[i]
    }
    fn alg_name(&self, i: usize) -> &str {
        &self.algs[i]
    }
    fn constraint_name(&self, i: usize) -> &str {
        &self.constraints[i]
    }
    fn param_name(&self, _: usize) -> &str {
        ""
    }
    fn indices(&self) -> &[usize] {
        &self.indices
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        self.model.borrow().initial_state(x)
    }
    fn initial_alg(&self, z: &mut [f64]) {
        self.model.borrow().initial_alg(z)
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.rhs_calls.set(self.rhs_calls.get() + 1);
        self.model.borrow().rhs(t, x, z, dx)
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
        self.model.borrow().sliding(t, x, z, mu, w, s, ah)
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.pattern
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.jacobian_calls.set(self.jacobian_calls.get() + 1);
        self.model.borrow().jacobian(t, x, z, values)
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.model.borrow().beta(t, x, z, beta)
    }
}

/// The sink that stops the simulator at frame boundaries and serves commands there.
struct FrameSink<'a, M> {
    shared: &'a Shared<M>,
    commands: Receiver<Command>,
    replies: Sender<Reply>,
    /// The time the caller asked to reach.
    target: f64,
    /// Half a step: a step within it of the target ends the frame.
    tolerance: f64,
    steps: u64,
    updates: u64,
    slots: Vec<(usize, usize)>,
    f: Vec<f64>,
}

impl<M: ParticleDae> FrameSink<'_, M> {
    fn counters(&self) -> Counters {
        let factorisations = self.shared.jacobian_calls.get();
        Counters {
            steps: self.steps,
            f_evals: self.shared.rhs_calls.get(),
            factorisations,
            iterations: 0,
            updates: self.updates,
        }
    }

    /// Hand over the frame, then serve commands until told to advance (or stop).
    fn serve(&mut self, s: &Sample<'_>) -> io::Result<()> {
        let frame = Reply::Frame {
            t: s.t,
            x: s.x.to_vec(),
            counters: self.counters(),
        };
        let stopped = || io::Error::other("the DBSMC backend was dropped");
        self.replies.send(frame).map_err(|_| stopped())?;
        loop {
            match self.commands.recv().map_err(|_| stopped())? {
                Command::Advance(t) => {
                    self.target = t;
                    return Ok(());
                }
                Command::SetPin(k, pin) => {
                    let r = self
                        .shared
                        .model
                        .borrow_mut()
                        .set_pin(k, pin)
                        .map_err(|e| e.to_string());
                    self.replies.send(Reply::Pinned(r)).map_err(|_| stopped())?;
                }
                Command::Particle(k) => {
                    self.shared.model.borrow().rhs(s.t, s.x, s.z, &mut self.f);
                    let (p, v) = self.slots[k];
                    let k = Kinematics {
                        pos: [s.x[p], s.x[p + 1], s.x[p + 2]],
                        vel: [s.x[v], s.x[v + 1], s.x[v + 2]],
                        acc: [self.f[v], self.f[v + 1], self.f[v + 2]],
                        jerk: [0.0; 3],
                    };
                    self.replies
                        .send(Reply::Particle(k))
                        .map_err(|_| stopped())?;
                }
                Command::Stop => return Err(stopped()),
            }
        }
    }
}

impl<M: ParticleDae> Sink for FrameSink<'_, M> {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        Ok(())
    }
    fn wants(&self, _: u64, t: f64) -> bool {
        t >= self.target - self.tolerance
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.steps = s.step;
        if s.step == 0 || s.t >= self.target - self.tolerance {
            self.serve(s)?;
        }
        Ok(())
    }
    fn update(&mut self, _: f64) -> io::Result<()> {
        self.updates += 1;
        Ok(())
    }
}

/// DBSMC on a particle model: the runtime's [`Simulator`] with the given [`Settings`]
/// (layers `eps_i` in metres, `mu_i`, gains, step, solver), advanced frame by frame.
///
/// The step must divide the frame ([`FRAME`] / step a whole number), so that frames
/// end on steps. `settings.t_start` must be 0; `settings.t_end` is ignored (the run
/// lasts as long as the backend lives).
pub struct Dbsmc {
    name: String,
    n_particles: usize,
    slots: Vec<(usize, usize)>,
    commands: Sender<Command>,
    replies: Receiver<Reply>,
    thread: Option<JoinHandle<()>>,
    t: f64,
    x: Vec<f64>,
    counters: Counters,
    failed: Option<BackendError>,
}

impl std::fmt::Debug for Dbsmc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Dbsmc")
            .field("name", &self.name)
            .field("t", &self.t)
            .finish()
    }
}

impl Dbsmc {
    /// Start DBSMC on `model` with `settings`; `name` labels reports.
    pub fn new<M: ParticleDae + Send + 'static>(
        model: M,
        settings: Settings,
        name: &str,
    ) -> Result<Self, BackendError> {
        let fail = |reason: String| BackendError {
            method: name.to_string(),
            t: 0.0,
            reason,
        };
        let per_frame = FRAME / settings.step;
        if !(per_frame.is_finite()
            && per_frame >= 1.0
            && (per_frame - per_frame.round()).abs() < 1e-6)
        {
            return Err(fail(format!(
                "step {} does not divide the frame of 1/60 s (choose 1/(60 k))",
                settings.step
            )));
        }
        if settings.t_start != 0.0 {
            return Err(fail(format!("t_start is {}, must be 0", settings.t_start)));
        }
        let n_particles = model.n_particles();
        let slots: Vec<(usize, usize)> = (0..n_particles).map(|k| model.state_slots(k)).collect();
        let (cmd_tx, cmd_rx) = channel();
        let (rep_tx, rep_rx) = channel();
        let mut settings = settings;
        settings.t_end = 1e9;
        let thread_slots = slots.clone();
        let thread = std::thread::spawn(move || {
            let n = model.n_states();
            let shared = Shared::new(model);
            let mut sink = FrameSink {
                shared: &shared,
                commands: cmd_rx,
                replies: rep_tx.clone(),
                target: 0.0,
                tolerance: 0.5 * settings.step,
                steps: 0,
                updates: 0,
                slots: thread_slots,
                f: vec![0.0; n],
            };
            let (t, e) = match Simulator::new(&shared, settings) {
                Err(e) => (0.0, e),
                Ok(mut sim) => match sim.run(&mut sink) {
                    Ok(_) => return,
                    Err(e) => (sim.time(), e),
                },
            };
            // After a stop nobody listens any more; the send then fails harmlessly.
            let _ = rep_tx.send(Reply::Failed {
                t,
                reason: e.to_string(),
            });
        });
        let mut me = Self {
            name: name.to_string(),
            n_particles,
            slots,
            commands: cmd_tx,
            replies: rep_rx,
            thread: Some(thread),
            t: 0.0,
            x: Vec::new(),
            counters: Counters::default(),
            failed: None,
        };
        me.await_frame()?;
        Ok(me)
    }

    fn await_frame(&mut self) -> Result<(), BackendError> {
        match self.replies.recv() {
            Ok(Reply::Frame { t, x, counters }) => {
                self.t = t;
                self.x = x;
                self.counters = counters;
                Ok(())
            }
            Ok(Reply::Failed { t, reason }) => Err(self.failure(t, reason)),
            Ok(_) => {
                Err(self.failure(self.t, "unexpected reply from the simulating thread".into()))
            }
            Err(_) => Err(self.failure(self.t, "the simulating thread ended".into())),
        }
    }

    fn failure(&mut self, t: f64, reason: String) -> BackendError {
        let e = BackendError {
            method: self.name.clone(),
            t,
            reason,
        };
        self.failed = Some(e.clone());
        e
    }

    fn vec3(&self, i: usize) -> [f64; 3] {
        [self.x[i], self.x[i + 1], self.x[i + 2]]
    }

    /// Current states (positions and velocities as the model lays them out).
    pub fn state(&self) -> &[f64] {
        &self.x
    }
}

impl Drop for Dbsmc {
    fn drop(&mut self) {
        let _ = self.commands.send(Command::Stop);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Backend for Dbsmc {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn n_particles(&self) -> usize {
        self.n_particles
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if self.commands.send(Command::Advance(t)).is_err() {
            return Err(self.failure(self.t, "the simulating thread ended".into()));
        }
        self.await_frame()
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        for (k, p) in out.iter_mut().enumerate() {
            *p = self.vec3(self.slots[k].0);
        }
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        for (k, v) in out.iter_mut().enumerate() {
            *v = self.vec3(self.slots[k].1);
        }
    }
    fn particle(&self, k: usize) -> Kinematics {
        let (p, v) = self.slots[k];
        let still = Kinematics {
            pos: self.vec3(p),
            vel: self.vec3(v),
            ..Kinematics::default()
        };
        if self.commands.send(Command::Particle(k)).is_err() {
            return still;
        }
        match self.replies.recv() {
            Ok(Reply::Particle(k)) => k,
            _ => still,
        }
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        if k >= self.n_particles {
            return Err(self.failure(self.t, format!("particle {k} does not exist")));
        }
        if self.commands.send(Command::SetPin(k, pin)).is_err() {
            return Err(self.failure(self.t, "the simulating thread ended".into()));
        }
        match self.replies.recv() {
            Ok(Reply::Pinned(Ok(()))) => Ok(()),
            Ok(Reply::Pinned(Err(reason))) => Err(BackendError {
                method: self.name.clone(),
                t: self.t,
                reason,
            }),
            Ok(Reply::Failed { t, reason }) => Err(self.failure(t, reason)),
            _ => Err(self.failure(self.t, "the simulating thread ended".into())),
        }
    }
    fn counters(&self) -> Counters {
        self.counters
    }
}

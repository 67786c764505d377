//! The parts of a [`Simulator`](super::Simulator) besides the model, the settings and
//! the controller: where the integration stands, the buffers its steps work in, which
//! quantities are evaluated at the current point, and where a run in pieces stands.

use std::time::Instant;

/// The integration point: time, states, algebraic unknowns and the control with its
/// hold since the last update.
pub(super) struct Point {
    pub(super) t: f64,
    pub(super) x: Vec<f64>,
    pub(super) z: Vec<f64>,
    /// `z` and time at the last update: between updates `z = z_b + v (t - t_b)`.
    pub(super) zb: Vec<f64>,
    pub(super) tb: f64,
    pub(super) v: Vec<f64>,
    /// The rate of `v` between updates (a ramp against the drift): `v(t) = v + va (t -
    /// t_b)`; zero for the zero-order hold.
    pub(super) va: Vec<f64>,
    /// `v` on its ramp at the time last asked for (`Simulator::v_at`).
    pub(super) v_now: Vec<f64>,
    /// `f(t, x, z)` at the point, when [`Fresh::f`] says so (the next step's first
    /// stage).
    pub(super) f_cur: Vec<f64>,
}

impl Point {
    pub(super) fn new(n: usize, m: usize, t: f64) -> Self {
        Self {
            t,
            x: vec![0.0; n],
            z: vec![0.0; m],
            zb: vec![0.0; m],
            tb: t,
            v: vec![0.0; m],
            va: vec![0.0; m],
            v_now: vec![0.0; m],
            f_cur: vec![0.0; n],
        }
    }
}

/// Buffers of the steps, the samples and the model changes, allocated once.
pub(super) struct Scratch {
    pub(super) fx: Vec<f64>,
    /// The start of the current step, dense-output and stage scratch.
    pub(super) x0: Vec<f64>,
    pub(super) z0: Vec<f64>,
    pub(super) xs: Vec<f64>,
    pub(super) zs: Vec<f64>,
    /// SPSM stages of `z`.
    pub(super) kz: [Vec<f64>; 4],
    /// `z` at the end of a trial step, and `s` at its embedded solution (for the
    /// step's error in `s`).
    pub(super) z_trial: Vec<f64>,
    pub(super) s_embedded: Vec<f64>,
    /// The algebraic outputs and residuals of a sample.
    pub(super) z_eq: Vec<f64>,
    pub(super) z_star: Vec<f64>,
    pub(super) wres: Vec<f64>,
    /// `Omega` before a [`change_model`](super::Simulator::change_model).
    pub(super) omega_before: Vec<f64>,
}

impl Scratch {
    pub(super) fn new(n: usize, m: usize) -> Self {
        let vn = || vec![0.0; n];
        let vm = || vec![0.0; m];
        Self {
            fx: vn(),
            x0: vn(),
            z0: vm(),
            xs: vn(),
            zs: vm(),
            kz: [vm(), vm(), vm(), vm()],
            z_trial: vm(),
            s_embedded: vm(),
            z_eq: vm(),
            z_star: vm(),
            wres: vm(),
            omega_before: vm(),
        }
    }
}

/// Which quantities held by the simulator and its controller belong to the current
/// point. Moving the point or changing the model makes them stale; each is evaluated
/// again where it is needed, never read stale.
#[derive(Default)]
pub(super) struct Fresh {
    /// `Point::f_cur` is `f` at the point.
    pub(super) f: bool,
    /// The controller's `J_Omega` is the point's.
    pub(super) jacobian: bool,
    /// The controller's `beta` is the point's.
    pub(super) beta: bool,
    /// The model may have changed since the point was evaluated
    /// ([`model_mut`](super::Simulator::model_mut)): everything is evaluated again
    /// before the next step.
    pub(super) stale: bool,
}

/// Where a run in pieces stands.
pub(super) struct RunState {
    pub(super) phase: Phase,
    pub(super) clock: Option<Instant>,
    /// Fixed-step grid: steps `k` of `n` from `origin` to the piece's target.
    pub(super) origin: f64,
    pub(super) k: u64,
    pub(super) n: u64,
    pub(super) grid_target: f64,
    /// The embedded pairs' next step, once known; for the fixed-step integrators with
    /// located crossings, a limit below the user's step that the error in `s` set.
    pub(super) h_next: Option<f64>,
    /// The end of the last step was reached at a piece's target before `t_end`; its
    /// sample is recorded by the next piece (or `finish`, as the last one).
    pub(super) pending_record: bool,
    /// Step number of the last recorded sample.
    pub(super) recorded: Option<u64>,
    pub(super) update_requested: bool,
    /// The step just taken was cut at an event that asks for an update.
    pub(super) force_update: bool,
    /// Steps in a row that made almost no progress (the progress guard of `step`).
    pub(super) short_steps: u32,
    /// Steps in a row that made none to rounding (the progress guard of `step`).
    pub(super) tiny_steps: u32,
}

impl RunState {
    pub(super) fn new(phase: Phase, t0: f64) -> Self {
        Self {
            phase,
            clock: (phase == Phase::Running).then(Instant::now),
            origin: t0,
            k: 0,
            n: 0,
            grid_target: t0,
            h_next: None,
            pending_record: false,
            recorded: None,
            update_requested: false,
            force_update: false,
            short_steps: 0,
            tiny_steps: 0,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Phase {
    Idle,
    Running,
    Finished,
}

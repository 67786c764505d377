//! The scene runner: frames of 1/60 s through a [`Backend`], positions, strain, grabs.

use std::time::Instant;

use crate::backend::{Backend, BackendError};
use crate::motion::{GrabPath, Pin};
use crate::system::{Link, System, worst_strain};

/// The frame period of every scene (s).
pub const FRAME: f64 = 1.0 / 60.0;

/// Why a scene could not be set up or advanced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The backend failed.
    #[error(transparent)]
    Backend(#[from] BackendError),
    /// The backend simulates another number of particles than the system has.
    #[error("the backend has {backend} particles, the system {system}")]
    Particles {
        /// The backend's count.
        backend: usize,
        /// The system's count.
        system: usize,
    },
    /// A grab or release named a particle that does not exist.
    #[error("particle {particle} does not exist ({particles} particles)")]
    NoSuchParticle {
        /// The particle.
        particle: usize,
        /// The number of particles.
        particles: usize,
    },
    /// A grab's duration is not finite and positive.
    #[error("grab duration {0} must be finite and > 0")]
    Duration(f64),
}

/// What one frame did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Frame number (1 for the first frame advanced).
    pub index: u64,
    /// Simulation time at the end of the frame.
    pub t: f64,
    /// Wall-clock time the backend took for the frame (s).
    pub wall: f64,
    /// Largest relative strain `|L - L0| / L0` at the end of the frame.
    pub strain: f64,
    /// The link where it occurs.
    pub link: usize,
}

/// The worst strain of a run so far.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WorstStrain {
    /// Largest relative strain over all links and frames.
    pub strain: f64,
    /// The link.
    pub link: usize,
    /// The frame (0: the initial state).
    pub frame: u64,
}

/// A particle system advancing frame by frame through a [`Backend`].
///
/// Strain is measured at the end of every frame on every link of the system
/// (including links between two pinned particles).
#[derive(Debug)]
pub struct Scene<B: Backend> {
    backend: B,
    links: Vec<Link>,
    frame: u64,
    t0: f64,
    positions: Vec<[f64; 3]>,
    worst: WorstStrain,
}

impl<B: Backend> Scene<B> {
    /// A scene of `system` simulated by `backend` (built from the same system).
    pub fn new(system: &System, backend: B) -> Result<Self, SceneError> {
        if backend.n_particles() != system.n_particles() {
            return Err(SceneError::Particles {
                backend: backend.n_particles(),
                system: system.n_particles(),
            });
        }
        let mut positions = vec![[0.0; 3]; system.n_particles()];
        backend.positions(&mut positions);
        let (strain, link) = worst_strain(system.links(), &positions);
        Ok(Self {
            t0: backend.time(),
            backend,
            links: system.links().to_vec(),
            frame: 0,
            positions,
            worst: WorstStrain {
                strain,
                link,
                frame: 0,
            },
        })
    }

    /// Advance one frame of [`FRAME`] seconds.
    pub fn step(&mut self) -> Result<Frame, SceneError> {
        let index = self.frame + 1;
        let t = self.t0 + index as f64 * FRAME;
        let clock = Instant::now();
        self.backend.advance_to(t)?;
        let wall = clock.elapsed().as_secs_f64();
        self.frame = index;
        self.backend.positions(&mut self.positions);
        let (strain, link) = worst_strain(&self.links, &self.positions);
        // A NaN strain (a broken run) must win and stay.
        if !self.worst.strain.is_nan() && (strain.is_nan() || strain > self.worst.strain) {
            self.worst = WorstStrain {
                strain,
                link,
                frame: index,
            };
        }
        Ok(Frame {
            index,
            t,
            wall,
            strain,
            link,
        })
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        self.backend.time()
    }
    /// Frames advanced so far.
    pub fn frames(&self) -> u64 {
        self.frame
    }
    /// Positions at the end of the last frame.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    /// The system's links.
    pub fn links(&self) -> &[Link] {
        &self.links
    }
    /// The worst strain so far.
    pub fn worst_strain(&self) -> WorstStrain {
        self.worst
    }
    /// The backend.
    pub fn backend(&self) -> &B {
        &self.backend
    }
    /// The backend, mutably (e.g. to pin a particle to a motion of your own).
    pub fn backend_mut(&mut self) -> &mut B {
        &mut self.backend
    }

    fn check(&self, particle: usize) -> Result<(), SceneError> {
        let particles = self.positions.len();
        if particle < particles {
            Ok(())
        } else {
            Err(SceneError::NoSuchParticle {
                particle,
                particles,
            })
        }
    }

    /// Grab `particle` where it is and move it by `offset` over `duration` seconds on
    /// a [`GrabPath`] (continuous in position and velocity with the particle's own
    /// motion, three times differentiable, arriving at rest), then hold it. Returns the
    /// path.
    ///
    /// The hand takes the particle's position and velocity, not its acceleration: the
    /// acceleration jumps to the hand's (as it does at a release), and a backend keeps
    /// its constraints through that jump (DBSMC moves its tensions so that `s` does not
    /// jump: `Simulator::change_model`). Continuing the acceleration instead would
    /// extrapolate an instantaneous value, which the switching tensions of the sliding
    /// control make tens of g, over the whole move and fling the hand.
    pub fn grab(
        &mut self,
        particle: usize,
        offset: [f64; 3],
        duration: f64,
    ) -> Result<GrabPath, SceneError> {
        self.check(particle)?;
        if !(duration.is_finite() && duration > 0.0) {
            return Err(SceneError::Duration(duration));
        }
        let k = self.backend.particle(particle);
        let path = GrabPath {
            t0: self.backend.time(),
            p0: k.pos,
            v0: k.vel,
            a0: [0.0; 3],
            offset,
            duration,
        };
        self.backend.set_pin(particle, Some(Pin::moving(path)))?;
        Ok(path)
    }

    /// Release a grabbed (or pinned) particle: it moves freely from now on.
    pub fn release(&mut self, particle: usize) -> Result<(), SceneError> {
        self.check(particle)?;
        self.backend.set_pin(particle, None)?;
        Ok(())
    }
}

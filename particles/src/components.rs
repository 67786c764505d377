//! Parts of a system that no link joins, each simulated on a clock of its own.
//!
//! One simulator over a whole system makes every event pay for the whole system: a
//! sliding variable of any part that reaches its layer cuts the step of every particle
//! and updates every row, so each strand of the hair pays for the events of all the
//! others, and a step costs the whole head. Parts that no link
//! joins are independent DAEs: [`Components`] runs one backend per part, each with
//! its own steps and updates, which is the global method on each part exactly (the
//! guarantee of each part's layer is its own run's), and can advance the parts on
//! several threads.

use std::cell::RefCell;
use std::ops::Range;

use crate::backend::{Backend, BackendError, Counters, MuSearchCounters, SlidingCounters};
use crate::dbsmc::Dbsmc;
use crate::model::ParticleModel;
use crate::motion::{Kinematics, Pin};
use crate::system::{Edge, System, SystemError};

/// One part of a system ([`parts`]): its own [`System`] (particles renumbered from 0
/// in the order of the whole system's, links in the whole system's order), and where
/// its particles and links are in the whole system.
#[derive(Debug, Clone)]
pub struct Part {
    /// The part as a system of its own (with its pins, velocities and gravity).
    pub system: System,
    /// For each particle of the part, its index in the whole system.
    pub particles: Vec<usize>,
    /// For each link of the part, its index in the whole system.
    pub links: Vec<usize>,
}

impl Part {
    /// The whole of `system` as one part.
    pub fn whole(system: &System) -> Self {
        Part {
            system: system.clone(),
            particles: (0..system.n_particles()).collect(),
            links: (0..system.links().len()).collect(),
        }
    }
}

/// The parts of `system` that no link joins (a pinned particle joins the links at it,
/// since a release would couple them), in the order of their first particle. Particles
/// that belong to no part with a link between particles that are not both pinned (a
/// lone particle, a link between two pins) join the first part, so that every part has
/// a constraint; a system without any such link is one part.
///
/// Linear in the particles and links (a union-find with path halving).
pub fn parts(system: &System) -> Result<Vec<Part>, SystemError> {
    let n = system.n_particles();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut k: usize) -> usize {
        while root[k] != k {
            root[k] = root[root[k]];
            k = root[k];
        }
        k
    }
    for link in system.links() {
        let (a, b) = (find(&mut root, link.a), find(&mut root, link.b));
        if a != b {
            root[a.max(b)] = a.min(b);
        }
    }
    // A part is numbered when its first particle is met; parts without a constraint
    // (no link with a free end) go to part 0.
    let pins = system.pins();
    let mut constrained = vec![false; n];
    for link in system.links() {
        if pins[link.a].is_none() || pins[link.b].is_none() {
            let r = find(&mut root, link.a);
            constrained[r] = true;
        }
    }
    let mut number = vec![usize::MAX; n];
    let mut count = 0;
    for k in 0..n {
        let r = find(&mut root, k);
        if constrained[r] && number[r] == usize::MAX {
            number[r] = count;
            count += 1;
        }
    }
    let count = count.max(1);
    let part_of: Vec<usize> = (0..n)
        .map(|k| {
            let r = find(&mut root, k);
            if number[r] == usize::MAX {
                0
            } else {
                number[r]
            }
        })
        .collect();
    let mut particles = vec![Vec::new(); count];
    let mut local = vec![0; n];
    for (k, &p) in part_of.iter().enumerate() {
        local[k] = particles[p].len();
        particles[p].push(k);
    }
    let mut links = vec![Vec::new(); count];
    for (l, link) in system.links().iter().enumerate() {
        links[part_of[link.a]].push(l);
    }
    particles
        .into_iter()
        .zip(links)
        .map(|(particles, links)| {
            let edges: Vec<Edge> = links
                .iter()
                .map(|&l| {
                    let link = system.links()[l];
                    Edge {
                        a: local[link.a],
                        b: local[link.b],
                        rest: Some(link.rest),
                    }
                })
                .collect();
            let pick = |all: &[[f64; 3]]| particles.iter().map(|&k| all[k]).collect::<Vec<_>>();
            let masses = particles.iter().map(|&k| system.masses()[k]).collect();
            let mut sub = System::from_edges(pick(system.positions()), masses, &edges)?
                .with_velocities(pick(system.velocities()))?
                .with_gravity(system.gravity());
            for (i, &k) in particles.iter().enumerate() {
                if let Some(pin) = &pins[k] {
                    sub = sub.with_pin(i, pin.clone())?;
                }
            }
            Ok(Part {
                system: sub,
                particles,
                links,
            })
        })
        .collect()
}

/// A [`Backend`] made of one backend per part of a system ([`parts`]), each advanced
/// on its own clock: a part's events cut only its own steps and update only its own
/// rows. With [`threads`](Components::threads) above 1 the parts are advanced on that
/// many threads (each a run of parts with about the same number of links), with the
/// same results to the bit as on one.
///
/// What the parts did is summed in [`Backend::counters`] (the steps are the parts'
/// steps added up, each costing its own part's size), and
/// [`SlidingCounters::parts`] says how many there are. A part that fails stops the
/// frame with its error, which names the part and the system's particles in it.
pub struct Components<B> {
    backends: Vec<B>,
    particles: Vec<Vec<usize>>,
    /// For each particle of the system: its part and its index there.
    place: Vec<(usize, usize)>,
    threads: usize,
    /// Links per part, to share the parts out between threads.
    weights: Vec<usize>,
    scratch: RefCell<Vec<[f64; 3]>>,
}

impl<B: Backend + Send> std::fmt::Debug for Components<B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Components")
            .field("parts", &self.backends.len())
            .field("threads", &self.threads)
            .field("t", &self.time())
            .finish()
    }
}

impl<B: Backend + Send> Components<B> {
    /// One backend per part of `system`, each built by `build` from the [`Part`] (its
    /// own system, and where its particles and links are in the whole) and its index
    /// among the parts. An error names the part whose system or backend could not be
    /// built.
    pub fn new(
        system: &System,
        build: impl FnMut(&Part, usize) -> Result<B, BackendError>,
    ) -> Result<Self, BackendError> {
        let split = parts(system).map_err(|e| BackendError {
            method: "components".into(),
            t: 0.0,
            reason: format!("splitting the system into its parts: {e}"),
            deadline: false,
        })?;
        Self::of_parts(system.n_particles(), split, build)
    }

    /// The whole of `system` as one part, whatever joins it: for a model that can only
    /// be built for the whole system (a family model whose layout depends on the
    /// number of parts), with the counters and the seam of [`Components::new`].
    pub fn whole(
        system: &System,
        build: impl FnMut(&Part, usize) -> Result<B, BackendError>,
    ) -> Result<Self, BackendError> {
        Self::of_parts(system.n_particles(), vec![Part::whole(system)], build)
    }

    fn of_parts(
        n_particles: usize,
        split: Vec<Part>,
        mut build: impl FnMut(&Part, usize) -> Result<B, BackendError>,
    ) -> Result<Self, BackendError> {
        let count = split.len();
        let mut place = vec![(0, 0); n_particles];
        let mut backends = Vec::with_capacity(count);
        let mut particles = Vec::with_capacity(count);
        let mut weights = Vec::with_capacity(count);
        for (p, part) in split.into_iter().enumerate() {
            for (i, &k) in part.particles.iter().enumerate() {
                place[k] = (p, i);
            }
            let backend = build(&part, p).map_err(|e| in_part(e, p, count, &part.particles))?;
            backends.push(backend);
            weights.push(part.links.len());
            particles.push(part.particles);
        }
        let largest = particles.iter().map(Vec::len).max().unwrap_or(0);
        Ok(Self {
            backends,
            particles,
            place,
            threads: 1,
            weights,
            scratch: RefCell::new(vec![[0.0; 3]; largest]),
        })
    }

    /// Advance the parts on `threads` threads (1, the default, advances them in turn
    /// on the caller's; 0 is taken as 1).
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = threads.max(1);
        self
    }

    /// The parts' backends, in the order of [`parts`].
    pub fn backends(&self) -> &[B] {
        &self.backends
    }

    /// For each part, the indices of its particles in the whole system.
    pub fn particles(&self) -> &[Vec<usize>] {
        &self.particles
    }

    /// What `read` gives for each part's particles, at their places in `out`.
    fn scatter(&self, out: &mut [[f64; 3]], read: impl Fn(&B, &mut [[f64; 3]])) {
        let mut buf = self.scratch.borrow_mut();
        for (b, ks) in self.backends.iter().zip(&self.particles) {
            let part = &mut buf[..ks.len()];
            read(b, part);
            for (&k, v) in ks.iter().zip(part.iter()) {
                out[k] = *v;
            }
        }
    }

    /// Runs of parts with about equal numbers of links, one per thread.
    fn shares(&self) -> Vec<Range<usize>> {
        let threads = self.threads.min(self.backends.len()).max(1);
        let total: usize = self.weights.iter().sum::<usize>().max(1);
        let mut shares = Vec::with_capacity(threads);
        let (mut start, mut sum) = (0, 0);
        for (p, &w) in self.weights.iter().enumerate() {
            sum += w;
            if shares.len() + 1 < threads && sum * threads >= total * (shares.len() + 1) {
                shares.push(start..p + 1);
                start = p + 1;
            }
        }
        shares.push(start..self.weights.len());
        shares.retain(|r| !r.is_empty());
        shares
    }
}

impl Components<Dbsmc<ParticleModel>> {
    /// DBSMC on every part of `system`: the hand-written [`ParticleModel`] of each part
    /// and the frame-tied design of [`Dbsmc::online`] with every link within the
    /// relative layer `eps`; `name` labels reports. The way to simulate a system with
    /// DBSMC when one does not need a model or settings of one's own: a connected
    /// system is one part (the wrapper then costs a copy of the positions per read),
    /// and the hair's strands or the pieces of a scene each run on their own clock.
    pub fn online(system: &System, eps: f64, name: &str) -> Result<Self, BackendError> {
        Self::new(system, |part, _| {
            let model = ParticleModel::new(&part.system).map_err(|e| BackendError {
                method: name.to_string(),
                t: 0.0,
                reason: e.to_string(),
                deadline: false,
            })?;
            Dbsmc::online(model, eps, name)
        })
    }
}

/// Advance `backends` (parts `first..`) in turn to `t`; the first failure with its part.
fn advance_all<B: Backend>(
    backends: &mut [B],
    first: usize,
    t: f64,
) -> Option<(usize, BackendError)> {
    for (i, b) in backends.iter_mut().enumerate() {
        if b.time() < t {
            if let Err(e) = b.advance_to(t) {
                return Some((first + i, e));
            }
        }
    }
    None
}

/// `e` with the part it happened in (as it is when the system is one part).
fn in_part(mut e: BackendError, p: usize, count: usize, particles: &[usize]) -> BackendError {
    if count == 1 {
        return e;
    }
    let (first, last) = (particles[0], particles[particles.len() - 1]);
    let which = if last - first + 1 == particles.len() {
        format!("the system's particles {first} to {last}")
    } else {
        format!("{} of the system's particles from {first}", particles.len())
    };
    e.reason = format!(
        "{} (in part {p} of {count}, {which}; its particles and links are numbered within the part)",
        e.reason
    );
    e
}

impl<B: Backend + Send> Backend for Components<B> {
    fn name(&self) -> String {
        self.backends[0].name()
    }
    fn n_particles(&self) -> usize {
        self.place.len()
    }
    /// The earliest of the parts' times (all equal after a frame that every part
    /// finished).
    fn time(&self) -> f64 {
        self.backends
            .iter()
            .map(Backend::time)
            .fold(f64::INFINITY, f64::min)
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        let failed = if self.threads == 1 || self.backends.len() == 1 {
            advance_all(&mut self.backends, 0, t)
        } else {
            let shares = self.shares();
            let mut rest: &mut [B] = &mut self.backends;
            let mut runs = Vec::with_capacity(shares.len());
            for share in &shares {
                let (run, tail) = rest.split_at_mut(share.len());
                runs.push((share.start, run));
                rest = tail;
            }
            std::thread::scope(|scope| {
                let handles: Vec<_> = runs
                    .into_iter()
                    .map(|(first, run)| scope.spawn(move || advance_all(run, first, t)))
                    .collect();
                handles
                    .into_iter()
                    .filter_map(|h| h.join().expect("a part's thread panicked"))
                    .min_by_key(|(p, _)| *p)
            })
        };
        match failed {
            None => Ok(()),
            Some((p, e)) => Err(in_part(e, p, self.backends.len(), &self.particles[p])),
        }
    }
    fn set_deadline(&mut self, deadline: Option<std::time::Instant>) {
        for b in &mut self.backends {
            b.set_deadline(deadline);
        }
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        self.scatter(out, B::positions);
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        self.scatter(out, B::velocities);
    }
    fn particle(&self, k: usize) -> Kinematics {
        let (p, i) = self.place[k];
        self.backends[p].particle(i)
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        let Some(&(p, i)) = self.place.get(k) else {
            return Err(BackendError {
                method: self.name(),
                t: self.time(),
                reason: format!("particle {k} does not exist"),
                deadline: false,
            });
        };
        let count = self.backends.len();
        self.backends[p]
            .set_pin(i, pin)
            .map_err(|e| in_part(e, p, count, &self.particles[p]))
    }
    fn counters(&self) -> Counters {
        let mut all = Counters::default();
        let mut searches = Vec::new();
        let mut sliding: Option<SlidingCounters> = None;
        for c in self.backends.iter().map(Backend::counters) {
            all.steps += c.steps;
            all.f_evals += c.f_evals;
            all.factorisations += c.factorisations;
            all.iterations += c.iterations;
            let Some(d) = c.sliding else { continue };
            searches.push(d.mu_search);
            let Some(sum) = sliding.as_mut() else {
                sliding = Some(d);
                continue;
            };
            sum.updates += d.updates;
            sum.blocks = sum.blocks.zip(d.blocks).map(|(a, b)| crate::BlockCounters {
                blocks: a.blocks + b.blocks,
                block_solves: a.block_solves + b.block_solves,
                global_updates: a.global_updates + b.global_updates,
            });
            sum.steps_cut += d.steps_cut;
            sum.links_asking += d.links_asking;
            sum.layer_lost_at = match (sum.layer_lost_at, d.layer_lost_at) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            sum.layer_worst_ratio = match (sum.layer_worst_ratio, d.layer_worst_ratio) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            };
        }
        if let Some(sum) = sliding.as_mut() {
            sum.parts = self.backends.len() as u64;
            sum.mu_search = merged_searches(&searches);
        }
        all.sliding = sliding;
        all
    }
}

/// The parts' searches for `mu` as one: moves and refusals added up, the scale their
/// geometric mean; `None` unless every part searched.
fn merged_searches(searches: &[Option<MuSearchCounters>]) -> Option<MuSearchCounters> {
    let all: Option<Vec<MuSearchCounters>> = searches.iter().copied().collect();
    let all = all.filter(|a| !a.is_empty())?;
    let log_mean = all.iter().map(|s| s.scale.ln()).sum::<f64>() / all.len() as f64;
    Some(MuSearchCounters {
        scale: log_mean.exp(),
        moves: all.iter().map(|s| s.moves).sum(),
        refused: all.iter().map(|s| s.refused).sum(),
    })
}

//! Recording a run: the [`Sink`] trait, a Vec-backed [`Trace`], a streaming
//! [`CsvSink`], the [`Decimate`] adapter and the [`Tee`] that feeds two sinks.
//!
//! The simulator offers a sample after every step (and always the first and the last);
//! it asks [`Sink::wants`] first, so that `z_eq` (one solve with the update's factors)
//! and `z*` (one factorisation and solve at the sample) are only computed for samples
//! that are kept. Update times go through [`Sink::update`] and are never
//! decimated: there are few of them (except under SPSM, where every step is an update
//! and none are reported).

use std::io::{self, Write};

/// Names of the recorded quantities, handed to [`Sink::begin`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Layout {
    /// State names (`x`).
    pub states: Vec<String>,
    /// Algebraic unknown names (`z`, `z_eq` and `z_star`).
    pub algs: Vec<String>,
    /// Constraint names (`s` and `w`).
    pub constraints: Vec<String>,
}

impl Layout {
    /// CSV column names: `t`, then `x.<state>`, `z.<alg>`, `z_eq.<alg>`,
    /// `z_star.<alg>`, `s.<constraint>`, `w.<constraint>`.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec!["t".to_string()];
        c.extend(self.states.iter().map(|n| format!("x.{n}")));
        c.extend(self.algs.iter().map(|n| format!("z.{n}")));
        c.extend(self.algs.iter().map(|n| format!("z_eq.{n}")));
        c.extend(self.algs.iter().map(|n| format!("z_star.{n}")));
        c.extend(self.constraints.iter().map(|n| format!("s.{n}")));
        c.extend(self.constraints.iter().map(|n| format!("w.{n}")));
        c
    }
}

/// One recorded point of a run.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Step number (0 = initial point).
    pub step: u64,
    /// Time.
    pub t: f64,
    /// States.
    pub x: &'a [f64],
    /// Algebraic unknowns as integrated (zero-order hold ramps).
    pub z: &'a [f64],
    /// `z_eq = z - J_s^{-1} s(x, z)` with the factors of the last update: the algebraic
    /// values that put the state on `s = 0`. Empty when the sink declined the algebraic
    /// outputs ([`Sink::algebraic_outputs`]).
    pub z_eq: &'a [f64],
    /// `z* = z - J_Omega^{-1} Omega(t, x, z)` at this state: the algebraic values of the
    /// index-1 reduction (exact where `Omega` is affine in `z`). Empty when the sink
    /// declined the algebraic outputs.
    pub z_star: &'a [f64],
    /// Sliding variables.
    pub s: &'a [f64],
    /// Constraint residuals `w_i = g_i(t, x, z)`.
    pub w: &'a [f64],
    /// Whether this is the last sample of the run.
    pub last: bool,
}

/// Receives the recorded time series of a run.
pub trait Sink {
    /// Called once before the first sample.
    fn begin(&mut self, layout: &Layout) -> io::Result<()>;
    /// Whether the sample of this step should be recorded (decimation). The first and
    /// the last samples are recorded regardless.
    fn wants(&self, step: u64, t: f64) -> bool {
        let _ = (step, t);
        true
    }
    /// Whether the samples need `z_eq` and `z*` (one solve, and one factorisation of
    /// `J_Omega` at the sample); a sink that never reads them (e.g. a pilot estimator)
    /// returns `false` and then receives empty slices (unless another sink it is teed
    /// with asks for them).
    fn algebraic_outputs(&self) -> bool {
        true
    }
    /// Record one sample.
    fn record(&mut self, sample: &Sample<'_>) -> io::Result<()>;
    /// A control update happened at time `t`.
    fn update(&mut self, t: f64) -> io::Result<()>;
    /// Called once after the last sample of a successful run.
    fn finish(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A sink that records nothing (statistics only).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoTrace;

impl Sink for NoTrace {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        Ok(())
    }
    fn wants(&self, _: u64, _: f64) -> bool {
        false
    }
    fn algebraic_outputs(&self) -> bool {
        false
    }
    fn record(&mut self, _: &Sample<'_>) -> io::Result<()> {
        Ok(())
    }
    fn update(&mut self, _: f64) -> io::Result<()> {
        Ok(())
    }
}

/// In-memory trace: one row per recorded sample, plus all update times.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    layout: Layout,
    n: usize,
    m: usize,
    t: Vec<f64>,
    /// Row-major rows of `x, z, z_eq, z_star, s, w`.
    rows: Vec<f64>,
    updates: Vec<f64>,
}

impl Trace {
    /// An empty trace.
    pub fn new() -> Self {
        Self::default()
    }
    fn width(&self) -> usize {
        self.n + 5 * self.m
    }
    fn row(&self, i: usize) -> &[f64] {
        let w = self.width();
        &self.rows[i * w..(i + 1) * w]
    }
    /// Names of the recorded quantities.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// Number of recorded samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// Sample times.
    pub fn times(&self) -> &[f64] {
        &self.t
    }
    /// States of sample `i`.
    pub fn x(&self, i: usize) -> &[f64] {
        &self.row(i)[..self.n]
    }
    /// Algebraic unknowns of sample `i`.
    pub fn z(&self, i: usize) -> &[f64] {
        &self.row(i)[self.n..self.n + self.m]
    }
    /// `z_eq` of sample `i`.
    pub fn z_eq(&self, i: usize) -> &[f64] {
        &self.row(i)[self.n + self.m..self.n + 2 * self.m]
    }
    /// `z*` of sample `i`.
    pub fn z_star(&self, i: usize) -> &[f64] {
        &self.row(i)[self.n + 2 * self.m..self.n + 3 * self.m]
    }
    /// Sliding variables of sample `i`.
    pub fn s(&self, i: usize) -> &[f64] {
        &self.row(i)[self.n + 3 * self.m..self.n + 4 * self.m]
    }
    /// Constraint residuals of sample `i`.
    pub fn w(&self, i: usize) -> &[f64] {
        &self.row(i)[self.n + 4 * self.m..]
    }
    /// Times of all control updates.
    pub fn update_times(&self) -> &[f64] {
        &self.updates
    }
    /// Write the samples as CSV (header from [`Layout::columns`]).
    pub fn write_csv<W: Write>(&self, mut out: W) -> io::Result<()> {
        write_header(&mut out, &self.layout)?;
        for i in 0..self.len() {
            write_row(&mut out, self.t[i], self.row(i))?;
        }
        out.flush()
    }
    /// Write the update times as a one-column CSV (`t_update`).
    pub fn write_updates_csv<W: Write>(&self, mut out: W) -> io::Result<()> {
        writeln!(out, "t_update")?;
        for t in &self.updates {
            writeln!(out, "{t}")?;
        }
        out.flush()
    }
}

impl Sink for Trace {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.layout = layout.clone();
        self.n = layout.states.len();
        self.m = layout.algs.len();
        self.t.clear();
        self.rows.clear();
        self.updates.clear();
        Ok(())
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.t.push(s.t);
        for part in [s.x, s.z, s.z_eq, s.z_star, s.s, s.w] {
            self.rows.extend_from_slice(part);
        }
        Ok(())
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.updates.push(t);
        Ok(())
    }
}

fn write_header<W: Write>(out: &mut W, layout: &Layout) -> io::Result<()> {
    writeln!(out, "{}", layout.columns().join(","))
}

fn write_row<W: Write>(out: &mut W, t: f64, values: &[f64]) -> io::Result<()> {
    write!(out, "{t}")?;
    for v in values {
        write!(out, ",{v}")?;
    }
    writeln!(out)
}

/// Streams samples as CSV rows to a writer (wrap files in a `BufWriter`); keeps only the
/// update times in memory.
#[derive(Debug)]
pub struct CsvSink<W: Write> {
    out: W,
    updates: Vec<f64>,
}

impl<W: Write> CsvSink<W> {
    /// Stream to `out`.
    pub fn new(out: W) -> Self {
        Self {
            out,
            updates: Vec::new(),
        }
    }
    /// Times of all control updates so far.
    pub fn update_times(&self) -> &[f64] {
        &self.updates
    }
    /// Give back the writer (flush it first if it buffers).
    pub fn into_inner(self) -> W {
        self.out
    }
}

impl<W: Write> Sink for CsvSink<W> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.updates.clear();
        write_header(&mut self.out, layout)
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        write!(self.out, "{}", s.t)?;
        for part in [s.x, s.z, s.z_eq, s.z_star, s.s, s.w] {
            for v in part {
                write!(self.out, ",{v}")?;
            }
        }
        writeln!(self.out)?;
        if s.last {
            self.out.flush()?;
        }
        Ok(())
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.updates.push(t);
        Ok(())
    }
    fn finish(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

/// Keeps every `every`-th step's sample, and only if at least `min_spacing` has passed
/// since the last kept one; the first and last samples and all update times pass.
#[derive(Debug)]
pub struct Decimate<S> {
    inner: S,
    every: u64,
    min_spacing: f64,
    last_t: f64,
}

impl<S: Sink> Decimate<S> {
    /// Wrap `inner`, initially keeping every sample.
    pub fn new(inner: S) -> Self {
        Self {
            inner,
            every: 1,
            min_spacing: 0.0,
            last_t: f64::NEG_INFINITY,
        }
    }
    /// Keep only steps that are multiples of `k` (`k = 0` is treated as 1).
    pub fn every(mut self, k: u64) -> Self {
        self.every = k.max(1);
        self
    }
    /// Keep samples at least `dt` apart in time.
    pub fn min_spacing(mut self, dt: f64) -> Self {
        self.min_spacing = dt;
        self
    }
    /// The wrapped sink.
    pub fn inner(&self) -> &S {
        &self.inner
    }
    /// Unwrap.
    pub fn into_inner(self) -> S {
        self.inner
    }
}

impl<S: Sink> Sink for Decimate<S> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.last_t = f64::NEG_INFINITY;
        self.inner.begin(layout)
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        step % self.every == 0 && t - self.last_t >= self.min_spacing && self.inner.wants(step, t)
    }
    fn algebraic_outputs(&self) -> bool {
        self.inner.algebraic_outputs()
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.last_t = s.t;
        self.inner.record(s)
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.inner.update(t)
    }
    fn finish(&mut self) -> io::Result<()> {
        self.inner.finish()
    }
}

/// An absent sink records nothing; a present one records as itself. For a run whose
/// outputs are optional (a CSV file, charts), usually inside a [`Tee`].
impl<S: Sink> Sink for Option<S> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.as_mut().map_or(Ok(()), |s| s.begin(layout))
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        self.as_ref().is_some_and(|s| s.wants(step, t))
    }
    fn algebraic_outputs(&self) -> bool {
        self.as_ref().is_some_and(|s| s.algebraic_outputs())
    }
    fn record(&mut self, sample: &Sample<'_>) -> io::Result<()> {
        self.as_mut().map_or(Ok(()), |s| s.record(sample))
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.as_mut().map_or(Ok(()), |s| s.update(t))
    }
    fn finish(&mut self) -> io::Result<()> {
        self.as_mut().map_or(Ok(()), |s| s.finish())
    }
}

/// Two sinks fed the same run (`Tee(a, b)`). Each is asked [`Sink::wants`] on its own
/// and receives only the samples it wants (and, as always, the first and the last), so
/// each keeps its own decimation: a CSV of every step beside a thinned trace for charts,
/// say. Both see every update and `begin`/`finish`.
#[derive(Debug, Clone, Default)]
pub struct Tee<A, B>(pub A, pub B);

impl<A: Sink, B: Sink> Sink for Tee<A, B> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.0.begin(layout)?;
        self.1.begin(layout)
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        self.0.wants(step, t) || self.1.wants(step, t)
    }
    fn algebraic_outputs(&self) -> bool {
        self.0.algebraic_outputs() || self.1.algebraic_outputs()
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        // The simulator records the first sample (step 0), the last, and what `wants`.
        let always = s.step == 0 || s.last;
        if always || self.0.wants(s.step, s.t) {
            self.0.record(s)?;
        }
        if always || self.1.wants(s.step, s.t) {
            self.1.record(s)?;
        }
        Ok(())
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.0.update(t)?;
        self.1.update(t)
    }
    fn finish(&mut self) -> io::Result<()> {
        self.0.finish()?;
        self.1.finish()
    }
}

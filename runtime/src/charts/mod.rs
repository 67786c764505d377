//! SVG charts of simulation traces (feature `plot`).
//!
//! The functions take plain slices, not simulator types, so any trace can be drawn:
//!
//! * [`plot_sliding`]: sliding variables `s_i(t)`, one panel per constraint, with the
//!   layer `|s_i| <= eps_i` drawn as dashed lines;
//! * [`plot_periods`]: control update periods against update time, with the guaranteed
//!   `T_min` of the design as a horizontal line;
//! * [`plot_errors`]: constraint errors `|w_i|(t)`, linear or logarithmic axis;
//! * [`plot_run`]: all three for one run, from its [`Trace`](crate::Trace).
//!
//! Input is validated before anything is drawn: empty data, mismatched lengths, NaN or
//! infinite values and decreasing times are [`ChartError`]s. Long traces are thinned per
//! pixel column to the first, smallest, largest and last value, which keeps the drawn
//! envelope exact while the file stays small.

mod draw;
mod run;

use std::path::Path;

pub use run::{RunCharts, plot_run};

/// One constraint's sliding variable for [`plot_sliding`].
#[derive(Debug, Clone, Copy)]
pub struct SlidingSeries<'a> {
    /// Legend name (e.g. the constraint's name).
    pub name: &'a str,
    /// `s_i` at the common times.
    pub s: &'a [f64],
    /// Layer half-width `eps_i > 0`.
    pub eps: f64,
}

/// One constraint's error for [`plot_errors`]; its absolute value is drawn.
#[derive(Debug, Clone, Copy)]
pub struct ErrorSeries<'a> {
    /// Legend name.
    pub name: &'a str,
    /// `w_i` at the common times (signed; `|w_i|` is drawn).
    pub w: &'a [f64],
}

/// The y axis of [`plot_errors`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum YScale {
    /// Linear from 0.
    #[default]
    Linear,
    /// Logarithmic over at most 12 decades below the largest value; smaller values and
    /// zeros are drawn on the bottom edge.
    Log,
}

/// Why a chart could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// Nothing to draw.
    #[error("nothing to draw: {0}")]
    Empty(&'static str),
    /// A series does not have one value per time.
    #[error("series `{series}` has {got} values, expected {expected}")]
    LengthMismatch {
        /// The series name.
        series: String,
        /// Its length.
        got: usize,
        /// The number of times.
        expected: usize,
    },
    /// A NaN or infinite value.
    #[error("non-finite value {value} in `{series}` at index {index}")]
    NonFinite {
        /// The series name (`t` for the times).
        series: String,
        /// Position in the series.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Times must not decrease.
    #[error("`{series}` decreases at index {index}")]
    Decreasing {
        /// `t` or `update_times`.
        series: &'static str,
        /// Position of the first smaller value.
        index: usize,
    },
    /// A layer half-width or `T_min` is not finite and positive.
    #[error("{what} of `{series}` must be finite and positive, got {value}")]
    NotPositive {
        /// `eps` or `t_min`.
        what: &'static str,
        /// The series name.
        series: String,
        /// The value.
        value: f64,
    },
    /// plotters failed while drawing.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// The file could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The target path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// Draws `s_i(t)` of every series in its own panel, with dashed lines at `+-eps_i`, and
/// writes the SVG to `path`.
pub fn plot_sliding(
    path: impl AsRef<Path>,
    title: &str,
    t: &[f64],
    series: &[SlidingSeries<'_>],
) -> Result<(), ChartError> {
    check_times("t", t)?;
    if series.is_empty() {
        return Err(ChartError::Empty("no sliding series"));
    }
    for s in series {
        check_series(s.name, s.s, t.len())?;
        if !(s.eps.is_finite() && s.eps > 0.0) {
            return Err(ChartError::NotPositive {
                what: "eps",
                series: s.name.to_string(),
                value: s.eps,
            });
        }
    }
    write(path.as_ref(), draw::sliding(title, t, series)?)
}

/// Draws the control update periods `T_k = t_k - t_(k-1)` against the update times
/// `t_k` (so the first update has no period), with `t_min` as a horizontal line when
/// given, and writes the SVG to `path`. Needs at least two update times.
pub fn plot_periods(
    path: impl AsRef<Path>,
    title: &str,
    update_times: &[f64],
    t_min: Option<f64>,
) -> Result<(), ChartError> {
    check_times("update_times", update_times)?;
    if update_times.len() < 2 {
        return Err(ChartError::Empty("fewer than two update times, no period"));
    }
    if let Some(tm) = t_min {
        if !(tm.is_finite() && tm > 0.0) {
            return Err(ChartError::NotPositive {
                what: "t_min",
                series: "T_min".to_string(),
                value: tm,
            });
        }
    }
    write(path.as_ref(), draw::periods(title, update_times, t_min)?)
}

/// Draws `|w_i|(t)` of every series in one panel (one colour each) and writes the SVG
/// to `path`.
pub fn plot_errors(
    path: impl AsRef<Path>,
    title: &str,
    t: &[f64],
    series: &[ErrorSeries<'_>],
    scale: YScale,
) -> Result<(), ChartError> {
    check_times("t", t)?;
    if series.is_empty() {
        return Err(ChartError::Empty("no error series"));
    }
    for s in series {
        check_series(s.name, s.w, t.len())?;
    }
    write(path.as_ref(), draw::errors(title, t, series, scale)?)
}

fn write_dir(dir: &Path) -> Result<(), ChartError> {
    std::fs::create_dir_all(dir).map_err(|source| ChartError::Io {
        path: dir.display().to_string(),
        source,
    })
}

fn write(path: &Path, svg: String) -> Result<(), ChartError> {
    std::fs::write(path, svg).map_err(|source| ChartError::Io {
        path: path.display().to_string(),
        source,
    })
}

fn check_finite(name: &str, xs: &[f64]) -> Result<(), ChartError> {
    match xs.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(ChartError::NonFinite {
            series: name.to_string(),
            index,
            value: xs[index],
        }),
        None => Ok(()),
    }
}

fn check_times(name: &'static str, t: &[f64]) -> Result<(), ChartError> {
    if t.is_empty() {
        return Err(ChartError::Empty(name));
    }
    check_finite(name, t)?;
    match t.windows(2).position(|w| w[1] < w[0]) {
        Some(i) => Err(ChartError::Decreasing {
            series: name,
            index: i + 1,
        }),
        None => Ok(()),
    }
}

fn check_series(name: &str, ys: &[f64], expected: usize) -> Result<(), ChartError> {
    if ys.len() != expected {
        return Err(ChartError::LengthMismatch {
            series: name.to_string(),
            got: ys.len(),
            expected,
        });
    }
    check_finite(name, ys)
}

/// Thins `(t, y)` to at most four points per column of `columns` equal time bins
/// (first, smallest, largest, last, in time order); short series are returned whole.
fn thin(t: &[f64], y: impl Fn(usize) -> f64, columns: usize) -> Vec<(f64, f64)> {
    let n = t.len();
    if n <= 4 * columns {
        return (0..n).map(|i| (t[i], y(i))).collect();
    }
    let (t0, t1) = (t[0], t[n - 1]);
    let width = (t1 - t0) / columns as f64;
    let column = |x: f64| {
        if width > 0.0 {
            (((x - t0) / width) as usize).min(columns - 1)
        } else {
            0
        }
    };
    let mut out = Vec::with_capacity(4 * columns);
    let mut start = 0;
    while start < n {
        let c = column(t[start]);
        let mut end = start + 1;
        while end < n && column(t[end]) == c {
            end += 1;
        }
        let (mut lo, mut hi) = (start, start);
        for i in start..end {
            if y(i) < y(lo) {
                lo = i;
            }
            if y(i) > y(hi) {
                hi = i;
            }
        }
        let mut keep = [start, lo, hi, end - 1];
        keep.sort_unstable();
        let mut last = usize::MAX;
        for i in keep {
            if i != last {
                out.push((t[i], y(i)));
                last = i;
            }
        }
        start = end;
    }
    out
}

#[cfg(test)]
mod tests;

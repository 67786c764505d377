//! The charts of one run from its [`Trace`]: what `daec run --plot` and the chapter-5
//! example draw.

use std::path::{Path, PathBuf};

use super::{ChartError, ErrorSeries, SlidingSeries, YScale, plot_errors, plot_periods};
use super::{plot_sliding, write_dir};
use crate::Trace;

/// The files [`plot_run`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunCharts {
    /// `sliding.svg`: `s_i(t)` with the layers `+-eps_i`.
    pub sliding: PathBuf,
    /// `errors.svg`: `|w_i|(t)`, logarithmic axis.
    pub errors: PathBuf,
    /// `periods.svg`: the update periods with `T_min`; absent when the run made fewer than
    /// two updates (no period to draw).
    pub periods: Option<PathBuf>,
}

/// Draws the charts of a run into the folder `dir` (created if needed): the sliding
/// variables of every constraint with its layer `eps[i]`, the constraint errors, and the
/// update periods with the guaranteed `t_min` of the design when there is one. The
/// constraints are named as in the trace; `title` starts every chart's title (e.g. the
/// model's name).
pub fn plot_run(
    dir: &Path,
    title: &str,
    trace: &Trace,
    eps: &[f64],
    t_min: Option<f64>,
) -> Result<RunCharts, ChartError> {
    let names = &trace.layout().constraints;
    if eps.len() != names.len() {
        return Err(ChartError::LengthMismatch {
            series: "eps".into(),
            got: eps.len(),
            expected: names.len(),
        });
    }
    write_dir(dir)?;
    let t = trace.times();
    let column = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { (0..t.len()).map(f).collect() };
    let s: Vec<Vec<f64>> = (0..names.len())
        .map(|i| column(&|k| trace.s(k)[i]))
        .collect();
    let w: Vec<Vec<f64>> = (0..names.len())
        .map(|i| column(&|k| trace.w(k)[i]))
        .collect();
    let sliding: Vec<SlidingSeries<'_>> = names
        .iter()
        .enumerate()
        .map(|(i, name)| SlidingSeries {
            name,
            s: &s[i],
            eps: eps[i],
        })
        .collect();
    let errors: Vec<ErrorSeries<'_>> = names
        .iter()
        .enumerate()
        .map(|(i, name)| ErrorSeries { name, w: &w[i] })
        .collect();
    let charts = RunCharts {
        sliding: dir.join("sliding.svg"),
        errors: dir.join("errors.svg"),
        periods: (trace.update_times().len() >= 2).then(|| dir.join("periods.svg")),
    };
    plot_sliding(
        &charts.sliding,
        &format!("{title}: sliding variables s with +-eps"),
        t,
        &sliding,
    )?;
    plot_errors(
        &charts.errors,
        &format!("{title}: constraint errors |w|"),
        t,
        &errors,
        YScale::Log,
    )?;
    if let Some(path) = &charts.periods {
        let what = if t_min.is_some() {
            "update periods (line: guaranteed T_min)"
        } else {
            "update periods"
        };
        plot_periods(
            path,
            &format!("{title}: {what}"),
            trace.update_times(),
            t_min,
        )?;
    }
    Ok(charts)
}

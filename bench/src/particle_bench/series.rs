//! A method's settings on one scene as a series, cheapest first: the runs after one
//! that says nothing new about a costlier setting are not run.
//!
//! Only the series of a method without a bound (XPBD, the index-1 method) end early, after
//! a run that ran out of its wall-clock budget (a costlier setting would too, after fewer
//! frames, and a stopped run is the cheapest holding setting at no level) or that held
//! the tightest of [`STRAIN_LEVELS`] over its whole scene (a costlier setting would be the
//! cheapest at no level either). Every DBSMC setting runs: each eps is a bound to check,
//! over the frames its budget allows (a run of explicit Euler leaves its layer at one eps
//! and not at another).

use super::run::ParticleRecord;

/// The worst strains the tables ask the cheapest holding setting of (relative strain).
pub const STRAIN_LEVELS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// Why a series ends after `r` (the costlier settings are not run), or `None`.
pub fn ends_series(r: &ParticleRecord) -> Option<String> {
    let tightest = STRAIN_LEVELS[STRAIN_LEVELS.len() - 1];
    if r.eps.is_some() {
        None
    } else if r.status == "budget" {
        Some(format!(
            "{} ran out of its budget after {} of {} frames",
            r.knob, r.frames, r.frames_total
        ))
    } else if r.complete() && r.worst_strain <= tightest {
        Some(format!(
            "{} held worst strain {tightest:e} over the whole scene ({:.2e})",
            r.knob, r.worst_strain
        ))
    } else {
        None
    }
}

/// What a series left out: the settings not run and why.
#[derive(Clone, Debug, PartialEq)]
pub struct NotRun {
    /// The settings (knobs) not run, in their order.
    pub knobs: Vec<String>,
    /// What ended the series ([`ends_series`]).
    pub reason: String,
}

/// Run `settings` in order with `run` until one ends the series ([`ends_series`]): the
/// records of the settings run, and those left out (`knob` names a setting).
pub fn run_series<S>(
    settings: &[S],
    knob: impl Fn(&S) -> String,
    mut run: impl FnMut(&S) -> ParticleRecord,
) -> (Vec<ParticleRecord>, Option<NotRun>) {
    let mut records = Vec::with_capacity(settings.len());
    for (i, s) in settings.iter().enumerate() {
        let r = run(s);
        let reason = ends_series(&r);
        records.push(r);
        if let Some(reason) = reason {
            let knobs: Vec<String> = settings[i + 1..].iter().map(&knob).collect();
            let left = (!knobs.is_empty()).then_some(NotRun { knobs, reason });
            return (records, left);
        }
    }
    (records, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(knob: &str, eps: Option<f64>, status: &str, worst: f64) -> ParticleRecord {
        ParticleRecord {
            status: status.into(),
            frames: if status == "ok" { 300 } else { 20 },
            ..ParticleRecord::for_tests("xpbd-substeps", knob, eps, worst)
        }
    }

    /// Runs `outcomes` as a series over knobs `0, 1, ...`; returns the knobs run and
    /// what was left out.
    fn series(outcomes: &[(Option<f64>, &str, f64)]) -> (Vec<String>, Option<NotRun>) {
        let knobs: Vec<usize> = (0..outcomes.len()).collect();
        let (records, left) = run_series(
            &knobs,
            |k| k.to_string(),
            |&k| {
                let (eps, status, worst) = outcomes[k];
                rec(&k.to_string(), eps, status, worst)
            },
        );
        (records.into_iter().map(|r| r.knob).collect(), left)
    }

    #[test]
    fn a_series_ends_after_a_run_out_of_its_budget() {
        let (run, left) = series(&[
            (None, "ok", 0.5),
            (None, "budget", 0.2),
            (None, "ok", 0.0),
            (None, "ok", 0.0),
        ]);
        assert_eq!(run, ["0", "1"]);
        let left = left.expect("two settings left out");
        assert_eq!(left.knobs, ["2", "3"]);
        assert!(
            left.reason
                .contains("1 ran out of its budget after 20 of 300 frames")
        );
    }

    #[test]
    fn an_unbounded_method_ends_once_it_held_the_tightest_level_whole() {
        // 2e-4 holds 1e-3 but not 1e-4: the series goes on.
        let (run, left) = series(&[(None, "ok", 2e-4), (None, "ok", 1e-4), (None, "ok", 1e-6)]);
        assert_eq!(run, ["0", "1"]);
        assert_eq!(left.expect("one left out").knobs, ["2"]);
    }

    #[test]
    fn a_bounded_or_failed_run_does_not_end_a_series() {
        // DBSMC holding a tight strain, or out of its budget: the next eps is a bound to
        // check all the same.
        let (run, left) = series(&[
            (Some(1e-2), "ok", 1e-5),
            (Some(1e-3), "budget", 1e-4),
            (None, "failed: diverged", f64::NAN),
            (Some(1e-4), "ok", 1e-5),
        ]);
        assert_eq!(run, ["0", "1", "2", "3"]);
        assert_eq!(left, None);
    }

    #[test]
    fn the_last_setting_ending_its_series_leaves_nothing_out() {
        let (run, left) = series(&[(None, "ok", 0.1), (None, "budget", 0.1)]);
        assert_eq!(run, ["0", "1"]);
        assert_eq!(left, None);
    }
}

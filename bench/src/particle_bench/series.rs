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

/// Whether `r` held worst strain `level` over its whole scene (a complete run).
pub(super) fn held_whole(r: &ParticleRecord, level: f64) -> bool {
    r.complete() && r.worst_strain <= level
}

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
    } else if held_whole(r, tightest) {
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

/// Between two settings of a series `k_fail < k_hold` (whole numbers: XPBD's substeps),
/// the settings that bisection runs to find the least `k` whose run holds worst strain
/// `level` over its whole scene, until the bracket is within a sixteenth of its lower
/// end: `run(k)` makes the run of `k`; the runs made, in their order.
///
/// A grid of `k` by 2x can put the cheapest holding setting up to 2x too high; the
/// bisection brings that within about 6 %. It assumes a larger `k` holds what a smaller
/// one holds, but claims nothing from it: every run it makes is a row, and the tables take
/// the cheapest run that held.
pub fn bisect_least_holding(
    k_fail: u32,
    k_hold: u32,
    level: f64,
    mut run: impl FnMut(u32) -> ParticleRecord,
) -> Vec<ParticleRecord> {
    let (mut lo, mut hi) = (k_fail, k_hold);
    let mut made = Vec::new();
    while hi - lo > 1 && (hi - lo) * 16 > lo {
        let mid = lo + (hi - lo) / 2;
        let r = run(mid);
        let held = held_whole(&r, level);
        made.push(r);
        if held {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    made
}

/// For each of [`STRAIN_LEVELS`], the pair `(k_fail, k_hold)` of a series' complete runs
/// (knobs `k=N`) that bisection ([`bisect_least_holding`]) would search between: the
/// least `k` that held the level whole, and the largest `k` below it that ran whole
/// without holding it. Levels without both are left out.
pub fn holding_brackets(runs: &[ParticleRecord]) -> Vec<(f64, u32, u32)> {
    let ks: Vec<(u32, &ParticleRecord)> = runs
        .iter()
        .filter(|r| r.complete())
        .filter_map(|r| Some((r.knob.strip_prefix("k=")?.parse().ok()?, r)))
        .collect();
    STRAIN_LEVELS
        .iter()
        .filter_map(|&level| {
            let hold = ks
                .iter()
                .filter(|(_, r)| r.worst_strain <= level)
                .map(|&(k, _)| k)
                .min()?;
            let fail = ks
                .iter()
                .filter(|&&(k, r)| k < hold && r.worst_strain > level)
                .map(|&(k, _)| k)
                .max()?;
            Some((level, fail, hold))
        })
        .collect()
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

    #[test]
    fn bisection_finds_the_least_holding_k_within_a_sixteenth() {
        // Worst strain 1 / k: k >= 1000 holds 1e-3; the grid had 512 (fails), 1024.
        let mut asked = Vec::new();
        let made = bisect_least_holding(512, 1024, 1e-3, |k| {
            asked.push(k);
            rec(&format!("k={k}"), None, "ok", 1.0 / k as f64)
        });
        assert_eq!(made.len(), asked.len());
        // The least holding k among the runs made and the grid's 1024.
        let least = made
            .iter()
            .filter(|r| r.worst_strain <= 1e-3)
            .map(|r| r.knob.trim_start_matches("k=").parse::<u32>().unwrap())
            .fold(1024, u32::min);
        assert!(
            (1000..=1000 + 1000 / 16).contains(&least),
            "{least}, asked {asked:?}"
        );
        assert!(asked.iter().all(|&k| k > 512 && k < 1024), "{asked:?}");
        // A run stopped by its budget holds nothing: the bracket moves up.
        let made =
            bisect_least_holding(8, 16, 1e-3, |k| rec(&format!("k={k}"), None, "budget", 0.0));
        assert!(made.iter().all(|r| r.status == "budget"));
        assert_eq!(made.last().map(|r| r.knob.as_str()), Some("k=15"));
    }

    #[test]
    fn brackets_pair_the_least_holding_k_with_the_largest_failing_one_below() {
        let runs = [
            rec("k=256", None, "ok", 3e-3),
            rec("k=512", None, "ok", 8e-4),
            rec("k=1024", None, "budget", 1e-5),
            rec("k=2048", None, "ok", 9e-5),
        ];
        assert_eq!(
            holding_brackets(&runs),
            vec![(1e-3, 256, 512), (1e-4, 512, 2048)],
            "1e-2 held at the smallest k has no failing k below it"
        );
    }
}

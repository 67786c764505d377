//! The text form of a [`Summary`]: a few lines whatever the size of the model.
//!
//! A family model with 10^5 constraints must not print 10^5 lines: per-constraint
//! values are given as is up to [`TEXT_LINES_MAX`] of them and as a range beyond, and
//! the constraints listed one per line are the [`TEXT_LINES_MAX`] with the largest
//! `max |s| / eps`, found by a selection (linear in the number of constraints).

use std::fmt;

use super::Summary;

/// Most constraints listed one per line (and most values printed as a list) in the
/// text of a [`Summary`].
pub const TEXT_LINES_MAX: usize = 16;

/// Most constraints named in the line saying which asked for the updates.
const TRIGGER_NAMES_MAX: usize = 5;

/// Of `0..m`, all up to [`TEXT_LINES_MAX`], else the [`TEXT_LINES_MAX`] with the
/// largest `key`, in increasing order (a selection, linear in `m`).
///
/// ```
/// use dae_runtime::summary::{TEXT_LINES_MAX, listed_by};
///
/// assert_eq!(listed_by(3, |i| i as f64), vec![0, 1, 2]);
/// let listed = listed_by(1000, |i| -(i as f64));
/// assert_eq!(listed, (0..TEXT_LINES_MAX).collect::<Vec<_>>());
/// ```
pub fn listed_by(m: usize, key: impl Fn(usize) -> f64) -> Vec<usize> {
    if m <= TEXT_LINES_MAX {
        return (0..m).collect();
    }
    let mut order: Vec<usize> = (0..m).collect();
    order.select_nth_unstable_by(TEXT_LINES_MAX - 1, |&a, &b| key(b).total_cmp(&key(a)));
    order.truncate(TEXT_LINES_MAX);
    order.sort_unstable();
    order
}

/// A list of values (one per constraint or state) for a line of text: as is up to
/// [`TEXT_LINES_MAX`] values; longer, `0.05 (all 1000)` when every value is the same,
/// else its range.
///
/// ```
/// use dae_runtime::summary::values_text;
///
/// assert_eq!(values_text(&[0.5, 2.0]), "[0.5, 2.0]");
/// assert_eq!(values_text(&[0.05; 1000]), "0.05 (all 1000)");
/// let ramp: Vec<f64> = (0..100).map(f64::from).collect();
/// assert_eq!(values_text(&ramp), "0 .. 99 (100 values)");
/// ```
pub fn values_text(v: &[f64]) -> String {
    match v {
        _ if v.len() <= TEXT_LINES_MAX => format!("{v:?}"),
        [first, ..] if v.iter().all(|x| x == first) => format!("{first} (all {})", v.len()),
        _ => {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            format!("{lo} .. {hi} ({} values)", v.len())
        }
    }
}

/// The line saying which constraints asked for the monitored updates
/// ([`Summary::triggered_updates`]): how many of them did, and the ones that asked
/// most, with their counts (a selection, linear in their number). `None` when none did.
fn triggered_text(counts: &[u64], names: &[String]) -> Option<String> {
    let mut asked: Vec<usize> = (0..counts.len()).filter(|&i| counts[i] > 0).collect();
    if asked.is_empty() {
        return None;
    }
    let of = asked.len();
    let by_count = |a: &usize, b: &usize| counts[*b].cmp(&counts[*a]).then(a.cmp(b));
    if asked.len() > TRIGGER_NAMES_MAX {
        asked.select_nth_unstable_by(TRIGGER_NAMES_MAX - 1, by_count);
        asked.truncate(TRIGGER_NAMES_MAX);
    }
    asked.sort_unstable_by(by_count);
    let name = |i: usize| names.get(i).map_or("?", String::as_str);
    let most: Vec<String> = asked
        .iter()
        .map(|&i| format!("{} ({})", name(i), counts[i]))
        .collect();
    let most = if of > asked.len() {
        format!("most by {}", most.join(", "))
    } else {
        format!("by {}", most.join(", "))
    };
    Some(format!(
        "  updates asked for by {of} of {} constraints, {most}",
        counts.len()
    ))
}

/// `v[i]`, or NaN where `v` is shorter (a summary deserialised from an older form).
fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// The text `daec run` prints for a run: the steps, updates and evaluations; when the
/// layers were reached and from when the statistics count; the update periods; which
/// constraints asked for the updates; per constraint its largest `|s|` (also as a
/// multiple of its `eps`) and `|w|`; the final `z`, `z_eq` and `z*` (the final `x`
/// without constraints); the solver's counters; the wall time.
///
/// One line per constraint up to [`TEXT_LINES_MAX`] constraints; beyond, only the
/// [`TEXT_LINES_MAX`] with the largest `max |s| / eps` are listed and value lists are
/// given as ranges, so that the text stays a few dozen lines for any model. Lines after
/// the first are indented by two spaces; there is no newline after the last.
///
/// ```
/// # #[cfg(feature = "macros")] {
/// use dae_runtime::{Settings, Simulator, dae, trace::NoTrace};
///
/// dae! {
///     model Pendulum {
///         param m = 1.0, L = 1.0, g = 9.81;
///         state x = 1.0, y = 0.0, vx = 0.0, vy = 0.0;
///         alg z = 0.0;
///         let l = sqrt(x^2 + y^2);
///         der(x) = vx;
///         der(y) = vy;
///         der(vx) = -z * x / (m * l);
///         der(vy) = -z * y / (m * l) - g;
///         constraint rod: l = L;
///     }
/// }
///
/// let settings = Settings::new(vec![1e-3], vec![0.05], vec![50.0])
///     .step(1e-4)
///     .t_end(0.5);
/// let summary = Simulator::new(Pendulum::default(), settings)?.run(&mut NoTrace)?;
/// let text = summary.to_string();
/// assert!(text.starts_with("model Pendulum to t = 0.5: "));
/// assert!(text.contains("\n  rod: max |s| = "));
/// assert!(text.contains("\n  solver dense: "));
/// assert!(text.lines().last().unwrap().starts_with("  wall time "));
/// # }
/// # Ok::<(), dae_runtime::SimError>(())
/// ```
impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self;
        let m = s.constraints.len();
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.6}"));
        write!(
            f,
            "model {} to t = {}: {} steps ({} rejected, {} cut at a crossing), {} updates ({} while reaching), {} f evaluations ({:.1} per update)",
            s.model,
            s.t_end,
            s.steps,
            s.rejected_steps,
            s.located_crossings,
            s.updates,
            s.reaching_updates,
            s.f_evals,
            s.f_evals as f64 / s.updates.max(1) as f64
        )?;
        if let Some(b) = s.blocks {
            write!(
                f,
                "\n  updates by blocks ({} blocks of at most {} constraints): {} block solves, {} updates of every row",
                b.blocks, b.largest, b.block_solves, b.global_updates
            )?;
        }
        if let Some(a) = s.mu_search {
            write!(
                f,
                "\n  mu searched for over {} frames: {} moves ({} refused, {} down at a surge of the work), mu at the end {} times the start's",
                a.frames, a.moves, a.refused, a.surges, a.scale
            )?;
        }
        if s.unlocated_steps > 0 {
            write!(
                f,
                "\n  {} steps taken whole by the progress guard (no progress in the steps before them): crossings were not located inside them",
                s.unlocated_steps
            )?;
        }
        if m == 0 {
            write!(f, "\n  no constraints: integrated as an ODE")?;
        }
        let window = match (s.reaching_time, s.stats_from) {
            _ if m == 0 => "none (no constraints)".to_string(),
            (None, _) => "not reached".to_string(),
            (Some(r), None) => format!(
                "reached at {r:.6}; statistics window not entered (the settle time reaches past the end)"
            ),
            (Some(r), Some(from)) => format!("reached at {r:.6}, statistics from {from:.6}"),
        };
        write!(f, "\n  layers {window}")?;
        write!(
            f,
            "\n  update period min {}, average {}",
            opt(s.min_period),
            opt(s.mean_period)
        )?;
        if let Some(line) = triggered_text(&s.triggered_updates, &s.constraints) {
            write!(f, "\n{line}")?;
        }
        let max_s = s.max_abs_s.as_ref().unwrap_or(&s.seen_max_abs_s);
        let listed = listed_by(m, |i| at(max_s, i) / at(&s.eps, i));
        if listed.len() < m {
            write!(
                f,
                "\n  {m} constraints; the {} with the largest max |s| / eps:",
                listed.len()
            )?;
        }
        for (i, c) in listed.iter().map(|&i| (i, &s.constraints[i])) {
            match (&s.max_abs_s, &s.max_abs_w) {
                (Some(ms), Some(mw)) => write!(
                    f,
                    "\n  {c}: max |s| = {:.6} ({:.4} eps), max |w| = {:.6}",
                    at(ms, i),
                    at(ms, i) / at(&s.eps, i),
                    at(mw, i)
                )?,
                _ => write!(
                    f,
                    "\n  {c}: no statistics (window not entered); seen max |s| = {:.6}, max |w| = {:.6}; at the end s = {:.6}, w = {:.6}",
                    at(&s.seen_max_abs_s, i),
                    at(&s.seen_max_abs_w, i),
                    at(&s.s, i),
                    at(&s.w, i)
                )?,
            }
        }
        if m == 0 {
            write!(f, "\n  final x = {}", values_text(&s.x))?;
        } else {
            write!(
                f,
                "\n  final z = {}, z_eq = {}, z* = {}",
                values_text(&s.z),
                values_text(&s.z_eq),
                values_text(&s.z_star)
            )?;
            write!(
                f,
                "\n  solver {}: {} factorisations, {} solves, {} iterations, {} robustness failures",
                s.solver.name,
                s.solver.factorisations,
                s.solver.solves,
                s.solver.iterations,
                s.robustness_violations
                    .map_or("unchecked".to_string(), |v| v.to_string())
            )?;
            if s.solver.set_aside > 0 {
                write!(
                    f,
                    "\n  J_s singular at {} of them: the constraints the others imply set aside (at most {})",
                    s.solver.set_aside, s.solver.set_aside_max
                )?;
            }
        }
        write!(f, "\n  wall time {:.3} s", s.wall_time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trigger_line_names_the_constraints_that_asked_most() {
        let names: Vec<String> = (0..8).map(|i| format!("c{i}")).collect();
        assert_eq!(triggered_text(&[0; 8], &names), None);
        let counts = [0, 3, 0, 9, 1, 9, 2, 4];
        assert_eq!(
            triggered_text(&counts, &names).unwrap(),
            "  updates asked for by 6 of 8 constraints, most by c3 (9), c5 (9), c7 (4), c1 (3), c6 (2)"
        );
        assert_eq!(
            triggered_text(&[0, 2, 0, 5], &names[..4]).unwrap(),
            "  updates asked for by 2 of 4 constraints, by c3 (5), c1 (2)"
        );
    }

    #[test]
    fn listed_by_keeps_the_largest_keys_in_order() {
        let key = |i: usize| if i % 100 == 7 { 10.0 + i as f64 } else { 0.0 };
        let listed = listed_by(10_000, key);
        assert_eq!(listed.len(), TEXT_LINES_MAX);
        let expected: Vec<usize> = (0..100)
            .map(|k| 100 * k + 7)
            .skip(100 - TEXT_LINES_MAX)
            .collect();
        assert_eq!(listed, expected);
    }
}

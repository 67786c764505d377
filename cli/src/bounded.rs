//! Output of `daec run` that stays bounded for large models: a family model with 10^5
//! constraints must not print 10^5 summary lines, a JSON of megabytes, or a CSV trace of
//! gigabytes.

use dae_runtime::Model;
use serde_json::{Value, json};

/// Longest array printed as is in the JSON summary; longer ones are summarised.
pub(crate) const JSON_LIST_MAX: usize = 256;

/// Most constraints listed one per line in the text summary.
pub(crate) const TEXT_LINES_MAX: usize = 16;

/// Most values (rows times columns) written to `--csv` (and kept for `--plot`): about
/// 250 MB of CSV at most.
pub(crate) const TRACE_VALUES_MAX: u64 = 10_000_000;

/// Every how many steps a trace row is kept: at most `max_rows` rows, and at most
/// [`TRACE_VALUES_MAX`] values for the model's columns.
pub(crate) fn trace_every(model: &dyn Model, steps: u64, max_rows: u64) -> u64 {
    let (n, m) = (model.n_states() as u64, model.n_constraints() as u64);
    let columns = 1 + n + 4 * m;
    let rows = max_rows.min((TRACE_VALUES_MAX / columns).max(2));
    steps.div_ceil(rows).max(1)
}

/// Replaces every array longer than [`JSON_LIST_MAX`] inside `v` by a summary: numbers
/// by `{count, min, max, max_at, max_at_name}` (the name of the constraint or state at
/// the largest value, when the array is one per constraint or state), names by
/// `{count, first, last}`. Adds `"summarised": true` at the top when it did.
pub(crate) fn summarise(v: &mut Value, model: &dyn Model) {
    let mut any = false;
    walk(v, model, &mut any);
    if any {
        if let Value::Object(o) = v {
            o.insert("summarised".into(), json!(true));
            o.insert(
                "summarised_note".into(),
                json!(format!(
                    "arrays longer than {JSON_LIST_MAX} are given as count, min, max and where the max is; --csv records every value"
                )),
            );
        }
    }
}

fn walk(v: &mut Value, model: &dyn Model, any: &mut bool) {
    match v {
        Value::Object(o) => {
            for (_, x) in o.iter_mut() {
                walk(x, model, any);
            }
        }
        Value::Array(a) if a.len() > JSON_LIST_MAX => {
            *any = true;
            *v = summary_of(a, model);
        }
        Value::Array(a) => {
            for x in a {
                walk(x, model, any);
            }
        }
        _ => {}
    }
}

fn summary_of(a: &[Value], model: &dyn Model) -> Value {
    let n = a.len();
    if a.iter().all(|x| x.is_string()) {
        return json!({"count": n, "first": a[0], "last": a[n - 1]});
    }
    let nums: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
    if nums.len() != n {
        return json!({"count": n});
    }
    let (mut lo, mut hi, mut at) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    for (i, &x) in nums.iter().enumerate() {
        lo = lo.min(x);
        if x > hi {
            hi = x;
            at = i;
        }
    }
    let name = if n == model.n_constraints() {
        Some(model.constraint_name(at))
    } else if n == model.n_states() {
        Some(model.state_name(at))
    } else {
        None
    };
    json!({"count": n, "min": lo, "max": hi, "max_at": at, "max_at_name": name})
}

/// The constraints listed in the text summary: all of them up to [`TEXT_LINES_MAX`],
/// else the ones with the largest `max |s| / eps`, in constraint order.
pub(crate) fn listed_constraints(max_abs_s: &[f64], eps: &[f64]) -> Vec<usize> {
    listed_by(max_abs_s.len(), |i| max_abs_s[i] / eps[i])
}

/// Of `0..m`, all up to [`TEXT_LINES_MAX`], else the ones with the largest `key`, in
/// order (a selection, `O(m)`).
pub(crate) fn listed_by(m: usize, key: impl Fn(usize) -> f64) -> Vec<usize> {
    if m <= TEXT_LINES_MAX {
        return (0..m).collect();
    }
    let mut order: Vec<usize> = (0..m).collect();
    order.select_nth_unstable_by(TEXT_LINES_MAX - 1, |&a, &b| key(b).total_cmp(&key(a)));
    order.truncate(TEXT_LINES_MAX);
    order.sort_unstable();
    order
}

/// A list of per-constraint values for the text summary: as is up to
/// [`TEXT_LINES_MAX`] values; longer, `0.05 (all 1000)` when every value is the same,
/// else its range.
pub(crate) fn values_text(v: &[f64]) -> String {
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

/// Most constraints named in the line saying which asked for the updates.
pub(crate) const TRIGGER_NAMES_MAX: usize = 5;

/// The line of the text summary saying which constraints asked for the monitored
/// updates (`Summary::triggered_updates`): how many of them did, and the ones that
/// asked most, with their counts (a selection, `O(m)`). `None` when none did.
pub(crate) fn triggered_text(counts: &[u64], names: &[String]) -> Option<String> {
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
    let most: Vec<String> = asked
        .iter()
        .map(|&i| format!("{} ({})", names[i], counts[i]))
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
    use dae_runtime::family::{FamilyInstance, Interpreter, Spec};

    #[test]
    fn the_trace_of_a_large_model_keeps_at_most_the_value_budget() {
        let src = include_str!("../../examples/models/chain.dae");
        let c = dae_lang::compile_source(src).unwrap().remove(0);
        let spec = Spec {
            sizes: vec![("N".into(), 3000)],
            ..Spec::default()
        };
        let chain = FamilyInstance::interpreted(Interpreter::new(c).unwrap(), &spec).unwrap();
        let columns = 1 + 6 * 3001 + 4 * 3000;
        for steps in [10, 1_000, 1_000_000] {
            let every = trace_every(&chain, steps, 200_000);
            let rows = steps.div_ceil(every);
            assert!(rows * columns <= TRACE_VALUES_MAX, "{steps}: every {every}");
            // Not thinner than needed.
            assert!(every == 1 || (steps.div_ceil(every - 1)) * columns > TRACE_VALUES_MAX);
        }
        // A small model keeps the row limit.
        assert_eq!(trace_every(&chain, 10, 200_000), 1);
    }
}

//! Output of `daec run` that stays bounded for large models: a family model with 10^5
//! constraints must not print a JSON of megabytes or a CSV trace of gigabytes (the text
//! summary is kept short by `dae_runtime::Summary`'s `Display`).

use dae_runtime::Model;
use serde_json::{Value, json};

/// Longest array printed as is in the JSON summary; longer ones are summarised.
pub(crate) const JSON_LIST_MAX: usize = 256;

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

#[cfg(test)]
mod tests {
    use super::*;

    use dae_runtime::family::{FamilyInstance, Interpreter, Spec};

    #[test]
    fn the_trace_of_a_large_model_keeps_at_most_the_value_budget() {
        let src = include_str!("../../examples/models/chain.dae");
        let c = dae_lang::compile_source(src).unwrap().remove(0);
        let spec = Spec {
            sizes: vec![("N".into(), 3000)],
            ..Spec::default()
        };
        let chain = FamilyInstance::interpreted(Interpreter::new(c), &spec).unwrap();
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

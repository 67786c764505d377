//! `particles.csv` (one row per run) and the tables of docs/particles.md: the cheapest
//! setting of each method holding a strain, the fitted cost exponents, stability.

use std::fmt::Write as _;
use std::io::{self, Write};

use super::run::ParticleRecord;

/// The CSV's columns, in order (the first eight are the ones issue 13 asks for).
pub const CSV_COLUMNS: [&str; 24] = [
    "scene",
    "size",
    "method",
    "knob",
    "eps",
    "worst_strain",
    "ms_per_frame_mean",
    "ms_per_frame_max",
    "variant",
    "param",
    "frames",
    "frames_total",
    "status",
    "bound_held",
    "steps",
    "f_evals",
    "factorisations",
    "iterations",
    "updates",
    "pos_err_1s",
    "energy_drift",
    "dbsmc_t_min",
    "s_layer_lost_at",
    "s_layer_worst_ratio",
];

fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}
fn opt(v: Option<f64>) -> String {
    v.map(num).unwrap_or_default()
}
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Whether a DBSMC run kept `|L - L0| <= 1.05 eps L0` on every link and frame it ran
/// (`None` for methods without a bound).
pub fn bound_held(r: &ParticleRecord) -> Option<bool> {
    r.eps.map(|e| r.worst_strain <= 1.05 * e)
}

/// Write the records as CSV with [`CSV_COLUMNS`].
pub fn write_particles_csv<W: Write>(records: &[ParticleRecord], mut out: W) -> io::Result<()> {
    writeln!(out, "{}", CSV_COLUMNS.join(","))?;
    for r in records {
        let fields = [
            r.scene.clone(),
            r.size.to_string(),
            r.method.clone(),
            r.knob.clone(),
            opt(r.eps),
            num(r.worst_strain),
            num(r.ms_mean),
            num(r.ms_max),
            r.variant.clone(),
            num(r.param),
            r.frames.to_string(),
            r.frames_total.to_string(),
            r.status.clone(),
            bound_held(r).map(|b| b.to_string()).unwrap_or_default(),
            r.counters.steps.to_string(),
            r.counters.f_evals.to_string(),
            r.counters.factorisations.to_string(),
            r.counters.iterations.to_string(),
            r.counters.updates.to_string(),
            opt(r.pos_err),
            opt(r.energy_drift),
            opt(r.t_min),
            opt(r.counters.layer_lost_at),
            opt(r.counters.layer_worst_ratio),
        ];
        let line: Vec<String> = fields.iter().map(|f| quote(f)).collect();
        writeln!(out, "{}", line.join(","))?;
    }
    Ok(())
}

/// The cheapest complete run (lowest mean cost per frame) of `method` on the scene
/// `title` whose worst strain is at most `target` and which kept its guarantee: a DBSMC
/// run that left its `s`-layer is not counted, even where its strain happened to stay
/// small (its design no longer covered the run).
pub fn cheapest<'a>(
    records: &'a [ParticleRecord],
    title: &str,
    method: &str,
    target: f64,
) -> Option<&'a ParticleRecord> {
    records
        .iter()
        .filter(|r| format!("{} {}", r.scene, r.variant) == title && r.method == method)
        .filter(|r| r.complete() && r.worst_strain <= target)
        .filter(|r| r.counters.layer_lost_at.is_none())
        .min_by(|a, b| a.ms_mean.total_cmp(&b.ms_mean))
}

/// Least-squares slope of `ln y` against `ln x` (the fitted exponent), `None` with
/// fewer than two points.
pub fn fitted_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if p.len() < 2 {
        return None;
    }
    let n = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1).sum::<f64>() / n,
    );
    let sxx: f64 = p.iter().map(|q| (q.0 - mx) * (q.0 - mx)).sum();
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Markdown table: for every scene and method, the cheapest setting holding worst
/// strain 1e-2, 1e-3 and 1e-4 for the whole run, with its mean cost per frame.
pub fn cheapest_table(records: &[ParticleRecord], methods: &[String]) -> String {
    let mut titles: Vec<String> = Vec::new();
    for r in records {
        let t = format!("{} {}", r.scene, r.variant);
        if !titles.contains(&t) {
            titles.push(t);
        }
    }
    let mut s = String::from(
        "| scene | method | worst strain <= 1e-2 | <= 1e-3 | <= 1e-4 |\n|---|---|---|---|---|\n",
    );
    for t in &titles {
        for m in methods {
            if !records
                .iter()
                .any(|r| &format!("{} {}", r.scene, r.variant) == t && &r.method == m)
            {
                continue;
            }
            let cell = |target: f64| match cheapest(records, t, m, target) {
                Some(r) => format!("{} ({:.3} ms)", r.knob, r.ms_mean),
                None => "none".into(),
            };
            let _ = writeln!(
                s,
                "| {t} | {m} | {} | {} | {} |",
                cell(1e-2),
                cell(1e-3),
                cell(1e-4)
            );
        }
    }
    s
}

/// Markdown table: per scene and method, how many runs completed, stopped at the
/// budget, failed, and (DBSMC) lost the bound, with the first failure.
pub fn stability_table(records: &[ParticleRecord]) -> String {
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in records {
        let k = (format!("{} {}", r.scene, r.variant), r.method.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let mut s = String::from(
        "| scene | method | runs | complete | budget | failed | strain bound lost (> 1.05 eps) | s-layer left | first failure |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for (t, m) in keys {
        let runs: Vec<&ParticleRecord> = records
            .iter()
            .filter(|r| format!("{} {}", r.scene, r.variant) == t && r.method == m)
            .collect();
        let count = |f: &dyn Fn(&ParticleRecord) -> bool| runs.iter().filter(|r| f(r)).count();
        let failed: Vec<&&ParticleRecord> = runs
            .iter()
            .filter(|r| r.status.starts_with("failed"))
            .collect();
        let lost = count(&|r| bound_held(r) == Some(false));
        let bounded = runs.iter().any(|r| r.eps.is_some());
        let first = failed
            .first()
            .map(|r| {
                format!(
                    "{}: {}",
                    r.knob,
                    r.status.trim_start_matches("failed: ").replace('|', "/")
                )
            })
            .unwrap_or_default();
        let first: String = first.chars().take(140).collect();
        let _ = writeln!(
            s,
            "| {t} | {m} | {} | {} | {} | {} | {} | {} | {first} |",
            runs.len(),
            count(&|r| r.complete()),
            count(&|r| r.status == "budget"),
            failed.len(),
            if bounded {
                lost.to_string()
            } else {
                "-".into()
            },
            if bounded {
                count(&|r| r.counters.layer_lost_at.is_some()).to_string()
            } else {
                "-".into()
            },
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use dae_particles::Counters;

    fn rec(
        method: &str,
        knob: &str,
        eps: Option<f64>,
        strain: f64,
        ms: f64,
        status: &str,
    ) -> ParticleRecord {
        ParticleRecord {
            scene: "C1".into(),
            variant: "N=10 r=1".into(),
            size: 10,
            param: 1.0,
            method: method.into(),
            knob: knob.into(),
            eps,
            worst_strain: strain,
            ms_mean: ms,
            ms_max: 2.0 * ms,
            frames: 300,
            frames_total: 300,
            status: status.into(),
            counters: Counters::default(),
            pos_err: None,
            energy_drift: Some(-0.5),
            t_min: None,
            step: None,
        }
    }

    #[test]
    fn csv_has_the_required_columns_first_and_one_row_per_run() {
        let records = vec![
            rec("dbsmc", "eps=1e-3", Some(1e-3), 9e-4, 0.5, "ok"),
            rec(
                "xpbd-substeps",
                "k=16",
                None,
                6e-3,
                0.01,
                "failed: x, \"y\"",
            ),
        ];
        let mut out = Vec::new();
        write_particles_csv(&records, &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with(
            "scene,size,method,knob,eps,worst_strain,ms_per_frame_mean,ms_per_frame_max,"
        ));
        let head: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(head.len(), CSV_COLUMNS.len());
        assert!(lines[1].starts_with("C1,10,dbsmc,eps=1e-3,1e-3,9e-4,5e-1,1e0,"));
        assert!(lines[1].contains(",ok,true,"));
        // Methods without a bound leave eps and bound_held empty; quoting keeps commas.
        assert!(lines[2].starts_with("C1,10,xpbd-substeps,k=16,,6e-3,"));
        assert!(lines[2].contains("\"failed: x, \"\"y\"\"\",,"));
    }

    #[test]
    fn cheapest_picks_the_lowest_cost_complete_run_under_the_target() {
        let records = vec![
            rec("m", "a", None, 1e-3, 5.0, "ok"),
            rec("m", "b", None, 5e-4, 3.0, "ok"),
            rec("m", "c", None, 1e-4, 1.0, "budget"),
            rec("m", "d", None, 2e-3, 0.5, "ok"),
        ];
        assert_eq!(
            cheapest(&records, "C1 N=10 r=1", "m", 1e-3).unwrap().knob,
            "b"
        );
        assert!(cheapest(&records, "C1 N=10 r=1", "m", 1e-4).is_none());
        // A run that left its s-layer holds nothing, whatever its strain.
        let mut lost = rec("m", "e", None, 1e-4, 0.1, "ok");
        lost.counters.layer_lost_at = Some(0.5);
        let records = [records, vec![lost]].concat();
        assert_eq!(
            cheapest(&records, "C1 N=10 r=1", "m", 1e-3).unwrap().knob,
            "b"
        );
    }

    #[test]
    fn the_fitted_exponent_of_a_power_law_is_its_power() {
        let p: Vec<(f64, f64)> = [10.0, 100.0, 1000.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(1.2)))
            .collect();
        assert!((fitted_exponent(&p).unwrap() - 1.2).abs() < 1e-12);
        assert!(fitted_exponent(&p[..1]).is_none());
    }
}

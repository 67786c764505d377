//! `particles.csv` (one row per run) and the tables of docs/particles.md: the cheapest
//! setting of each method holding a strain, the fitted cost exponents, stability.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::{self, Write};

use dae_particles::MuSearchCounters;

use super::run::ParticleRecord;
use super::series::{STRAIN_LEVELS, held_whole};

/// The CSV's columns, in order (the first eight are the ones issue 13 asks for).
pub const CSV_COLUMNS: [&str; 29] = [
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
    "links_asking",
    "timings",
    "mu_scale",
    "mu_moves",
    "mu_refused",
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
/// (`None` for methods without a bound, and for a run that failed before its first
/// frame: it measured no strain, so it neither held nor lost the bound).
pub fn bound_held(r: &ParticleRecord) -> Option<bool> {
    if r.frames == 0 {
        return None;
    }
    r.eps.map(|e| r.worst_strain <= 1.05 * e)
}

/// Whether a DBSMC run kept both its guarantees over the frames it ran: the strain
/// within 1.05 eps ([`bound_held`]) and every `s_i` within its layer.
pub fn kept_both(r: &ParticleRecord) -> bool {
    bound_held(r) == Some(true) && r.counters.layer_lost_at().is_none()
}

/// Whether a run lost a guarantee: it left an `s`-layer, or a frame it ran broke the
/// strain bound. A run that ran no frame lost nothing (nor kept anything).
pub fn left_a_guarantee(r: &ParticleRecord) -> bool {
    bound_held(r) == Some(false) || r.counters.layer_lost_at().is_some()
}

/// A count of the search for `mu`, for the runs that searched (empty otherwise).
fn searched(r: &ParticleRecord, count: impl Fn(MuSearchCounters) -> u64) -> String {
    r.counters
        .mu_search()
        .map_or_else(String::new, |m| count(m).to_string())
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
            r.counters.updates().to_string(),
            opt(r.pos_err),
            opt(r.energy_drift),
            opt(r.t_min),
            opt(r.counters.layer_lost_at()),
            opt(r.counters.layer_worst_ratio()),
            if r.method.starts_with("dbsmc") {
                r.counters.links_asking().to_string()
            } else {
                String::new()
            },
            r.timings.to_string(),
            opt(r.counters.mu_search().map(|m| m.scale)),
            searched(r, |m| m.moves),
            searched(r, |m| m.refused),
        ];
        let line: Vec<String> = fields.iter().map(|f| quote(f)).collect();
        writeln!(out, "{}", line.join(","))?;
    }
    Ok(())
}

/// The rows of a CSV `text` as [`write_particles_csv`] writes it (fields quoted where
/// they hold a comma, a quote or a line break; `""` a quote within).
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let (mut row, mut field) = (Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, text.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, '\r') => {}
            (false, c) => field.push(c),
        }
    }
    if !field.is_empty() || !row.is_empty() {
        row.push(field);
        rows.push(row);
    }
    rows
}

/// The records of a benchmark CSV `text` ([`write_particles_csv`]) as far as the tables
/// and the pictures' choices read them: the scene, the method and its setting, the
/// strain, the cost, the frames, the status and the `s`-layer (the other counters are
/// zero, the accuracy and energy `None`). An error names a missing column or a row of
/// the wrong length.
pub fn records_from_csv(text: &str) -> Result<Vec<ParticleRecord>, String> {
    let rows = csv_rows(text);
    let Some((head, rows)) = rows.split_first() else {
        return Ok(Vec::new());
    };
    let col = |name: &str| {
        head.iter()
            .position(|h| h == name)
            .ok_or(format!("no column `{name}`"))
    };
    // The columns read, by name: the twelve that lead the CSV, then three more.
    let mut first = [0usize; 12];
    for (at, name) in first.iter_mut().zip(&CSV_COLUMNS) {
        *at = col(name)?;
    }
    let [
        scene,
        size,
        method,
        knob,
        eps,
        worst,
        ms,
        ms_max,
        variant,
        param,
        frames,
        total,
    ] = first;
    let (status, lost, ratio) = (
        col("status")?,
        col("s_layer_lost_at")?,
        col("s_layer_worst_ratio")?,
    );
    let opt = |f: &str| f.parse::<f64>().ok();
    let num = |f: &str| opt(f).unwrap_or(f64::NAN);
    rows.iter()
        .enumerate()
        .filter(|(_, r)| !(r.len() == 1 && r[0].is_empty()))
        .map(|(i, r)| {
            if r.len() != head.len() {
                return Err(format!(
                    "row {}: {} fields, not {}",
                    i + 2,
                    r.len(),
                    head.len()
                ));
            }
            let sliding = r[method]
                .starts_with("dbsmc")
                .then(|| dae_particles::SlidingCounters {
                    layer_lost_at: opt(&r[lost]),
                    layer_worst_ratio: opt(&r[ratio]),
                    ..Default::default()
                });
            Ok(ParticleRecord {
                scene: r[scene].clone(),
                variant: r[variant].clone(),
                size: r[size].parse().unwrap_or(0),
                param: num(&r[param]),
                method: r[method].clone(),
                knob: r[knob].clone(),
                eps: opt(&r[eps]),
                worst_strain: num(&r[worst]),
                ms_mean: num(&r[ms]),
                ms_max: num(&r[ms_max]),
                frames: r[frames].parse().unwrap_or(0),
                frames_total: r[total].parse().unwrap_or(0),
                status: r[status].clone(),
                counters: dae_particles::Counters {
                    sliding,
                    ..Default::default()
                },
                ..ParticleRecord::default()
            })
        })
        .collect()
}

/// The records grouped by `key`, groups in order of first appearance, in one pass (a
/// benchmark writes hundreds of rows; a scan of all rows per group would be quadratic).
pub(super) fn grouped<'a, K: std::hash::Hash + Eq + Clone>(
    records: impl IntoIterator<Item = &'a ParticleRecord>,
    key: impl Fn(&ParticleRecord) -> K,
) -> Vec<(K, Vec<&'a ParticleRecord>)> {
    let mut index: HashMap<K, usize> = HashMap::new();
    let mut groups: Vec<(K, Vec<&ParticleRecord>)> = Vec::new();
    for r in records {
        let k = key(r);
        let g = *index.entry(k.clone()).or_insert_with(|| {
            groups.push((k, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(r);
    }
    groups
}

/// The records grouped by scene title ([`scene_title`]), scenes in order of first
/// appearance, in one pass.
pub fn scene_groups(records: &[ParticleRecord]) -> Vec<(String, Vec<&ParticleRecord>)> {
    grouped(records, scene_title)
}

/// The scene title of a record (`C1 N=10 r=1e4`): the key of the tables and charts.
pub fn scene_title(r: &ParticleRecord) -> String {
    format!("{} {}", r.scene, r.variant)
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
    cheapest_of(
        records
            .iter()
            .filter(|r| scene_title(r) == title && r.method == method),
        target,
    )
}

/// [`cheapest`] among `runs` (already one scene and method).
pub(super) fn cheapest_of<'a>(
    runs: impl Iterator<Item = &'a ParticleRecord>,
    target: f64,
) -> Option<&'a ParticleRecord> {
    cheapest_kept(runs, |r| held_whole(r, target))
}

/// Where no run holds `target` over the whole scene: the cheapest run that held it (and
/// its `s`-layer) over the frames its budget allowed. A large scene's table cell then says
/// "not known over the whole scene" rather than "none held".
fn cheapest_until_budget<'a>(
    runs: impl Iterator<Item = &'a ParticleRecord>,
    target: f64,
) -> Option<&'a ParticleRecord> {
    cheapest_kept(runs, |r| {
        r.status == "budget" && r.frames > 0 && r.worst_strain <= target
    })
}

/// The cheapest of `runs` that `held` and kept its `s`-layer (a run that left it holds
/// nothing).
fn cheapest_kept<'a>(
    runs: impl Iterator<Item = &'a ParticleRecord>,
    held: impl Fn(&ParticleRecord) -> bool,
) -> Option<&'a ParticleRecord> {
    runs.filter(|r| held(r) && r.counters.layer_lost_at().is_none())
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
    let mut s = String::from(
        "| scene | method | worst strain <= 1e-2 | <= 1e-3 | <= 1e-4 |\n|---|---|---|---|---|\n",
    );
    for (t, runs) in scene_groups(records) {
        let by_method = grouped(runs, |r| r.method.clone());
        for m in methods {
            let Some((_, runs)) = by_method.iter().find(|(k, _)| k == m) else {
                continue;
            };
            let cell = |target: f64| {
                if let Some(r) = cheapest_of(runs.iter().copied(), target) {
                    format!("{} ({:.3} ms)", r.knob, r.ms_mean)
                } else if let Some(r) = cheapest_until_budget(runs.iter().copied(), target) {
                    format!(
                        "not whole: {} held it over the first {} of {} frames ({:.3} ms)",
                        r.knob, r.frames, r.frames_total, r.ms_mean
                    )
                } else {
                    "none".into()
                }
            };
            let [a, b, c] = STRAIN_LEVELS.map(cell);
            let _ = writeln!(s, "| {t} | {m} | {a} | {b} | {c} |");
        }
    }
    s
}

/// Markdown table: per scene and method, how many runs completed, stopped at the
/// budget, failed, and (DBSMC) lost the bound, with the first failure.
pub fn stability_table(records: &[ParticleRecord]) -> String {
    let groups = grouped(records, |r| (scene_title(r), r.method.clone()));
    let mut s = String::from(
        "| scene | method | runs | complete | budget | failed | strain bound lost (> 1.05 eps) | s-layer left | first failure |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for ((t, m), runs) in groups {
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
                count(&|r| r.counters.layer_lost_at().is_some()).to_string()
            } else {
                "-".into()
            },
        );
    }
    s
}

/// Markdown table: every DBSMC run (all designs, scenes in order of first appearance)
/// with its worst strain over the frames it ran, whether it kept the strain bound and
/// its `s`-layer, its cost and the counts that explain the cost: control updates and
/// steps per frame, and how many links asked for updates.
pub fn dbsmc_runs_table(records: &[ParticleRecord]) -> String {
    let mut s = String::from(
        "| scene | links | method | setting | worst strain (frames) | strain bound held | s-layer left at (max \\|s\\|/eps) | ms / frame mean (max) | updates / frame | steps / frame | links asking | status |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (t, runs) in scene_groups(records) {
        for r in runs.iter().filter(|r| r.method.starts_with("dbsmc")) {
            let per_frame = |n: u64| n as f64 / r.frames.max(1) as f64;
            let layer = r.counters.layer_lost_at().map_or("-".into(), |at| {
                format!(
                    "t = {at:.3} s ({:.3})",
                    r.counters.layer_worst_ratio().unwrap_or(f64::NAN)
                )
            });
            let held = match bound_held(r) {
                Some(true) => "yes",
                Some(false) => "**no**",
                None => "-",
            };
            let status: String = r.status.replace('|', "/").chars().take(80).collect();
            let _ = writeln!(
                s,
                "| {t} | {} | {} | {} | {:.2e} ({}) | {held} | {layer} | {:.3} ({:.3}) | {:.0} | {:.0} | {} | {status} |",
                r.size,
                r.method,
                r.knob,
                r.worst_strain,
                r.frames,
                r.ms_mean,
                r.ms_max,
                per_frame(r.counters.updates()),
                per_frame(r.counters.steps),
                r.counters.links_asking(),
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(
        method: &str,
        knob: &str,
        eps: Option<f64>,
        strain: f64,
        ms: f64,
        status: &str,
    ) -> ParticleRecord {
        ParticleRecord {
            ms_mean: ms,
            ms_max: 2.0 * ms,
            status: status.into(),
            energy_drift: Some(-0.5),
            ..ParticleRecord::for_tests(method, knob, eps, strain)
        }
    }

    #[test]
    fn the_records_are_read_back_from_the_csv() {
        let mut lost = rec("dbsmc-ramp", "eps=1e-2 c=4", Some(1e-2), 5e-3, 0.5, "ok");
        lost.counters.sliding = Some(dae_particles::SlidingCounters {
            layer_lost_at: Some(1.5),
            layer_worst_ratio: Some(1.2),
            ..Default::default()
        });
        let records = vec![
            rec("xpbd-coloured", "k=64", None, 2e-2, 1.0, "ok"),
            rec("xpbd-coloured", "k=256", None, 8e-3, 4.0, "ok"),
            rec("xpbd-coloured", "k=128", None, 5e-3, 2.0, "budget"),
            rec("xpbd-coloured", "k=512", None, 2e-3, 8.0, "ok"),
            rec(
                "vbd",
                "k=4",
                None,
                9e-3,
                3.0,
                "failed: a, \"quoted\"\nstatus",
            ),
            lost,
        ];
        let mut csv = Vec::new();
        write_particles_csv(&records, &mut csv).unwrap();
        let csv = String::from_utf8(csv).unwrap();
        let back = records_from_csv(&csv).unwrap();
        assert_eq!(back.len(), records.len());
        assert_eq!(back[4].status, "failed: a, \"quoted\"\nstatus");
        assert_eq!(back[5].counters.layer_lost_at(), Some(1.5));
        assert!(back[4].counters.sliding.is_none());
        let title = "C1 N=10 r=1";
        let knob = |m: &str, level: f64| cheapest(&back, title, m, level).map(|r| r.knob.as_str());
        assert_eq!(knob("xpbd-coloured", 1e-2), Some("k=256"));
        assert_eq!(knob("xpbd-coloured", 4e-3), Some("k=512"));
        assert_eq!(knob("xpbd-coloured", 1e-3), None);
        assert_eq!(knob("vbd", 1e-2), None);
        // A run that left its s-layer holds nothing.
        assert_eq!(knob("dbsmc-ramp", 1e-2), None);
        assert!(cheapest(&back, "C1 N=100 r=1", "xpbd-coloured", 1e-2).is_none());
        assert!(records_from_csv("scene,size\nC1,10\n").is_err());
    }

    #[test]
    fn csv_has_the_required_columns_first_and_one_row_per_run() {
        let mut searched = rec("dbsmc-adapt", "eps=1e-3", Some(1e-3), 9e-4, 0.5, "ok");
        searched.counters.sliding.get_or_insert_default().mu_search = Some(MuSearchCounters {
            scale: 0.25,
            moves: 5,
            refused: 1,
        });
        let records = vec![
            rec("dbsmc", "eps=1e-3", Some(1e-3), 9e-4, 0.5, "ok"),
            searched,
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
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with(
            "scene,size,method,knob,eps,worst_strain,ms_per_frame_mean,ms_per_frame_max,"
        ));
        let head: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(head.len(), CSV_COLUMNS.len());
        assert!(lines[1].starts_with("C1,10,dbsmc,eps=1e-3,1e-3,9e-4,5e-1,1e0,"));
        assert!(lines[1].contains(",ok,true,"));
        // The search for mu: where it ended, its moves and refusals; empty without one.
        assert!(lines[1].ends_with(",,,"), "{}", lines[1]);
        assert!(lines[2].ends_with(",2.5e-1,5,1"), "{}", lines[2]);
        // Methods without a bound leave eps and bound_held empty; quoting keeps commas.
        assert!(lines[3].starts_with("C1,10,xpbd-substeps,k=16,,6e-3,"));
        assert!(lines[3].contains("\"failed: x, \"\"y\"\"\",,"));
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
        lost.counters.sliding.get_or_insert_default().layer_lost_at = Some(0.5);
        let records = [records, vec![lost]].concat();
        assert_eq!(
            cheapest(&records, "C1 N=10 r=1", "m", 1e-3).unwrap().knob,
            "b"
        );
    }

    #[test]
    fn tables_list_scenes_and_methods_in_order_of_first_appearance_with_their_own_runs() {
        let on = |variant: &str, r: ParticleRecord| ParticleRecord {
            variant: variant.into(),
            ..r
        };
        // Interleaved scenes and methods, as a benchmark with resumed sweeps writes them.
        let records = vec![
            on("N=100 r=1", rec("b", "k=1", None, 1e-3, 2.0, "ok")),
            on("N=10 r=1", rec("a", "k=1", None, 1e-3, 4.0, "ok")),
            on("N=100 r=1", rec("a", "k=2", None, 5e-4, 3.0, "failed: x")),
            on("N=10 r=1", rec("a", "k=2", None, 1e-4, 1.0, "ok")),
        ];
        let rows =
            |t: String| -> Vec<String> { t.lines().skip(2).map(|l| l.to_string()).collect() };
        let stability = rows(stability_table(&records));
        assert_eq!(stability.len(), 3, "{stability:?}");
        assert!(stability[0].starts_with("| C1 N=100 r=1 | b | 1 | 1 | 0 | 0 |"));
        assert!(stability[1].starts_with("| C1 N=10 r=1 | a | 2 | 2 | 0 | 0 |"));
        assert!(stability[2].starts_with("| C1 N=100 r=1 | a | 1 | 0 | 0 | 1 |"));
        let cheapest = rows(cheapest_table(&records, &["a".into(), "b".into()]));
        assert_eq!(
            cheapest,
            [
                "| C1 N=100 r=1 | a | none | none | none |",
                "| C1 N=100 r=1 | b | k=1 (2.000 ms) | k=1 (2.000 ms) | none |",
                "| C1 N=10 r=1 | a | k=2 (1.000 ms) | k=2 (1.000 ms) | k=2 (1.000 ms) |",
            ]
        );
    }

    #[test]
    fn a_cell_without_a_whole_run_names_the_cheapest_run_that_held_until_its_budget() {
        let stopped = |knob: &str, strain: f64, ms: f64, frames: u64| ParticleRecord {
            frames,
            ..rec("m", knob, None, strain, ms, "budget")
        };
        let mut lost = stopped("lost", 1e-5, 0.1, 40);
        lost.counters.sliding.get_or_insert_default().layer_lost_at = Some(0.2);
        let records = vec![
            // Complete, but holds only 1e-2.
            rec("m", "whole", None, 5e-3, 9.0, "ok"),
            // Stopped by the budget: the cheaper one holds 1e-3 over 12 frames, the
            // costlier one 1e-4 over 8; one that left its layer holds nothing.
            stopped("k=1", 5e-4, 3.0, 12),
            stopped("k=2", 5e-5, 4.0, 8),
            lost,
            // Stopped before its first frame: no strain to speak of.
            stopped("k=0", 0.0, 0.0, 0),
        ];
        let rows: Vec<String> = cheapest_table(&records, &["m".into()])
            .lines()
            .skip(2)
            .map(String::from)
            .collect();
        assert_eq!(
            rows,
            [
                "| C1 N=10 r=1 | m | whole (9.000 ms) | not whole: k=1 held it over the first 12 of 300 frames (3.000 ms) | not whole: k=2 held it over the first 8 of 300 frames (4.000 ms) |"
            ]
        );
    }

    #[test]
    fn a_run_that_failed_before_its_first_frame_neither_held_nor_lost_the_bound() {
        let mut never = rec(
            "dbsmc",
            "eps=1e-2",
            Some(1e-2),
            f64::NAN,
            f64::NAN,
            "failed: singular",
        );
        never.frames = 0;
        assert_eq!(bound_held(&never), None);
        let stability = stability_table(&[never]);
        assert!(
            stability.contains("| 1 | 0 | 0 | 1 | 0 | 0 |"),
            "{stability}"
        );
        let lost = rec("dbsmc", "eps=1e-2", Some(1e-2), 2e-2, 1.0, "ok");
        assert_eq!(bound_held(&lost), Some(false));
        assert_eq!(
            bound_held(&rec("xpbd-substeps", "k=1", None, 2e-2, 1.0, "ok")),
            None
        );
    }

    #[test]
    fn the_dbsmc_table_has_every_dbsmc_run_and_no_other() {
        let mut lost = rec("dbsmc-euler", "eps=1e-3", Some(1e-3), 2e-3, 1.0, "ok");
        lost.counters.sliding.get_or_insert_default().layer_lost_at = Some(1.527);
        lost.counters
            .sliding
            .get_or_insert_default()
            .layer_worst_ratio = Some(2.64);
        lost.counters.sliding.get_or_insert_default().updates = 600;
        let records = vec![
            rec("dbsmc", "eps=1e-3", Some(1e-3), 9e-4, 0.5, "ok"),
            rec("xpbd-substeps", "k=16", None, 6e-3, 0.01, "ok"),
            lost,
        ];
        let rows: Vec<String> = dbsmc_runs_table(&records)
            .lines()
            .skip(2)
            .map(String::from)
            .collect();
        assert_eq!(rows.len(), 2, "{rows:?}");
        assert!(
            rows[0]
                .starts_with("| C1 N=10 r=1 | 10 | dbsmc | eps=1e-3 | 9.00e-4 (300) | yes | - |"),
            "{}",
            rows[0]
        );
        assert!(rows[1].contains("| dbsmc-euler | eps=1e-3 | 2.00e-3 (300) | **no** | t = 1.527 s (2.640) | 1.000 (2.000) | 2 |"), "{}", rows[1]);
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

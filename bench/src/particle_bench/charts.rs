//! SVG charts of the particle benchmark (plotters): cost per frame against worst strain
//! per scene, cost against size, cost to hold a strain against the end-mass ratio.

use std::path::Path;

use plotters::prelude::*;

use super::report::cheapest;
use super::run::ParticleRecord;

/// The methods' colours (a method's is its line's index, round): twelve.
const COLORS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(0, 100, 50),
];

/// The methods' marker shapes (round): circle, square, triangle, diamond.
const SHAPES: usize = 4;

/// The worst strain below which a complete run held, for the charts: a run at or above
/// it (or not finite) diverged, whatever its status.
pub const HELD_BELOW: f64 = 1.0;

/// One line of a chart: a label and its points.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points `(x, y)`, drawn in order.
    pub points: Vec<(f64, f64)>,
}

/// How a run ended, for the charts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Complete, worst strain finite and below [`HELD_BELOW`].
    Held,
    /// Worst strain not finite or at least [`HELD_BELOW`].
    Diverged,
    /// Stopped by the wall-clock budget (status `budget`), strain still finite and small.
    Stopped,
    /// Any other failure (status `failed: ...`), strain still finite and small.
    Failed,
}

impl Outcome {
    /// The outcome of `r` (the not yet run, status empty, as failed).
    pub fn of(r: &ParticleRecord) -> Outcome {
        if !(r.worst_strain.is_finite() && r.worst_strain < HELD_BELOW) {
            Outcome::Diverged
        } else if r.complete() {
            Outcome::Held
        } else if r.status == "budget" {
            Outcome::Stopped
        } else {
            Outcome::Failed
        }
    }

    /// The legend's text of the runs that did not hold.
    fn legend(self) -> &'static str {
        match self {
            Outcome::Held => "held",
            Outcome::Diverged => "diverged / not finite (at the right edge)",
            Outcome::Stopped => "stopped by the budget",
            Outcome::Failed => "failed",
        }
    }
}

/// A run that did not hold, marked apart from the lines: the index of its method's
/// line, its point as measured (`(x, y)`, maybe not finite) and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Off {
    /// Index of its method's line (colour and legend).
    pub line: usize,
    /// Its point as measured.
    pub point: (f64, f64),
    /// How it ended.
    pub outcome: Outcome,
}

/// A chart's log-log axes: `((x0, x1), (y0, y1))`.
pub type Range = ((f64, f64), (f64, f64));

/// The axes of a log-log chart from the lines' points (those finite and positive: the
/// runs that held), a factor 2 of margin; `None` without any.
pub fn chart_range(lines: &[Line]) -> Option<Range> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for (x, y) in lines.iter().flat_map(|l| l.points.iter()) {
        if *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite() {
            (x0, x1, y0, y1) = (x0.min(*x), x1.max(*x), y0.min(*y), y1.max(*y));
        }
    }
    (x1 > 0.0).then_some(((x0 / 2.0, x1 * 2.0), (y0 / 2.0, y1 * 2.0)))
}

/// Where an [`Off`] run is drawn in `range`: a diverged one at the right edge, the
/// others where they are, each coordinate held inside the range (not finite: the far
/// edge).
pub fn off_place(off: &Off, range: Range) -> (f64, f64) {
    let ((x0, x1), (y0, y1)) = range;
    let inside = |v: f64, a: f64, b: f64| if v.is_finite() { v.clamp(a, b) } else { b };
    let x = match off.outcome {
        Outcome::Diverged => x1,
        _ => inside(off.point.0, x0, x1),
    };
    (x, inside(off.point.1, y0, y1))
}

/// A chart of [`loglog_marked`].
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// Draw the markers `shape` (round [`SHAPES`]: circle, square, triangle, diamond) at
/// `points`, `r` pixels, in `style`.
fn draw_markers(
    chart: &mut Chart,
    shape: usize,
    points: &[(f64, f64)],
    r: i32,
    style: ShapeStyle,
) -> Result<(), String> {
    let at = |q: (f64, f64)| EmptyElement::at(q);
    let done = match shape % SHAPES {
        0 => chart
            .draw_series(
                points
                    .iter()
                    .map(|&q| at(q) + Circle::new((0, 0), r, style)),
            )
            .map(|_| ()),
        1 => chart
            .draw_series(
                points
                    .iter()
                    .map(|&q| at(q) + Rectangle::new([(-r, -r), (r, r)], style)),
            )
            .map(|_| ()),
        2 => chart
            .draw_series(
                points
                    .iter()
                    .map(|&q| at(q) + TriangleMarker::new((0, 0), r + 1, style)),
            )
            .map(|_| ()),
        _ => chart
            .draw_series(points.iter().map(|&q| {
                at(q)
                    + Polygon::new(
                        vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)],
                        style,
                    )
            }))
            .map(|_| ()),
    };
    done.map_err(|e| e.to_string())
}

/// The legend entry of line `i`: its colour's stroke and its marker.
fn line_legend<'a, 'b: 'a>(
    anno: &mut plotters::chart::SeriesAnno<'a, SVGBackend<'b>>,
    i: usize,
    c: RGBColor,
) {
    let stroke = move |(x, y): (i32, i32)| {
        EmptyElement::at((x, y)) + PathElement::new(vec![(0, 0), (18, 0)], c.stroke_width(2))
    };
    let f = c.filled();
    match i % SHAPES {
        0 => anno.legend(move |p| stroke(p) + Circle::new((9, 0), 4, f)),
        1 => anno.legend(move |p| stroke(p) + Rectangle::new([(5, -4), (13, 4)], f)),
        2 => anno.legend(move |p| stroke(p) + TriangleMarker::new((9, 0), 5, f)),
        _ => anno
            .legend(move |p| stroke(p) + Polygon::new(vec![(9, -5), (14, 0), (9, 5), (4, 0)], f)),
    };
}

/// Draw the runs `off` that ended as `kind`, in their lines' colours, with a legend
/// entry for the kind.
fn draw_off<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    kind: Outcome,
    off: &[&Off],
    range: Range,
) -> Result<(), String> {
    let placed: Vec<((f64, f64), RGBColor)> = off
        .iter()
        .map(|o| (off_place(o, range), COLORS[o.line % COLORS.len()]))
        .collect();
    let at = |q: (f64, f64)| EmptyElement::at(q);
    let e = |e: &dyn std::fmt::Display| e.to_string();
    match kind {
        Outcome::Stopped => {
            chart
                .draw_series(
                    placed
                        .iter()
                        .map(|&(q, c)| at(q) + TriangleMarker::new((0, 0), 7, c.stroke_width(2))),
                )
                .map_err(|x| e(&x))?
                .label(kind.legend())
                .legend(|p| {
                    EmptyElement::at(p) + TriangleMarker::new((9, 0), 6, BLACK.stroke_width(2))
                });
        }
        Outcome::Failed => {
            chart
                .draw_series(
                    placed.iter().map(|&(q, c)| {
                        at(q) + Rectangle::new([(-6, -6), (6, 6)], c.stroke_width(2))
                    }),
                )
                .map_err(|x| e(&x))?
                .label(kind.legend())
                .legend(|p| {
                    EmptyElement::at(p) + Rectangle::new([(4, -5), (14, 5)], BLACK.stroke_width(2))
                });
        }
        Outcome::Diverged | Outcome::Held => {
            chart
                .draw_series(
                    placed
                        .iter()
                        .map(|&(q, c)| at(q) + Cross::new((0, 0), 6, c.stroke_width(2))),
                )
                .map_err(|x| e(&x))?
                .label(kind.legend())
                .legend(|p| EmptyElement::at(p) + Cross::new((9, 0), 5, BLACK.stroke_width(2)));
        }
    }
    Ok(())
}

/// A log-log chart of `lines` into `path`.
pub fn loglog(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line],
) -> Result<(), String> {
    loglog_marked(path, title, x_label, y_label, lines, &[])
}

/// A log-log chart of `lines` (the runs that held: they set the axes) and of `off`, the
/// runs that did not, marked apart ([`off_place`]) in their method's colour. Every line
/// is in the legend, with or without points, and each kind of `off` run.
pub fn loglog_marked(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line],
    off: &[Off],
) -> Result<(), String> {
    if lines.is_empty() && off.is_empty() {
        return Err(format!("{title}: nothing to chart"));
    }
    let ((x0, x1), (y0, y1)) = chart_range(lines).unwrap_or(((1e-6, 1.0), (1e-2, 1e2)));
    let range = ((x0, x1), (y0, y1));
    let root = SVGBackend::new(path, (760, 520)).into_drawing_area();
    let e = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|x| e(&x))?;
    let ok = |(x, y): &(f64, f64)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite();
    for (i, line) in lines.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let p: Vec<(f64, f64)> = line.points.iter().copied().filter(ok).collect();
        let label = if p.is_empty() {
            format!("{} (none held)", line.label)
        } else {
            line.label.clone()
        };
        let anno = chart
            .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
            .map_err(|x| e(&x))?;
        anno.label(label);
        line_legend(anno, i, c);
        draw_markers(&mut chart, i, &p, 4, c.filled()).map_err(|x| e(&x))?;
    }
    for kind in [Outcome::Diverged, Outcome::Stopped, Outcome::Failed] {
        let of_kind: Vec<&Off> = off.iter().filter(|o| o.outcome == kind).collect();
        if !of_kind.is_empty() {
            draw_off(&mut chart, kind, &of_kind, range).map_err(|x| e(&x))?;
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

/// The lines of [`strain_chart`]: one per method of `methods` that ran in `runs`, its
/// points `(worst strain, ms per frame)` of the runs that held, and the runs that did
/// not ([`Outcome`]).
pub fn strain_lines(runs: &[&ParticleRecord], methods: &[String]) -> (Vec<Line>, Vec<Off>) {
    let mut lines = Vec::new();
    let mut off = Vec::new();
    for m in methods {
        let of_m: Vec<&&ParticleRecord> = runs.iter().filter(|r| &r.method == m).collect();
        if of_m.is_empty() {
            continue;
        }
        let mut points = Vec::new();
        for r in of_m {
            match Outcome::of(r) {
                Outcome::Held => points.push((r.worst_strain, r.ms_mean)),
                outcome => off.push(Off {
                    line: lines.len(),
                    point: (r.worst_strain, r.ms_mean),
                    outcome,
                }),
            }
        }
        lines.push(Line {
            label: m.clone(),
            points,
        });
    }
    (lines, off)
}

/// Cost per frame against worst strain for one scene (`runs`: that scene's records,
/// [`scene_groups`](super::scene_groups)), one line per method (the runs that held, in
/// the order of their settings); the runs that did not marked apart.
pub fn strain_chart(
    runs: &[&ParticleRecord],
    title: &str,
    methods: &[String],
    path: &Path,
) -> Result<(), String> {
    let (lines, off) = strain_lines(runs, methods);
    loglog_marked(
        path,
        &format!("{title}: cost per frame against worst strain (runs that held)"),
        "worst strain |L - L0| / L0 over all links and frames",
        "wall time per 1/60 s frame, mean [ms]",
        &lines,
        &off,
    )
}

/// Cost to hold `target` against the C1 end-mass ratio, one line per method, for the
/// chains of `links` links.
pub fn ratio_chart(
    records: &[ParticleRecord],
    links: usize,
    target: f64,
    methods: &[String],
    path: &Path,
) -> Result<(), String> {
    let mut ratios: Vec<f64> = records
        .iter()
        .filter(|r| r.scene == "C1" && r.size == links)
        .map(|r| r.param)
        .collect();
    ratios.sort_by(f64::total_cmp);
    ratios.dedup();
    let lines: Vec<Line> = methods
        .iter()
        .map(|m| Line {
            label: m.clone(),
            points: ratios
                .iter()
                .filter_map(|&q| {
                    let title = records
                        .iter()
                        .find(|r| r.scene == "C1" && r.size == links && r.param == q)
                        .map(super::scene_title)?;
                    cheapest(records, &title, m, target).map(|r| (q, r.ms_mean))
                })
                .collect(),
        })
        .filter(|l| !l.points.is_empty())
        .collect();
    loglog(
        path,
        &format!("C1 N={links}: cost to hold worst strain {target:e} against end-mass ratio"),
        "end-mass ratio",
        "cheapest mean wall time per frame [ms]",
        &lines,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn runs() -> Vec<ParticleRecord> {
        let mut diverged = ParticleRecord::for_tests("xpbd", "k=1", None, 1e17);
        diverged.ms_mean = 0.01;
        let mut nan = ParticleRecord::for_tests("vbd", "n=1", None, f64::NAN);
        nan.status = "failed: not finite".into();
        let mut budget = ParticleRecord::for_tests("index1-rk4", "steps/frame=4096", None, 3e-4);
        budget.status = "budget".into();
        budget.ms_mean = 500.0;
        vec![
            ParticleRecord::for_tests("xpbd", "k=16", None, 1e-3),
            ParticleRecord::for_tests("xpbd", "k=64", None, 1e-4),
            diverged,
            ParticleRecord::for_tests("dbsmc", "eps=1e-2", Some(1e-2), 5e-3),
            nan,
            budget,
        ]
    }

    #[test]
    fn the_axes_come_from_the_runs_that_held_and_every_method_is_in_the_legend() {
        let records = runs();
        let refs: Vec<&ParticleRecord> = records.iter().collect();
        let methods: Vec<String> = ["dbsmc", "xpbd", "index1-rk4", "vbd", "avbd"]
            .map(String::from)
            .to_vec();
        let (lines, off) = strain_lines(&refs, &methods);
        let labels: Vec<&str> = lines.iter().map(|l| l.label.as_str()).collect();
        // avbd did not run: not in the chart; vbd ran and did not hold: still in it.
        assert_eq!(labels, ["dbsmc", "xpbd", "index1-rk4", "vbd"]);
        let range = chart_range(&lines).unwrap();
        let ((x0, x1), (y0, y1)) = range;
        assert!(
            x0 <= 1e-4 / 2.0 + 1e-18 && (5e-3..1.0).contains(&x1),
            "{range:?}"
        );
        assert!(y0 > 0.1 && y1 < 10.0, "{range:?}");
        let kinds: Vec<(usize, Outcome)> = off.iter().map(|o| (o.line, o.outcome)).collect();
        assert_eq!(
            kinds,
            [
                (1, Outcome::Diverged),
                (2, Outcome::Stopped),
                (3, Outcome::Diverged)
            ]
        );
        // The diverged at the right edge, inside the y range; the stopped at its strain,
        // its cost held at the top.
        assert_eq!(off_place(&off[0], range), (x1, 0.5));
        assert_eq!(off_place(&off[1], range), (3e-4, y1));
        assert_eq!(off_place(&off[2], range).0, x1);
        assert_eq!(off_place(&off[2], range).1, 1.0);
    }

    #[test]
    fn a_strain_chart_names_every_method_and_the_diverged() {
        let records = runs();
        let refs: Vec<&ParticleRecord> = records.iter().collect();
        let methods: Vec<String> = ["dbsmc", "xpbd", "index1-rk4", "vbd"]
            .map(String::from)
            .to_vec();
        let dir = std::env::temp_dir().join(format!("dae_bench_charts_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("strain.svg");
        strain_chart(&refs, "C1 N=10 r=1", &methods, &path).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        for m in &methods {
            assert!(svg.contains(m.as_str()), "{m}");
        }
        assert!(svg.contains("vbd (none held)") && svg.contains("diverged"));
        assert!(svg.contains("stopped by the budget") && !svg.contains("1e17"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn twelve_colours_are_distinct() {
        for (i, a) in COLORS.iter().enumerate() {
            for b in &COLORS[..i] {
                assert_ne!(a, b);
            }
        }
    }
}

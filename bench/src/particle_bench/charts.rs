//! SVG charts of the particle benchmark (plotters): cost per frame against worst strain
//! per scene, cost against size, cost to hold a strain against the end-mass ratio.

use std::path::Path;

use plotters::prelude::*;

use super::report::cheapest;
use super::run::ParticleRecord;

const COLORS: [RGBColor; 6] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(127, 127, 127),
];

/// One line of a chart: a label and its points.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points `(x, y)`, drawn in order.
    pub points: Vec<(f64, f64)>,
}

/// A log-log chart of `lines` into `path`.
pub fn loglog(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line],
) -> Result<(), String> {
    let pts: Vec<(f64, f64)> = lines
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .collect();
    if pts.is_empty() {
        return Err(format!("{title}: nothing to chart"));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for (x, y) in &pts {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    let (x0, x1, y0, y1) = (x0 / 2.0, x1 * 2.0, y0 / 2.0, y1 * 2.0);
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
    for (i, line) in lines.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let p: Vec<(f64, f64)> = line
            .points
            .iter()
            .copied()
            .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
            .collect();
        if p.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
            .map_err(|x| e(&x))?
            .label(line.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        chart
            .draw_series(p.iter().map(|&q| Circle::new(q, 4, c.filled())))
            .map_err(|x| e(&x))?;
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

/// Cost per frame against worst strain for one scene (`runs`: that scene's records,
/// [`scene_groups`](super::scene_groups)), one line per method (complete runs, in the
/// order of their settings).
pub fn strain_chart(
    runs: &[&ParticleRecord],
    title: &str,
    methods: &[String],
    path: &Path,
) -> Result<(), String> {
    let lines: Vec<Line> = methods
        .iter()
        .map(|m| Line {
            label: m.clone(),
            points: runs
                .iter()
                .filter(|r| &r.method == m && r.complete())
                .map(|r| (r.worst_strain, r.ms_mean))
                .collect(),
        })
        .filter(|l| !l.points.is_empty())
        .collect();
    loglog(
        path,
        &format!("{title}: cost per frame against worst strain (complete runs)"),
        "worst strain |L - L0| / L0 over all links and frames",
        "wall time per 1/60 s frame, mean [ms]",
        &lines,
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

//! Log-log work-precision charts (SVG, plotters).

use std::path::Path;

use plotters::prelude::*;

use super::Record;

/// Which error goes on the vertical axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorAxis {
    /// Position error at `t_end` against the truth.
    Position,
    /// Largest constraint residual over the run.
    Constraint,
}

/// Which cost goes on the horizontal axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostAxis {
    /// Best wall time of the repeats.
    Wall,
    /// `J_s` factorisations and solves: the cost that dominates for many constraints.
    JSolves,
    /// Evaluations of `f`.
    FEvals,
}

impl CostAxis {
    fn of(self, r: &Record) -> f64 {
        match self {
            CostAxis::Wall => r.wall,
            CostAxis::JSolves => r.j_solves as f64,
            CostAxis::FEvals => r.f_evals as f64,
        }
    }
    fn label(self) -> &'static str {
        match self {
            CostAxis::Wall => "wall time [s] (best of repeats)",
            CostAxis::JSolves => "J_s solves",
            CostAxis::FEvals => "f evaluations",
        }
    }
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Chart error against cost (log-log), one line per [`Record::line`], from the
/// successful records of one scene. Errors below `1e-16` are drawn at `1e-16`.
pub fn chart(
    records: &[Record],
    title: &str,
    axis: ErrorAxis,
    cost: CostAxis,
    path: &Path,
) -> Result<(), String> {
    let err = |r: &Record| {
        let e = match axis {
            ErrorAxis::Position => r.pos_err,
            ErrorAxis::Constraint => r.max_w,
        };
        e.max(1e-16)
    };
    let ok: Vec<&Record> = records
        .iter()
        .filter(|r| r.ok && cost.of(r) > 0.0)
        .collect();
    if ok.is_empty() {
        return Err(format!("{title}: no successful run to chart"));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for r in &ok {
        x0 = x0.min(cost.of(r));
        x1 = x1.max(cost.of(r));
        y0 = y0.min(err(r));
        y1 = y1.max(err(r));
    }
    let (x0, x1) = (x0 / 2.0, x1 * 2.0);
    let (y0, y1) = (y0 / 3.0, y1 * 3.0);
    let mut lines: Vec<String> = Vec::new();
    for r in &ok {
        if !lines.contains(&r.line) {
            lines.push(r.line.clone());
        }
    }
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    let e = |e: Box<dyn std::error::Error>| format!("{title}: {e}");
    root.fill(&WHITE).map_err(|x| e(Box::new(x)))?;
    let ylabel = match axis {
        ErrorAxis::Position => "position error at t_end",
        ErrorAxis::Constraint => "max |w| over the run",
    };
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|x| e(Box::new(x)))?;
    c.configure_mesh()
        .x_desc(cost.label())
        .y_desc(ylabel)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|x| e(Box::new(x)))?;
    for (i, line) in lines.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let mut pts: Vec<(f64, f64)> = ok
            .iter()
            .filter(|r| &r.line == line)
            .map(|r| (cost.of(r), err(r)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        c.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(|x| e(Box::new(x)))?
            .label(line.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        c.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(|x| e(Box::new(x)))?;
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|x| e(Box::new(x)))?;
    root.present().map_err(|x| e(Box::new(x)))?;
    Ok(())
}

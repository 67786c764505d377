//! The plotters code behind the chart functions; input is already validated.

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

use super::{ChartError, ErrorSeries, SlidingSeries, YScale, thin};

const WIDTH: u32 = 900;
const PANEL_HEIGHT: u32 = 260;
/// Time bins for thinning long traces (about one per horizontal pixel of the plot).
const COLUMNS: usize = 800;

const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

fn draw_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> ChartError {
    ChartError::Draw(e.to_string())
}

/// `[lo, hi]` widened by 5% (or by 1 if it is a single value) so lines stay off the frame.
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if hi > lo {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    } else {
        let pad = if lo == 0.0 { 1.0 } else { 0.5 * lo.abs() };
        (lo - pad, hi + pad)
    }
}

fn span(xs: impl Iterator<Item = f64>) -> (f64, f64) {
    xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    })
}

fn time_range(t: &[f64]) -> (f64, f64) {
    if t[t.len() - 1] > t[0] {
        (t[0], t[t.len() - 1])
    } else {
        padded(t[0], t[0])
    }
}

fn svg_canvas<F>(height: u32, draw: F) -> Result<String, ChartError>
where
    F: FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), ChartError>,
{
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        draw(&root)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

pub(super) fn sliding(
    title: &str,
    t: &[f64],
    series: &[SlidingSeries<'_>],
) -> Result<String, ChartError> {
    let height = 40 + PANEL_HEIGHT * series.len() as u32;
    svg_canvas(height, |root| {
        let root = root.titled(title, ("sans-serif", 22)).map_err(draw_err)?;
        let panels = root.split_evenly((series.len(), 1));
        let (t0, t1) = time_range(t);
        for (i, (panel, s)) in panels.iter().zip(series).enumerate() {
            let (lo, hi) = span(s.s.iter().copied());
            let (y0, y1) = padded(lo.min(-s.eps), hi.max(s.eps));
            let mut chart = ChartBuilder::on(panel)
                .margin(8)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d(t0..t1, y0..y1)
                .map_err(draw_err)?;
            chart
                .configure_mesh()
                .x_desc("t")
                .y_desc(s.name)
                // Ticks at zero come out as +-2e-16 from the range arithmetic.
                .y_label_formatter(&|v| axis_number(if v.abs() < 1e-9 * s.eps { 0.0 } else { *v }))
                .light_line_style(WHITE)
                .draw()
                .map_err(draw_err)?;
            let c = colour(i);
            let line = thin(t, |k| s.s[k], COLUMNS);
            chart
                .draw_series(LineSeries::new(line, c.stroke_width(1)))
                .map_err(draw_err)?
                .label(s.name)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c));
            let band = BLACK.mix(0.6).stroke_width(1);
            chart
                .draw_series(DashedLineSeries::new(
                    [(t0, s.eps), (t1, s.eps)],
                    6,
                    4,
                    band,
                ))
                .map_err(draw_err)?
                .label(format!("+-eps = {}", s.eps))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], band));
            chart
                .draw_series(DashedLineSeries::new(
                    [(t0, -s.eps), (t1, -s.eps)],
                    6,
                    4,
                    band,
                ))
                .map_err(draw_err)?;
            chart
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.85))
                .draw()
                .map_err(draw_err)?;
        }
        Ok(())
    })
}

pub(super) fn periods(
    title: &str,
    update_times: &[f64],
    t_min: Option<f64>,
) -> Result<String, ChartError> {
    let pts: Vec<(f64, f64)> = update_times
        .windows(2)
        .map(|w| (w[1], w[1] - w[0]))
        .collect();
    let (lo, hi) = span(pts.iter().map(|p| p.1).chain(t_min));
    let (_, y1) = padded(lo.min(0.0), hi);
    let (t0, t1) = time_range(update_times);
    svg_canvas(40 + 2 * PANEL_HEIGHT, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(t0..t1, 0.0..y1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc("update time")
            .y_desc("period")
            .light_line_style(WHITE)
            .draw()
            .map_err(draw_err)?;
        let c = colour(0);
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), c.mix(0.4)))
            .map_err(draw_err)?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 2, c.filled())))
            .map_err(draw_err)?
            .label(format!("update period ({} updates)", update_times.len()))
            .legend(move |(x, y)| Circle::new((x + 10, y), 3, c.filled()));
        if let Some(tm) = t_min {
            let red = colour(1).stroke_width(2);
            chart
                .draw_series(LineSeries::new([(t0, tm), (t1, tm)], red))
                .map_err(draw_err)?
                .label(format!("guaranteed T_min = {tm:.4e}"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], red));
        }
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.85))
            .draw()
            .map_err(draw_err)?;
        Ok(())
    })
}

pub(super) fn errors(
    title: &str,
    t: &[f64],
    series: &[ErrorSeries<'_>],
    scale: YScale,
) -> Result<String, ChartError> {
    let (t0, t1) = time_range(t);
    let max = span(series.iter().flat_map(|s| s.w.iter().map(|w| w.abs()))).1;
    svg_canvas(40 + 2 * PANEL_HEIGHT, |root| match scale {
        YScale::Linear => {
            let (_, y1) = padded(0.0, max);
            errors_on(root, title, t, series, t0..t1, 0.0..y1, 0.0)
        }
        YScale::Log => {
            // At most 12 decades below the largest value; everything smaller (and
            // zero) sits on the bottom edge rather than stretching the axis.
            let top = if max > 0.0 { max * 2.0 } else { 1.0 };
            let smallest = series
                .iter()
                .flat_map(|s| s.w.iter().map(|w| w.abs()))
                .filter(|&w| w > 0.0)
                .fold(f64::INFINITY, f64::min);
            let floor = if smallest.is_finite() {
                (smallest * 0.5).max(top * 1e-12)
            } else {
                top * 1e-3
            };
            errors_on(
                root,
                title,
                t,
                series,
                t0..t1,
                (floor..top).log_scale(),
                floor,
            )
        }
    })
}

fn errors_on<Y>(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    t: &[f64],
    series: &[ErrorSeries<'_>],
    x: std::ops::Range<f64>,
    y: Y,
    floor: f64,
) -> Result<(), ChartError>
where
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 22))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .x_desc("t")
        .y_desc("|w|")
        .y_label_formatter(&|v| axis_number(*v))
        .light_line_style(WHITE)
        .draw()
        .map_err(draw_err)?;
    for (i, s) in series.iter().enumerate() {
        let c = colour(i);
        let line = thin(t, |k| s.w[k].abs().max(floor), COLUMNS);
        chart
            .draw_series(LineSeries::new(line, c.stroke_width(1)))
            .map_err(draw_err)?
            .label(s.name)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c));
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .draw()
        .map_err(draw_err)?;
    Ok(())
}

/// A short axis label: plain decimals from 1e-3 to 1e4, otherwise `1e-5` or `2.5e-5`
/// (the default formatting prints log-scale ticks as `9.99999999999e-5`).
fn axis_number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (1e-3..1e4).contains(&a) {
        let text = format!("{v:.4}");
        return text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    let text = format!("{v:.2e}");
    let (mantissa, exp) = text.split_once('e').unwrap_or((&text, "0"));
    let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
    format!("{mantissa}e{exp}")
}

#[cfg(test)]
mod axis_tests {
    #[test]
    fn axis_numbers_are_short() {
        assert_eq!(super::axis_number(9.99999999999e-5), "1e-4");
        assert_eq!(super::axis_number(2.5e-6), "2.5e-6");
        assert_eq!(super::axis_number(0.001), "0.001");
        assert_eq!(super::axis_number(0.25), "0.25");
        assert_eq!(super::axis_number(1.0), "1");
        assert_eq!(super::axis_number(0.0), "0");
    }
}

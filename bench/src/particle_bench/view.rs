//! What a picture of a particle run shows and how: the orthographic camera, the ground
//! grid, the strain colours and their legend, the marks of pinned and grabbed particles,
//! the labels; one panel of one frame ([`draw_panel`]).

use dae_particles::{Link, distance};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::{GLYPH, draw_text, text_width};

/// Size of one panel (pixels).
pub const PANEL: (u32, u32) = (440, 400);
/// Where the scene is drawn in a panel: left, top, right, bottom (pixels); above are
/// the labels, right the colour legend, below the grid's spacing.
const SCENE_BOX: (f64, f64, f64, f64) = (12.0, 84.0, 372.0, 372.0);

/// An orthographic camera looking at the origin, `z` up: from the azimuth (degrees,
/// 0: looking along `+y`, `x` to the right; positive turns the camera about `z`
/// counter-clockwise seen from above) and the elevation (degrees above the horizon).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Degrees about `z`.
    pub azimuth: f64,
    /// Degrees above the horizon.
    pub elevation: f64,
}

/// The camera of the pictures: 30 degrees about `z`, 20 degrees above the horizon.
pub const CAMERA: Camera = Camera {
    azimuth: 30.0,
    elevation: 20.0,
};

impl Camera {
    /// `(u, v, depth)` of `p`: `u` to the right and `v` up on the screen (m), `depth`
    /// towards the camera (m; the larger, the nearer).
    ///
    /// `u = x cos a + y sin a`, `v = -x sin a sin e + y cos a sin e + z cos e`,
    /// `depth = x sin a cos e - y cos a cos e + z sin e`.
    pub fn project(&self, p: [f64; 3]) -> (f64, f64, f64) {
        let (sa, ca) = self.azimuth.to_radians().sin_cos();
        let (se, ce) = self.elevation.to_radians().sin_cos();
        (
            p[0] * ca + p[1] * sa,
            -p[0] * sa * se + p[1] * ca * se + p[2] * ce,
            p[0] * sa * ce - p[1] * ca * ce + p[2] * se,
        )
    }
}

/// The green, yellow, red and magenta of the strain scale.
pub const GREEN: RGBColor = RGBColor(30, 170, 60);
/// Half the bound.
pub const YELLOW: RGBColor = RGBColor(235, 200, 20);
/// The bound.
pub const RED: RGBColor = RGBColor(215, 25, 25);
/// Above the bound (or not finite).
pub const MAGENTA: RGBColor = RGBColor(200, 0, 200);

/// Colour of `strain` relative to `bound`: green at or below `bound / 10`, yellow at
/// `bound / 2` (log scale between), red at `bound` (linear between), magenta above it
/// (the bound exceeded) or when not finite.
pub fn strain_colour(strain: f64, bound: f64) -> RGBColor {
    let r = strain / bound;
    if !r.is_finite() || r > 1.0 {
        return MAGENTA;
    }
    let lerp = |a: RGBColor, b: RGBColor, f: f64| {
        let m = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
        RGBColor(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2))
    };
    if r <= 0.1 {
        GREEN
    } else if r <= 0.5 {
        lerp(GREEN, YELLOW, (r / 0.1).log10() / 5f64.log10())
    } else {
        lerp(YELLOW, RED, (r - 0.5) / 0.5)
    }
}

/// A spacing of 1, 2 or 5 times a power of ten that cuts `extent` into about 4 to 10.
pub fn grid_spacing(extent: f64) -> f64 {
    let raw = (extent / 6.0).max(1e-6);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * 0.75)
        .unwrap_or(10.0 * p)
}

/// The ground: a grid at height `z` over `[x0, x1] x [y0, y1]`, lines `spacing` apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ground {
    /// Height (m).
    pub z: f64,
    /// Extent in `x` (m).
    pub x: (f64, f64),
    /// Extent in `y` (m).
    pub y: (f64, f64),
    /// Spacing of the lines (m).
    pub spacing: f64,
}

impl Ground {
    /// The ground under `points` (finite ones): at `z` if given, else their lowest
    /// height less a margin; its extent theirs and a margin, on the grid.
    pub fn under(points: &[[f64; 3]], z: Option<f64>) -> Ground {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points.iter().filter(|p| p.iter().all(|c| c.is_finite())) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !lo[0].is_finite() {
            (lo, hi) = ([-0.5; 3], [0.5; 3]);
        }
        let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.2, f64::max);
        let spacing = grid_spacing(extent);
        let margin = 0.1 * extent;
        let snap = |a: f64, b: f64| {
            (
                ((a - margin) / spacing).floor() * spacing,
                ((b + margin) / spacing).ceil() * spacing,
            )
        };
        Ground {
            z: z.unwrap_or(lo[2] - 0.05 * extent),
            x: snap(lo[0], hi[0]),
            y: snap(lo[1], hi[1]),
            spacing,
        }
    }

    /// The corners of the grid.
    fn corners(&self) -> [[f64; 3]; 4] {
        let (x, y, z) = (self.x, self.y, self.z);
        [[x.0, y.0, z], [x.1, y.0, z], [x.1, y.1, z], [x.0, y.1, z]]
    }
}

/// Where the world goes in a panel: the camera, the ground, and the map from screen
/// metres to pixels (one for all panels and frames of a picture).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The camera.
    pub camera: Camera,
    /// The ground.
    pub ground: Ground,
    /// Screen `u` at the scene box's left edge, `v` at its top (m), pixels per metre.
    pub origin: (f64, f64),
    /// Pixels per metre.
    pub scale: f64,
}

impl View {
    /// The view that shows the ground and all of `points` (finite ones) in the scene box.
    pub fn fitting(camera: Camera, ground: Ground, points: &[[f64; 3]]) -> View {
        let (mut u0, mut u1, mut v0, mut v1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let finite = points.iter().filter(|p| p.iter().all(|c| c.is_finite()));
        for p in ground.corners().iter().chain(finite) {
            let (u, v, _) = camera.project(*p);
            (u0, u1, v0, v1) = (u0.min(u), u1.max(u), v0.min(v), v1.max(v));
        }
        let (bl, bt, br, bb) = SCENE_BOX;
        let scale = ((br - bl) / (u1 - u0).max(1e-9)).min((bb - bt) / (v1 - v0).max(1e-9));
        // Centred in the box.
        let origin = (
            (u0 + u1) / 2.0 - (br - bl) / 2.0 / scale,
            (v0 + v1) / 2.0 + (bb - bt) / 2.0 / scale,
        );
        View {
            camera,
            ground,
            origin,
            scale,
        }
    }

    /// Pixel of `p` in a panel (not rounded) and its depth.
    pub fn pixel(&self, p: [f64; 3]) -> (f64, f64, f64) {
        let (u, v, d) = self.camera.project(p);
        (
            SCENE_BOX.0 + (u - self.origin.0) * self.scale,
            SCENE_BOX.1 + (self.origin.1 - v) * self.scale,
            d,
        )
    }
}

/// The part of the segment `a`-`b` inside the panel (Liang-Barsky), rounded to pixels;
/// `None` if none is (or an end is not finite).
fn clip(a: (f64, f64), b: (f64, f64)) -> Option<[(i32, i32); 2]> {
    if ![a.0, a.1, b.0, b.1].iter().all(|c| c.is_finite()) {
        return None;
    }
    let (w, h) = (PANEL.0 as f64, PANEL.1 as f64);
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0), (dx, w - a.0), (-dy, a.1), (dy, h - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| {
        let at = |t: f64| ((a.0 + t * dx).round() as i32, (a.1 + t * dy).round() as i32);
        [at(t0), at(t1)]
    })
}

/// Which particles are marked in the pictures.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Marks {
    /// Pinned particles (filled black squares).
    pub pinned: Vec<usize>,
    /// Grabbed particles and the times they are held, `(particle, from, to)` (s; blue
    /// rings while held).
    pub grabbed: Vec<(usize, f64, f64)>,
    /// Height of the ground (m), or `None`: a little below the lowest point captured.
    pub ground: Option<f64>,
}

/// What one panel of one frame shows.
pub struct Shot<'a> {
    /// The links.
    pub links: &'a [Link],
    /// Positions.
    pub positions: &'a [[f64; 3]],
    /// Time (s).
    pub t: f64,
    /// The method's name.
    pub method: &'a str,
    /// Worst strain so far.
    pub worst: f64,
    /// Time the run stopped at, if it did before this frame.
    pub stopped: Option<f64>,
    /// The bound the colours are relative to.
    pub bound: f64,
}

/// Worst `|L - L0| / L0` over `links` at `positions` (`NaN` if a length is not finite).
pub fn worst_strain(links: &[Link], positions: &[[f64; 3]]) -> f64 {
    links.iter().fold(0.0, |w, l| {
        let s = (distance(positions[l.a], positions[l.b]) - l.rest).abs() / l.rest;
        if s.is_finite() { w.max(s) } else { f64::NAN }
    })
}

fn line<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    a: (f64, f64),
    b: (f64, f64),
    style: ShapeStyle,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    match clip(a, b) {
        Some(ends) => area
            .draw(&PathElement::new(ends.to_vec(), style))
            .map_err(|e| e.to_string()),
        None => Ok(()),
    }
}

/// Draw one panel: the ground, the links' shadows on it, the links by strain (far ones
/// first), the marks, the labels and the colour legend.
pub fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    view: &View,
    marks: &Marks,
    shot: &Shot,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: &dyn std::fmt::Display| e.to_string();
    area.fill(&WHITE).map_err(|x| e(&x))?;
    let g = view.ground;
    let px = |p: [f64; 3]| {
        let (x, y, _) = view.pixel(p);
        (x, y)
    };
    // The ground.
    let grid = RGBColor(200, 200, 205).stroke_width(1);
    let n = |r: (f64, f64)| ((r.1 - r.0) / g.spacing).round() as i64;
    for i in 0..=n(g.x) {
        let x = g.x.0 + i as f64 * g.spacing;
        line(area, px([x, g.y.0, g.z]), px([x, g.y.1, g.z]), grid)?;
    }
    for i in 0..=n(g.y) {
        let y = g.y.0 + i as f64 * g.spacing;
        line(area, px([g.x.0, y, g.z]), px([g.x.1, y, g.z]), grid)?;
    }
    // Shadows.
    let ps = shot.positions;
    let shadow = RGBColor(215, 215, 215).stroke_width(2);
    for l in shot.links {
        let (a, b) = (ps[l.a], ps[l.b]);
        line(area, px([a[0], a[1], g.z]), px([b[0], b[1], g.z]), shadow)?;
    }
    // Links, the farthest first.
    let mut order: Vec<(f64, &Link)> = shot
        .links
        .iter()
        .map(|l| (view.pixel(ps[l.a]).2 + view.pixel(ps[l.b]).2, l))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, l) in order {
        let (a, b) = (ps[l.a], ps[l.b]);
        let strain = (distance(a, b) - l.rest).abs() / l.rest;
        let c = strain_colour(strain, shot.bound);
        line(area, px(a), px(b), c.stroke_width(3))?;
    }
    // Marks.
    let at = |i: usize| -> Option<(i32, i32)> {
        let (x, y) = px(*ps.get(i)?);
        (x.is_finite() && y.is_finite() && x.abs() < 1e5 && y.abs() < 1e5)
            .then(|| (x.round() as i32, y.round() as i32))
    };
    for &i in &marks.pinned {
        if let Some((x, y)) = at(i) {
            area.draw(&Rectangle::new(
                [(x - 4, y - 4), (x + 4, y + 4)],
                BLACK.filled(),
            ))
            .map_err(|x| e(&x))?;
        }
    }
    let blue = RGBColor(20, 80, 230);
    for &(i, from, to) in &marks.grabbed {
        match at(i) {
            Some(c) if (from..to).contains(&shot.t) => {
                area.draw(&Circle::new(c, 8, blue.stroke_width(3)))
                    .map_err(|x| e(&x))?;
            }
            _ => {}
        }
    }
    labels(area, view, marks, shot)
}

/// `x` in 2 significant digits, or `NaN`.
fn short(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1e}")
    } else {
        "NAN".into()
    }
}

/// The labels and the colour legend of a panel.
fn labels<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    view: &View,
    marks: &Marks,
    shot: &Shot,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let dark = RGBColor(30, 30, 30);
    let (w, h) = (PANEL.0 as i32, PANEL.1 as i32);
    let line_h = GLYPH.1 * 2 + 5;
    draw_text(area, shot.method, (8, 6), 2, dark)?;
    draw_text(
        area,
        &format!("t = {:.2} s", shot.t),
        (8, 6 + line_h),
        2,
        dark,
    )?;
    let worst = format!(
        "worst {} = {:.2} bound",
        short(shot.worst),
        shot.worst / shot.bound
    );
    let wc = if shot.worst.is_finite() && shot.worst <= shot.bound {
        dark
    } else {
        MAGENTA
    };
    draw_text(area, &worst, (8, 6 + 2 * line_h), 2, wc)?;
    if let Some(t) = shot.stopped {
        draw_text(
            area,
            &format!("stopped at {t:.2} s"),
            (8, 6 + 3 * line_h),
            2,
            RED,
        )?;
    }
    // The colour legend: strain / bound from 0 (bottom) to 1.25 (top).
    let (x0, x1, top, bottom) = (w - 58, w - 44, 110, h - 70);
    let rel = |y: i32| 1.25 * (bottom - y) as f64 / (bottom - top) as f64;
    for y in top..=bottom {
        let c = strain_colour(rel(y), 1.0);
        area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(1)))
            .map_err(|x| e(&x))?;
    }
    area.draw(&Rectangle::new(
        [(x0, top), (x1, bottom)],
        dark.stroke_width(1),
    ))
    .map_err(|x| e(&x))?;
    let y_of = |r: f64| bottom - (r / 1.25 * (bottom - top) as f64).round() as i32;
    for (r, text) in [
        (0.0, "0"),
        (0.1, ".1"),
        (0.5, ".5"),
        (1.0, "1"),
        (1.15, ">1"),
    ] {
        let y = y_of(r);
        area.draw(&PathElement::new(
            vec![(x1, y), (x1 + 3, y)],
            dark.stroke_width(1),
        ))
        .map_err(|x| e(&x))?;
        draw_text(area, text, (x1 + 5, y - GLYPH.1 / 2), 1, dark)?;
    }
    let caption = ["strain", "/ bound", &format!("{:.0e}", shot.bound)];
    for (i, c) in caption.iter().enumerate() {
        draw_text(area, c, (w - 64, top - 34 + 10 * i as i32), 1, dark)?;
    }
    // The grid's spacing and what the marks mean.
    let spacing = view.ground.spacing;
    let metres = if spacing >= 1.0 {
        format!("grid {spacing} m")
    } else {
        format!("grid {} cm", spacing * 100.0)
    };
    draw_text(area, &metres, (8, h - 22), 2, RGBColor(120, 120, 130))?;
    let mut x = 8 + text_width(&metres, 2) + 16;
    if !marks.pinned.is_empty() {
        area.draw(&Rectangle::new(
            [(x, h - 20), (x + 8, h - 12)],
            BLACK.filled(),
        ))
        .map_err(|x| e(&x))?;
        draw_text(area, "pinned", (x + 12, h - 19), 1, dark)?;
        x += 12 + text_width("pinned", 1) + 14;
    }
    if !marks.grabbed.is_empty() {
        let blue = RGBColor(20, 80, 230);
        area.draw(&Circle::new((x + 5, h - 16), 5, blue.stroke_width(2)))
            .map_err(|x| e(&x))?;
        draw_text(area, "grabbed", (x + 14, h - 19), 1, dark)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_maps_the_ground_by_its_closed_form() {
        let (a, el) = (CAMERA.azimuth.to_radians(), CAMERA.elevation.to_radians());
        for p in [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 2.0, -1.0],
            [-3.0, 0.5, -1.0],
        ] {
            let (u, v, _) = CAMERA.project(p);
            let u_want = p[0] * a.cos() + p[1] * a.sin();
            let v_want = -p[0] * a.sin() * el.sin() + p[1] * a.cos() * el.sin() - el.cos();
            assert!(
                (u - u_want).abs() < 1e-12 && (v - v_want).abs() < 1e-12,
                "{p:?}"
            );
        }
        // Up is up, and +y goes into the picture (up the screen, away from the camera).
        let (_, v0, d0) = CAMERA.project([0.0; 3]);
        let (_, vz, _) = CAMERA.project([0.0, 0.0, 1.0]);
        let (_, vy, dy) = CAMERA.project([0.0, 1.0, 0.0]);
        assert!(vz > v0 && vy > v0 && dy < d0);
        // Orthographic: a length along the view direction vanishes.
        let (se, ce) = el.sin_cos();
        let dir = [a.sin() * ce, -a.cos() * ce, se];
        let (u, v, d) = CAMERA.project(dir);
        assert!(u.abs() < 1e-12 && v.abs() < 1e-12 && (d - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_view_puts_the_ground_in_the_scene_box() {
        let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0]];
        let g = Ground::under(&pts, None);
        assert!(g.z < -1.0 && g.x.0 <= 0.0 && g.x.1 >= 1.0);
        assert_eq!(Ground::under(&pts, Some(-3.0)).z, -3.0);
        let v = View::fitting(CAMERA, g, &pts);
        for c in g.corners().iter().chain(&pts) {
            let (x, y, _) = v.pixel(*c);
            assert!(
                (SCENE_BOX.0 - 1e-9..=SCENE_BOX.2 + 1e-9).contains(&x),
                "{x}"
            );
            assert!(
                (SCENE_BOX.1 - 1e-9..=SCENE_BOX.3 + 1e-9).contains(&y),
                "{y}"
            );
        }
        assert_eq!(grid_spacing(1.0), 0.2);
        assert_eq!(grid_spacing(30.0), 5.0);
        assert_eq!(grid_spacing(0.06), 0.01);
    }

    fn hue(c: RGBColor) -> f64 {
        let (r, g, b) = (c.0 as f64, c.1 as f64, c.2 as f64);
        let (max, min) = (r.max(g).max(b), r.min(g).min(b));
        let h = if max == min {
            0.0
        } else if max == r {
            60.0 * ((g - b) / (max - min))
        } else if max == g {
            60.0 * ((b - r) / (max - min) + 2.0)
        } else {
            60.0 * ((r - g) / (max - min) + 4.0)
        };
        h.rem_euclid(360.0)
    }

    #[test]
    fn the_colours_run_green_to_red_and_magenta_only_above_the_bound() {
        let bound = 1e-3;
        let mut last = f64::INFINITY;
        for i in 0..=1000 {
            let s = bound * i as f64 / 1000.0;
            let c = strain_colour(s, bound);
            assert_ne!(c, MAGENTA, "{s}");
            let h = hue(c);
            // Monotone but for the rounding to 8 bits (a degree or so).
            assert!(h <= last + 1.5, "hue {h} after {last} at {s}");
            last = last.min(h);
        }
        assert!(last < 1.0, "{last}");
        assert!(hue(GREEN) > 100.0 && (40.0..70.0).contains(&hue(YELLOW)));
        assert_eq!(strain_colour(0.0, bound), GREEN);
        assert_eq!(strain_colour(0.5 * bound, bound), YELLOW);
        assert_eq!(strain_colour(bound, bound), RED);
        for s in [1.0001e-3, 2e-3, 1e17, f64::INFINITY, f64::NAN] {
            assert_eq!(strain_colour(s, bound), MAGENTA, "{s}");
        }
    }

    #[test]
    fn clipping_keeps_the_part_inside() {
        assert_eq!(clip((10.0, 10.0), (20.0, 20.0)), Some([(10, 10), (20, 20)]));
        let [a, b] = clip((-100.0, 50.0), (1e17, 50.0)).unwrap();
        assert_eq!((a, b), ((0, 50), (PANEL.0 as i32, 50)));
        assert_eq!(clip((-10.0, -10.0), (-5.0, -20.0)), None);
        assert_eq!(clip((0.0, f64::NAN), (1.0, 1.0)), None);
    }
}

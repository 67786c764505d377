//! Pictures of a run: PNG frames and an animated GIF, links coloured by strain
//! (plotters' bitmap and GIF backends, the `png` crate for the frames).

use std::path::Path;

use dae_particles::{Link, distance};
use plotters::prelude::*;

/// Positions captured during a run: `(frame, positions)`.
pub type Capture = Vec<(u64, Vec<[f64; 3]>)>;

/// Picture size (pixels).
const SIZE: u32 = 320;

/// Frames a run keeps for its pictures: every fifth (12 per second of the scene's 60).
const CAPTURE_EVERY: u64 = 5;
/// The frames written as PNG: the start, 1 s, 2.5 s and 5 s.
const PNG_FRAMES: [u64; 4] = [0, 60, 150, 300];
/// The GIF's delay per picture (ms): five frames of 1/60 s, about real time.
const GIF_DELAY_MS: u32 = 83;

/// Keeps `frame` in `capture` if the pictures use it (every fifth frame): call it from a
/// run's [`FrameObserver`](super::FrameObserver).
pub fn capture_frame(capture: &mut Capture, frame: u64, positions: &[[f64; 3]]) {
    if frame % CAPTURE_EVERY == 0 {
        capture.push((frame, positions.to_vec()));
    }
}

/// The oblique view: `x` to the right, `z` up, `y` into the picture (shifted left and
/// up), so that chains in the `x`-`z` plane are seen side on and cloth at an angle.
fn project(p: [f64; 3]) -> (f64, f64) {
    (p[0] - 0.35 * p[1], p[2] + 0.25 * p[1])
}

/// Colour of a strain relative to `scale`: green at or below `scale / 10`, yellow at
/// `scale`, red at or above `10 scale` (log scale in between).
pub fn strain_colour(strain: f64, scale: f64) -> RGBColor {
    let r = if strain > 0.0 {
        (strain / scale).log10().clamp(-1.0, 1.0)
    } else {
        -1.0
    };
    let lerp = |a: u8, b: u8, f: f64| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    if r < 0.0 {
        let f = r + 1.0;
        RGBColor(lerp(40, 230, f), lerp(170, 200, f), lerp(60, 30, f))
    } else {
        RGBColor(lerp(230, 210, r), lerp(200, 20, r), lerp(30, 30, r))
    }
}

/// The view window of all captured frames, square, with a margin.
fn window(capture: &Capture) -> (f64, f64, f64) {
    let (mut u0, mut u1, mut v0, mut v1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (_, ps) in capture {
        for &p in ps {
            let (u, v) = project(p);
            if u.is_finite() && v.is_finite() {
                u0 = u0.min(u);
                u1 = u1.max(u);
                v0 = v0.min(v);
                v1 = v1.max(v);
            }
        }
    }
    let side = (u1 - u0).max(v1 - v0).max(1e-9) * 1.08;
    ((u0 + u1 - side) / 2.0, (v0 + v1 + side) / 2.0, side)
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    links: &[Link],
    ps: &[[f64; 3]],
    view: (f64, f64, f64),
    scale: f64,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (u0, vtop, side) = view;
    let px = |p: [f64; 3]| {
        let (u, v) = project(p);
        (
            ((u - u0) / side * SIZE as f64) as i32,
            ((vtop - v) / side * SIZE as f64) as i32,
        )
    };
    for l in links {
        let (a, b) = (ps[l.a], ps[l.b]);
        let strain = (distance(a, b) - l.rest).abs() / l.rest;
        let c = strain_colour(strain, scale);
        area.draw(&PathElement::new(vec![px(a), px(b)], c.stroke_width(2)))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Write `stem_t<time>.png` for the captured frames at 0, 1, 2.5 and 5 s, and
/// `stem.gif` of all captured frames ([`capture_frame`]) at about real time, links
/// coloured by strain relative to `scale` (e.g. the layer `eps`).
pub fn write_pictures(
    dir: &Path,
    stem: &str,
    links: &[Link],
    capture: &Capture,
    scale: f64,
) -> Result<Vec<String>, String> {
    let view = window(capture);
    let mut written = Vec::new();
    for (f, ps) in capture.iter().filter(|(f, _)| PNG_FRAMES.contains(f)) {
        let mut buf = vec![255u8; (SIZE * SIZE * 3) as usize];
        {
            let area = BitMapBackend::with_buffer(&mut buf, (SIZE, SIZE)).into_drawing_area();
            draw(&area, links, ps, view, scale)?;
            area.present().map_err(|e| e.to_string())?;
        }
        let name = format!("{stem}_t{:.2}.png", *f as f64 / 60.0);
        let file = std::fs::File::create(dir.join(&name)).map_err(|e| format!("{name}: {e}"))?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), SIZE, SIZE);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(|e| format!("{name}: {e}"))?;
        w.write_image_data(&buf)
            .map_err(|e| format!("{name}: {e}"))?;
        written.push(name);
    }
    let name = format!("{stem}.gif");
    let area = BitMapBackend::gif(dir.join(&name), (SIZE, SIZE), GIF_DELAY_MS)
        .map_err(|e| format!("{name}: {e}"))?
        .into_drawing_area();
    for (_, ps) in capture {
        draw(&area, links, ps, view, scale)?;
        area.present().map_err(|e| format!("{name}: {e}"))?;
    }
    written.push(name);
    Ok(written)
}

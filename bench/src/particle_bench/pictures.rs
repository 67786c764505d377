//! Pictures of runs: one method's PNG stills and an animated GIF of several methods side
//! by side (plotters' bitmap backend draws, the `png` and `gif` crates encode), drawn by
//! [`view`](super::view): an orthographic camera over a ground grid, links coloured by
//! strain relative to a bound with its legend, pinned and grabbed particles marked, the
//! time, the method and its worst strain so far in each frame.
//!
//! The GIF keeps each picture's exact colours (a local palette of at most 255, the
//! rarest mapped to the nearest kept one where a picture has more) and writes only the
//! rectangle that changed since the picture before, its unchanged pixels transparent:
//! the scenes' white background, grid and legend are written once.

use std::borrow::Cow;
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use dae_particles::Link;
use plotters::prelude::*;

use super::font::draw_text;
use super::scenes::ParticleScene;
use super::view::{CAMERA, Ground, Marks, PANEL, Shot, View, draw_panel, worst_strain};

/// Positions captured during a run: `(frame, positions)`.
pub type Capture = Vec<(u64, Vec<[f64; 3]>)>;

/// One method's run in a side-by-side picture.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Panel {
    /// The name printed on the panel (the method, and its setting if wanted).
    pub method: String,
    /// Its captured frames ([`capture_frame`]).
    pub capture: Capture,
}

/// Frames a run keeps for its pictures: every fifth (12 per second of the scene's 60).
const CAPTURE_EVERY: u64 = 5;
/// Frames per second of the scenes.
const FPS: f64 = 60.0;
/// The frames written as PNG: the start, 1 s, 2.5 s and 5 s.
const PNG_FRAMES: [u64; 4] = [0, 60, 150, 300];
/// The GIF's delay per picture (hundredths of a second): five frames of 1/60 s, about
/// real time.
const GIF_DELAY_CS: u16 = 8;

/// Keeps `frame` in `capture` if the pictures use it (every fifth frame): call it from a
/// run's [`FrameObserver`](super::FrameObserver).
pub fn capture_frame(capture: &mut Capture, frame: u64, positions: &[[f64; 3]]) {
    if frame % CAPTURE_EVERY == 0 {
        capture.push((frame, positions.to_vec()));
    }
}

/// The points that set the view: all finite captured positions not far from where the
/// first captured frame was (a diverged run's particles far away would shrink the rest
/// to a dot; they are drawn cut at the panel's edge).
fn sane_points(panels: &[Panel]) -> Vec<[f64; 3]> {
    let finite = |p: &[f64; 3]| p.iter().all(|c| c.is_finite());
    let Some((_, first)) = panels.iter().find_map(|p| p.capture.first()) else {
        return Vec::new();
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in first.iter().filter(|p| finite(p)) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let reach = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max) * 2.0 + 1.0;
    panels
        .iter()
        .flat_map(|p| p.capture.iter().flat_map(|(_, ps)| ps.iter()))
        .filter(|p| finite(p) && (0..3).all(|k| p[k] >= lo[k] - reach && p[k] <= hi[k] + reach))
        .copied()
        .collect()
}

/// The one view of all panels and frames.
fn view_of(panels: &[Panel], marks: &Marks) -> View {
    let points = sane_points(panels);
    View::fitting(CAMERA, Ground::under(&points, marks.ground), &points)
}

/// Each captured frame's worst strain so far (`NaN` from the first non-finite one on).
fn worst_so_far(links: &[Link], capture: &Capture) -> Vec<f64> {
    let mut worst = 0.0f64;
    capture
        .iter()
        .map(|(_, ps)| {
            let w = worst_strain(links, ps);
            worst = if worst.is_nan() || w.is_nan() {
                f64::NAN
            } else {
                worst.max(w)
            };
            worst
        })
        .collect()
}

/// What `panel` shows at `frame`: its last captured frame at or before it (index), and
/// the time it stopped at if that is before `frame`.
fn at_frame(capture: &Capture, frame: u64) -> Option<(usize, Option<f64>)> {
    let i = capture.iter().rposition(|(f, _)| *f <= frame)?;
    let last = capture.last().map(|(f, _)| *f)?;
    Some((i, (frame > last).then_some(last as f64 / FPS)))
}

/// What every frame of a picture draws from.
struct Picture<'a> {
    links: &'a [Link],
    marks: &'a Marks,
    panels: &'a [Panel],
    /// Per panel, per captured frame: the worst strain so far.
    worst: Vec<Vec<f64>>,
    view: View,
    bound: f64,
}

impl<'a> Picture<'a> {
    fn new(links: &'a [Link], marks: &'a Marks, panels: &'a [Panel], bound: f64) -> Self {
        Picture {
            links,
            marks,
            panels,
            worst: panels
                .iter()
                .map(|p| worst_so_far(links, &p.capture))
                .collect(),
            view: view_of(panels, marks),
            bound,
        }
    }

    /// Draw the frame `frame` of all panels side by side into `root`.
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
        frame: u64,
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let areas = root.split_evenly((1, self.panels.len().max(1)));
        for (k, (panel, area)) in self.panels.iter().zip(&areas).enumerate() {
            match at_frame(&panel.capture, frame) {
                Some((i, stopped)) => {
                    let shot = Shot {
                        links: self.links,
                        positions: &panel.capture[i].1,
                        t: frame as f64 / FPS,
                        method: &panel.method,
                        worst: self.worst[k][i],
                        stopped,
                        bound: self.bound,
                    };
                    draw_panel(area, &self.view, self.marks, &shot)?;
                }
                None => {
                    area.fill(&WHITE).map_err(|e| e.to_string())?;
                    draw_text(area, &panel.method, (8, 6), 2, BLACK)?;
                    draw_text(area, "no frame yet", (8, 26), 2, BLACK)?;
                }
            }
            if k > 0 {
                let h = PANEL.1 as i32;
                area.draw(&PathElement::new(
                    vec![(0, 0), (0, h)],
                    RGBColor(90, 90, 90).stroke_width(2),
                ))
                .map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    }
}

/// The frames of a side-by-side picture: every frame any panel captured, in order.
fn frames_of(panels: &[Panel]) -> Vec<u64> {
    let mut frames: Vec<u64> = panels
        .iter()
        .flat_map(|p| p.capture.iter().map(|(f, _)| *f))
        .collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// `frame` of `picture` drawn into an RGB buffer of `size` pixels.
fn render(picture: &Picture<'_>, frame: u64, size: (u32, u32)) -> Result<Vec<u8>, String> {
    let mut buf = vec![255u8; (size.0 * size.1 * 3) as usize];
    {
        let area = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        picture.draw(&area, frame)?;
        area.present().map_err(|e| e.to_string())?;
    }
    Ok(buf)
}

/// An animated GIF written picture by picture ([`GifWriter::add`]): each picture the
/// rectangle that changed since the one before, in its own exact colours.
struct GifWriter {
    encoder: gif::Encoder<BufWriter<File>>,
    size: (u32, u32),
    previous: Option<Vec<u8>>,
}

impl GifWriter {
    fn create(path: &Path, size: (u32, u32)) -> Result<GifWriter, String> {
        let file = File::create(path).map_err(|e| e.to_string())?;
        let mut encoder =
            gif::Encoder::new(BufWriter::new(file), size.0 as u16, size.1 as u16, &[])
                .map_err(|e| e.to_string())?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        Ok(GifWriter {
            encoder,
            size,
            previous: None,
        })
    }

    /// Append the picture `rgb` (`size`, RGB).
    fn add(&mut self, rgb: &[u8]) -> Result<(), String> {
        let (w, h) = (self.size.0 as usize, self.size.1 as usize);
        let pixel = |buf: &[u8], x: usize, y: usize| -> [u8; 3] {
            let i = (y * w + x) * 3;
            [buf[i], buf[i + 1], buf[i + 2]]
        };
        let changed = |x: usize, y: usize| {
            self.previous
                .as_ref()
                .is_none_or(|p| pixel(p, x, y) != pixel(rgb, x, y))
        };
        // The rectangle that changed (a pixel of it where nothing did: the delay holds).
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for y in 0..h {
            for x in 0..w {
                if changed(x, y) {
                    (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
                }
            }
        }
        if x0 >= x1 {
            (x0, y0, x1, y1) = (0, 0, 1, 1);
        }
        // Its colours, the most frequent first; the 256th index is the transparent one.
        let mut counts: HashMap<[u8; 3], u32> = HashMap::new();
        for y in y0..y1 {
            for x in x0..x1 {
                if changed(x, y) {
                    *counts.entry(pixel(rgb, x, y)).or_default() += 1;
                }
            }
        }
        let mut colours: Vec<([u8; 3], u32)> = counts.into_iter().collect();
        colours.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let kept: Vec<[u8; 3]> = colours.iter().take(255).map(|c| c.0).collect();
        let index: HashMap<[u8; 3], u8> = colours
            .iter()
            .map(|&(c, _)| {
                let dist = |k: &[u8; 3]| {
                    (0..3)
                        .map(|i| (c[i] as i32 - k[i] as i32).pow(2))
                        .sum::<i32>()
                };
                let nearest = (0..kept.len()).min_by_key(|&i| dist(&kept[i])).unwrap_or(0);
                (c, nearest as u8)
            })
            .collect();
        let transparent = kept.len() as u8;
        let mut indices = Vec::with_capacity((x1 - x0) * (y1 - y0));
        for y in y0..y1 {
            for x in x0..x1 {
                indices.push(if changed(x, y) {
                    index[&pixel(rgb, x, y)]
                } else {
                    transparent
                });
            }
        }
        let mut palette: Vec<u8> = kept.iter().flatten().copied().collect();
        palette.extend([255, 255, 255]);
        let frame = gif::Frame {
            delay: GIF_DELAY_CS,
            dispose: gif::DisposalMethod::Keep,
            transparent: self.previous.is_some().then_some(transparent),
            left: x0 as u16,
            top: y0 as u16,
            width: (x1 - x0) as u16,
            height: (y1 - y0) as u16,
            palette: Some(palette),
            buffer: Cow::Owned(indices),
            ..gif::Frame::default()
        };
        self.encoder
            .write_frame(&frame)
            .map_err(|e| e.to_string())?;
        self.previous = Some(rgb.to_vec());
        Ok(())
    }
}

/// Write `stem.gif`: the `panels` side by side (each `PANEL` pixels), one camera and
/// one window for all, every frame any of them captured at about real time; a panel
/// whose run stopped shows its last frame and the time it stopped at. Links coloured by
/// strain relative to `bound`, `marks` marked. Returns the file's name.
pub fn write_side_by_side(
    dir: &Path,
    stem: &str,
    links: &[Link],
    marks: &Marks,
    panels: &[Panel],
    bound: f64,
) -> Result<Vec<String>, String> {
    if panels.is_empty() {
        return Err(format!("{stem}: no panel"));
    }
    let picture = Picture::new(links, marks, panels, bound);
    let name = format!("{stem}.gif");
    let size = (PANEL.0 * panels.len() as u32, PANEL.1);
    let mut gif = GifWriter::create(&dir.join(&name), size).map_err(|e| format!("{name}: {e}"))?;
    for f in frames_of(panels) {
        let rgb = render(&picture, f, size).map_err(|e| format!("{name}: {e}"))?;
        gif.add(&rgb).map_err(|e| format!("{name}: {e}"))?;
    }
    Ok(vec![name])
}

/// Write `stem_t<time>.png` for the captured frames at 0, 1, 2.5 and 5 s of one
/// method's run (`panel`), drawn as one panel of [`write_side_by_side`] (whose GIF is
/// the run's animation). Returns the files' names.
pub fn write_stills(
    dir: &Path,
    stem: &str,
    links: &[Link],
    marks: &Marks,
    panel: &Panel,
    bound: f64,
) -> Result<Vec<String>, String> {
    let panels = std::slice::from_ref(panel);
    let picture = Picture::new(links, marks, panels, bound);
    let mut written = Vec::new();
    let (w, h) = PANEL;
    for f in PNG_FRAMES {
        if !panel.capture.iter().any(|(g, _)| *g == f) {
            continue;
        }
        let buf = render(&picture, f, PANEL)?;
        let name = format!("{stem}_t{:.2}.png", f as f64 / FPS);
        let file = File::create(dir.join(&name)).map_err(|e| format!("{name}: {e}"))?;
        let mut enc = png::Encoder::new(BufWriter::new(file), w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut wr = enc.write_header().map_err(|e| format!("{name}: {e}"))?;
        wr.write_image_data(&buf)
            .map_err(|e| format!("{name}: {e}"))?;
        written.push(name);
    }
    Ok(written)
}

impl Marks {
    /// The marks of `scene`: its pinned particles, its grab while held, the ground
    /// below the lowest point.
    pub fn of(scene: &ParticleScene) -> Marks {
        Marks {
            pinned: scene
                .system
                .pins()
                .iter()
                .enumerate()
                .filter_map(|(i, p)| p.as_ref().map(|_| i))
                .collect(),
            grabbed: scene
                .grab
                .iter()
                .map(|g| (g.particle, g.at, g.release))
                .collect(),
            ground: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn capture(n: u64, f: impl Fn(u64) -> Vec<[f64; 3]>) -> Capture {
        (0..n).map(|i| (i * CAPTURE_EVERY, f(i))).collect()
    }

    #[test]
    fn worst_so_far_only_grows_and_stays_nan() {
        let links = [Link {
            a: 0,
            b: 1,
            rest: 1.0,
        }];
        let lens = [1.0, 1.1, 1.05, f64::NAN, 1.0];
        let c = capture(5, |i| vec![[0.0; 3], [lens[i as usize], 0.0, 0.0]]);
        let w = worst_so_far(&links, &c);
        assert!((w[1] - 0.1).abs() < 1e-12 && (w[2] - 0.1).abs() < 1e-12);
        assert!(w[3].is_nan() && w[4].is_nan());
    }

    #[test]
    fn a_stopped_panel_shows_its_last_frame_and_a_diverged_one_does_not_set_the_view() {
        let c = capture(3, |_| vec![[0.0; 3]]);
        assert_eq!(at_frame(&c, 5), Some((1, None)));
        assert_eq!(at_frame(&c, 7), Some((1, None)));
        assert_eq!(at_frame(&c, 20), Some((2, Some(10.0 / FPS))));
        let calm = Panel {
            method: "calm".into(),
            capture: capture(3, |i| vec![[0.0; 3], [1.0, 0.0, -(i as f64) * 0.1]]),
        };
        let wild = Panel {
            method: "wild".into(),
            capture: capture(3, |i| vec![[0.0; 3], [1e17 * i as f64, f64::NAN, 0.0]]),
        };
        let pts = sane_points(&[calm.clone(), wild]);
        assert!(pts.iter().all(|p| p[0].abs() <= 1.0), "{pts:?}");
        assert_eq!(frames_of(&[calm]), vec![0, 5, 10]);
    }
}

//! The pictures of particle runs: a side-by-side GIF and one method's PNG stills of a
//! tiny two-link chain, decoded again (the GIF's pictures composed as a viewer does).

use dae_bench::particle_bench::{Capture, Marks, Panel, write_side_by_side, write_stills};
use dae_particles::Link;

fn links() -> Vec<Link> {
    vec![
        Link {
            a: 0,
            b: 1,
            rest: 1.0,
        },
        Link {
            a: 1,
            b: 2,
            rest: 1.0,
        },
    ]
}

/// A chain swinging down from `(0, 0, 0)` for `frames` captured frames (every fifth),
/// its second link stretched by `stretch` at the end.
fn swing(frames: u64, stretch: f64) -> Capture {
    (0..frames)
        .map(|i| {
            let s = i as f64 / (frames - 1).max(1) as f64;
            let a = s * std::f64::consts::FRAC_PI_2;
            let (x, z) = (a.cos(), -a.sin());
            let l2 = 1.0 + stretch * s;
            (
                i * 5,
                vec![[0.0; 3], [x, 0.0, z], [x * (1.0 + l2), 0.0, z * (1.0 + l2)]],
            )
        })
        .collect()
}

fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("dae_bench_pictures_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn marks() -> Marks {
    Marks {
        pinned: vec![0],
        grabbed: vec![(2, 0.1, 0.3)],
        ground: None,
    }
}

#[test]
fn a_side_by_side_gif_has_every_frame_and_both_panels() {
    let dir = scratch("side");
    // The second run stopped after 8 of 13 frames: its panel holds its last one.
    let panels = vec![
        Panel {
            method: "dbsmc eps=1e-2".into(),
            capture: swing(13, 0.0),
        },
        Panel {
            method: "xpbd k=16".into(),
            capture: swing(8, 0.05),
        },
    ];
    let files = write_side_by_side(&dir, "tiny", &links(), &marks(), &panels, 1e-2).unwrap();
    assert_eq!(files, ["tiny.gif"]);
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts
        .read_info(std::fs::File::open(dir.join("tiny.gif")).unwrap())
        .unwrap();
    let (w, h) = (dec.width() as usize, dec.height() as usize);
    assert_eq!((w, h), (880, 400));
    // Each picture is the rectangle that changed, its unchanged pixels transparent:
    // laid over the one before, as a viewer does.
    let mut frames = 0;
    let mut last = vec![0u8; w * h * 4];
    while let Some(f) = dec.read_next_frame().unwrap() {
        frames += 1;
        let (left, top, fw) = (f.left as usize, f.top as usize, f.width as usize);
        for (i, px) in f.buffer.chunks(4).enumerate() {
            if px[3] != 0 {
                let (x, y) = (left + i % fw, top + i / fw);
                last[(y * w + x) * 4..(y * w + x) * 4 + 4].copy_from_slice(px);
            }
        }
        if frames == 1 {
            assert_eq!((f.left, f.top, f.width, f.height), (0, 0, 880, 400));
        }
    }
    assert_eq!(frames, 13);
    assert!(last.chunks(4).all(|px| px[3] == 255), "every pixel drawn");
    // The last frame: the stopped run's strain (5 times the bound) is magenta in the
    // right panel only.
    let magenta = |px: &[u8]| px[0] > 150 && px[1] < 60 && px[2] > 150;
    let count = |x0: usize, x1: usize| {
        (0..h)
            .flat_map(|y| (x0..x1).map(move |x| (y, x)))
            .filter(|(y, x)| magenta(&last[(y * w + x) * 4..]))
            .count()
    };
    // Scene box only (the legend bar, right of x = 372 in a panel, has magenta too).
    assert_eq!(count(0, 372), 0);
    assert!(count(440, 440 + 372) > 20);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn one_methods_stills_are_png_frames_and_no_gif() {
    let dir = scratch("one");
    // 61 captured frames: 0 to 5 s.
    let panel = Panel {
        method: "xpbd k=16".into(),
        capture: swing(61, 0.0),
    };
    let files = write_stills(&dir, "one", &links(), &marks(), &panel, 1e-2).unwrap();
    assert_eq!(
        files,
        [
            "one_t0.00.png",
            "one_t1.00.png",
            "one_t2.50.png",
            "one_t5.00.png"
        ]
    );
    assert!(!dir.join("one.gif").exists());
    let dec = png::Decoder::new(std::fs::File::open(dir.join("one_t1.00.png")).unwrap());
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (440, 400));
    // Calm links are green, and something (the pin, the text) is black.
    let px: Vec<&[u8]> = buf.chunks(3).collect();
    assert!(
        px.iter()
            .filter(|p| p[0] < 60 && p[1] > 150 && p[2] < 90)
            .count()
            > 50
    );
    assert!(px.iter().any(|p| p[0] < 10 && p[1] < 10 && p[2] < 10));
    std::fs::remove_dir_all(&dir).unwrap();
}

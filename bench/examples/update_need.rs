//! How many rows a global control update serves: at each update of a run, for every
//! row, the time left before its `s_i` reaches the edge of the layer it is moving
//! towards at its current rate (the finite difference over the last step), and so the
//! interval the row would have had on its own. The frame-tied design (`dbsmc-relaxed`,
//! gains at the floor `4 eps / mu`, `mu` a quarter of the frame, crossings located) on
//! the chains and cloths of the particle benchmark, from the start to `T_END`.
//!
//! ```text
//! cargo run --release -p dae-bench --example update_need [-- T_END [TEXT ...]]
//! ```
//!
//! `T_END` in seconds (default 1), `TEXT` keeps the scenes whose title contains every
//! one given. Per scene: the updates, the mean over updates of the fraction of its own
//! interval the average row had used (`T / (T + tau_i)`, `T` the interval since the
//! last update, `tau_i` the time left), the rows that would reach their edge within one
//! more interval of the same length (`tau_i < T`), as a fraction and as a count. The
//! time left assumes the rate stays what it is; a row whose drift turns it sooner is
//! counted as not due.

use std::io;

use dae_bench::particle_bench::{RELAXED_MU_PER_FRAME, c1, c3, relaxed_settings_at};
use dae_particles::{GridPins, ParticleModel};
use dae_runtime::Simulator;
use dae_runtime::trace::{Layout, Sample, Sink};

/// The sliding variables of the last two steps, and the sums over the updates.
struct Need {
    eps: Vec<f64>,
    before: Option<(f64, Vec<f64>)>,
    last: Option<(f64, Vec<f64>)>,
    last_update: f64,
    updates: u64,
    /// Sum over updates of the mean over rows of `T / (T + tau_i)`.
    used: f64,
    /// Sum over updates of the fraction of rows with `tau_i < T`.
    due: f64,
}

impl Sink for Need {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        Ok(())
    }

    fn algebraic_outputs(&self) -> bool {
        false
    }

    fn record(&mut self, sample: &Sample<'_>) -> io::Result<()> {
        let mut kept = self.before.take().map(|(_, s)| s).unwrap_or_default();
        kept.clear();
        kept.extend_from_slice(sample.s);
        self.before = self.last.replace((sample.t, kept));
        Ok(())
    }

    fn update(&mut self, t: f64) -> io::Result<()> {
        let interval = t - self.last_update;
        self.last_update = t;
        let (Some((t1, s1)), Some((t0, s0))) = (&self.last, &self.before) else {
            return Ok(());
        };
        let dt = t1 - t0;
        if interval <= 0.0 || dt <= 0.0 {
            return Ok(());
        }
        let (mut used, mut due) = (0.0, 0usize);
        for ((&now, &then), &eps) in s1.iter().zip(s0).zip(&self.eps) {
            let rate = (now - then) / dt;
            let left = if rate == 0.0 {
                f64::INFINITY
            } else {
                ((eps * rate.signum() - now) / rate).max(0.0)
            };
            used += interval / (interval + left);
            due += usize::from(left < interval);
        }
        let rows = s1.len() as f64;
        self.used += used / rows;
        self.due += due as f64 / rows;
        self.updates += 1;
        Ok(())
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let t_end = match args.first().map(|v| v.parse::<f64>()) {
        None => 1.0,
        Some(Ok(t)) if t.is_finite() && t > 0.0 => t,
        Some(_) => {
            eprintln!("update_need: T_END must be a positive number of seconds");
            std::process::exit(2);
        }
    };
    let filters = args.get(1..).unwrap_or_default();
    let eps = 1e-2;
    let scenes = (|| -> Result<_, dae_particles::SystemError> {
        Ok(vec![
            c1(10, 1.0)?,
            c1(100, 1.0)?,
            c1(1000, 1.0)?,
            c3(16, GridPins::Corners, false)?,
            c3(32, GridPins::Corners, false)?,
        ])
    })();
    let scenes = scenes.unwrap_or_else(|e| {
        eprintln!("update_need: {e}");
        std::process::exit(1);
    });
    println!("eps = {eps:e}, from 0 to {t_end} s\n");
    println!(
        "| scene | rows | updates | mean used fraction of a row's own interval | rows due within one more interval | the same, rows | run |"
    );
    println!("|---|---|---|---|---|---|---|");
    for scene in scenes
        .iter()
        .filter(|s| filters.iter().all(|f| s.title().contains(f.as_str())))
    {
        let model = match ParticleModel::new(&scene.system) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("update_need: {}: {e}", scene.title());
                continue;
            }
        };
        let settings = relaxed_settings_at(&model, eps, 4.0, RELAXED_MU_PER_FRAME).t_end(t_end);
        let mut need = Need {
            eps: settings.layers.eps.clone(),
            before: None,
            last: None,
            last_update: 0.0,
            updates: 0,
            used: 0.0,
            due: 0.0,
        };
        let rows = need.eps.len();
        let outcome = Simulator::new(model, settings).and_then(|mut sim| sim.run(&mut need));
        let updates = need.updates.max(1) as f64;
        println!(
            "| {} | {rows} | {} | {:.3} | {:.4} | {:.1} | {} |",
            scene.title(),
            need.updates,
            need.used / updates,
            need.due / updates,
            need.due / updates * rows as f64,
            match outcome {
                Ok(_) => "ok".to_string(),
                Err(e) => format!("{e}"),
            }
        );
    }
}

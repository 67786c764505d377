//! DBSMC against its peers on the heavy-end scenes: the cheapest setting of each method
//! that held a worst strain over the whole scene, side by side.

use std::fmt::Write as _;

use super::report::{cheapest_of, grouped, scene_title};
use super::run::ParticleRecord;
use super::targets::is_sweep;

/// The peers, as they are named in the records: XPBD small steps in either sweep order,
/// Vertex Block Descent and its augmented-Lagrangian variant.
pub const PEERS: [&str; 5] = [
    "xpbd-substeps",
    "xpbd-coloured",
    "vbd",
    "avbd",
    "avbd-tuned",
];

/// The worst strains the peers table compares at.
pub const PEER_LEVELS: [f64; 2] = [1e-3, 1e-4];

/// Whether `r` is a whole-scene run of a chain with an end at least 100 times heavier
/// than its other particles (C1 r >= 1e2, the 4-pendulum C5, the ropes C6 and C7).
fn heavy_end(r: &ParticleRecord) -> bool {
    matches!(r.scene.as_str(), "C1" | "C5" | "C6" | "C7") && r.param >= 1e2 && !is_sweep(r)
}

/// The markdown section: for every heavy-end scene and every level of [`PEER_LEVELS`],
/// the cheapest DBSMC setting (any design), the cheapest setting of each of [`PEERS`],
/// and DBSMC's cost over the cheapest peer's (below 1: DBSMC is cheaper than every peer
/// at that worst strain). A method none of whose runs held the level says `none`, with
/// the least worst strain any of its complete runs reached.
pub fn peers_section(records: &[ParticleRecord]) -> String {
    let mut s = String::from(
        "\n## DBSMC against its peers on the heavy-end scenes\n\n\
         The cheapest setting of each method holding the worst strain over the whole scene \
         (complete runs; DBSMC runs that kept their s-layer), in ms per frame, and DBSMC's \
         cost over the cheapest peer's.\n\n\
         | scene | worst strain | DBSMC |",
    );
    for p in PEERS {
        let _ = write!(s, " {p} |");
    }
    s += " DBSMC / cheapest peer |\n|---|---|---|";
    s += &"---|".repeat(PEERS.len() + 1);
    s += "\n";
    for (title, runs) in grouped(records.iter().filter(|r| heavy_end(r)), scene_title) {
        // "dbsmc" stands for every DBSMC design.
        let of = |m: &'static str| {
            runs.iter()
                .copied()
                .filter(move |r| r.method == m || (m == "dbsmc" && r.method.starts_with("dbsmc")))
        };
        for level in PEER_LEVELS {
            let dbsmc = cheapest_of(of("dbsmc"), level);
            let cell = |m: &'static str, best: Option<&ParticleRecord>| match best {
                Some(r) => format!("{} {} ({:.3})", r.method, r.knob, r.ms_mean),
                None => of(m)
                    .filter(|r| r.complete())
                    .map(|r| r.worst_strain)
                    .min_by(f64::total_cmp)
                    .map_or("none ran".into(), |w| format!("none (least {w:.1e})")),
            };
            let _ = write!(s, "| {title} | {level:.0e} | {} |", cell("dbsmc", dbsmc));
            let mut cheapest_peer: Option<f64> = None;
            for p in PEERS {
                let best = cheapest_of(of(p), level);
                if let Some(r) = best {
                    cheapest_peer = Some(cheapest_peer.map_or(r.ms_mean, |c| c.min(r.ms_mean)));
                }
                let _ = write!(s, " {} |", cell(p, best));
            }
            let ratio = match (dbsmc, cheapest_peer) {
                (Some(d), Some(p)) => format!("{:.2}", d.ms_mean / p),
                (Some(_), None) => "no peer held it".into(),
                (None, _) => "-".into(),
            };
            let _ = writeln!(s, " {ratio} |");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(scene: &str, method: &str, knob: &str, strain: f64, ms: f64) -> ParticleRecord {
        ParticleRecord {
            scene: scene.into(),
            variant: "v".into(),
            size: 20,
            param: 1800.0,
            ms_mean: ms,
            ms_max: ms,
            ..ParticleRecord::for_tests(method, knob, None, strain)
        }
    }

    #[test]
    fn the_peers_table_compares_the_cheapest_holding_settings() {
        let records = vec![
            rec("C6", "dbsmc-ramp", "eps=1e-3", 5e-4, 2.0),
            rec("C6", "dbsmc-ramp", "eps=1e-4", 5e-5, 6.0),
            rec("C6", "vbd", "k=4", 8e-4, 4.0),
            rec("C6", "vbd", "k=2", 3e-3, 1.0),
            rec("C6", "avbd", "k=1", 9e-4, 3.0),
            rec("C6", "xpbd-substeps", "k=64", 2e-2, 1.0),
            // Not a heavy end: no row.
            rec("C3", "vbd", "k=1", 1e-5, 0.1),
        ];
        let s = peers_section(&records);
        let rows: Vec<&str> = s.lines().filter(|l| l.starts_with("| C")).collect();
        assert_eq!(rows.len(), 2, "{s}");
        // 1e-3: DBSMC 2.0 against AVBD's 3.0 (VBD's cheapest holding is 4.0).
        assert!(
            rows[0].contains("| 1e-3 | dbsmc-ramp eps=1e-3 (2.000) |"),
            "{s}"
        );
        assert!(rows[0].contains("vbd k=4 (4.000)"), "{s}");
        assert!(rows[0].contains("avbd k=1 (3.000)"), "{s}");
        assert!(
            s.contains("| DBSMC | xpbd-substeps | xpbd-coloured | vbd | avbd |"),
            "{s}"
        );
        assert!(rows[0].contains("none (least 2.0e-2)"), "{s}");
        assert!(rows[0].ends_with(" 0.67 |"), "{s}");
        // 1e-4: no peer held it.
        assert!(rows[1].ends_with(" no peer held it |"), "{s}");
    }
}

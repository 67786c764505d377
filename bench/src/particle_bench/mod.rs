//! The particle benchmark of docs/particles.md: scenes C1-C7, every method through the
//! [`dae_particles::Backend`] seam, the metrics, the CSV, the charts and the pictures.

mod charts;
mod draws;
mod font;
mod peers;
mod pictures;
mod pool;
mod report;
mod retime;
mod run;
mod scenes;
mod series;
mod targets;
mod view;

pub use charts::{
    HELD_BELOW, Line, Off, Outcome, Range, chart_range, loglog, loglog_marked, off_place,
    ratio_chart, strain_chart, strain_lines,
};
pub use draws::{Draws, FrameTied, NUDGES, Spread, frame_tied_draws};
pub use peers::{PEER_LEVELS, PEERS, peers_section};
pub use pictures::{Capture, Panel, capture_frame, write_side_by_side, write_stills};
pub use pool::{default_workers, parallel_map, parse_workers};
pub use report::{
    CSV_COLUMNS, bound_held, cheapest, cheapest_table, dbsmc_runs_table, fitted_exponent,
    kept_both, left_a_guarantee, records_from_csv, scene_groups, scene_title, stability_table,
    write_particles_csv,
};
pub use retime::{MAX_TIMINGS, RETIME_BELOW_MS, timed_repeatedly};
pub use run::{
    AVBD_ITERATIONS, AVBD_TUNED_K_START, FrameObserver, MethodSpec, PILOT_SAFETY, ParticleRecord,
    RELAXED_DRIFT_SAFETY, RELAXED_GRAZE_PER_MU, RELAXED_MU_PER_FRAME, RELAXED_STEP_PER_MU,
    RELAXED_TOLERANCE_PER_EPS, VBD_ITERATIONS, dbsmc_settings, drive_scene, index_one,
    particle_pilot, ramped, relaxed_settings, relaxed_settings_at, run_particle_method,
    run_relaxed_at, run_relaxed_with,
};
pub use scenes::{
    Grab, ParticleScene, SceneShape, c1, c2, c3, c3_with_slack, c4, c4_with_slack, c5, c6, c7,
    scene_of_spec,
};
pub use series::{
    NotRun, STRAIN_LEVELS, bisect_least_holding, ends_series, holding_brackets, run_series,
};
pub use targets::{SceneDraws, heavy_chain_choices, targets_section};
pub use view::{CAMERA, Camera, Ground, Marks, grid_spacing, strain_colour};

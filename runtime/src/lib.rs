//! `dae-runtime`: simulation of DAE models by discretized bounded sliding mode control.
#![warn(missing_docs)]

#[cfg(feature = "plot")]
mod charts;
mod design;
mod model;

#[cfg(feature = "plot")]
pub use charts::{
    ChartError, ErrorSeries, SlidingSeries, YScale, plot_errors, plot_periods, plot_sliding,
};
pub use design::{
    ConstraintDesign, ConstraintSpec, Design, DesignError, GainChoice, LayerBound, MAX_INDEX,
    MuSearch, PilotError, PilotEstimate, PilotEstimator, c_r, design, optimise_mu, reachable_bound,
    robust_gain, sufficient_gain, t_min,
};
pub use model::{Model, w_offsets};

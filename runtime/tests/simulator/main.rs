//! The simulator's integration tests in one binary (one build of the generic simulator, not one per file); the allocation counts and the family models have binaries of their own.

mod common;

mod display;
mod errors;
mod exact;
mod follow;
mod initial;
mod located;
mod omega_rate;
mod online;
mod pendulum;
mod pieces;
mod pilot_run;
mod point;
mod ramp;
mod rescale;
mod saturate;
mod scope;
mod start;
mod trace;
mod triggered;

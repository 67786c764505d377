//! dae-bench's integration tests in one binary (one link of the benchmark crate, not one per file); the allocation count has a binary of its own.

mod common;

mod baselines;
mod block_descent;
mod generated;
mod generated_particles;
mod harness;
mod particles;
mod pictures;
mod solvers;
mod stability;
mod standin;
mod tension;
mod truth;

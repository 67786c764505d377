//! The `dae!` macro as users meet it, compiled by trybuild: `tests/trybuild.rs` and the
//! files under `ui/`. The crate itself is empty; it exists so that trybuild's own
//! project has only the dependencies these files need.

//! The workspace tests, one module per topic, in one test binary: one link, and each kernel
//! the tests call compiled once for all of them (docs/build-time.md). Two stay apart:
//! `no_alloc` counts every allocation of its process, and `batch_kernels` turns the
//! process-wide FMA switch off and on.

#[path = "../support/mod.rs"]
mod support;

mod calibration;
mod chapter_model;
mod ci_build;
mod consistent_model;
mod delta;
mod derivatives;
mod docs_examples;
mod docs_figures;
mod docs_speed;
mod forward_dynamics;
mod freshness;
mod generated_kernels;
mod gough_stewart;
mod identification;
mod identification_from_encoders;
mod joint_space;
mod legged_identification;
mod limits;
mod ops_budget;
mod plan;
mod rus_hexapod;

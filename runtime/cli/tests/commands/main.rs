//! The `c5` program's tests, one module per command or topic, in one test binary (one link;
//! docs/build-time.md). Each runs the program built with every command (`full`).

#[path = "../support/mod.rs"]
mod support;

mod calibrate_cli;
mod cli_files;
mod conventions;
mod derivatives_cli;
mod doc_commands;
mod eval_cli;
mod export_cli;
mod forward_track;
mod gough_stewart_cli;
mod identify_cli;
mod limits_cli;
mod view_cli;

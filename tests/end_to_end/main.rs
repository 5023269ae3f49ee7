//! The tool's end-to-end tests: the binary as a real process (its commands, `serve` and its
//! stores, sweeps, hostile input), and the library's doors as a user meets them. Each file
//! is a module of this one test binary, so that the workspace links one binary for them
//! all instead of one per file; run one file's tests with
//! `cargo test --test end_to_end cli_stated::`.

mod support;

mod benchmark_report;
mod builtin_populations;
mod case_base_safety;
mod cli_cases;
mod cli_competence;
mod cli_contexts;
mod cli_experiments;
mod cli_goal_changes;
mod cli_population;
mod cli_render;
mod cli_simulate;
mod cli_stated;
mod cli_sweep;
#[cfg(feature = "console")]
mod console_cli;
mod controller_example;
mod hostile_arms;
mod hostile_bounds;
mod hostile_input;
mod hostile_names;
mod hostile_writers;
mod mission_attention;
mod missions_cli;
mod serve_cli;
mod serve_durability;
mod serve_fleet;
mod serve_mission;
mod serve_tcp;
mod strategy_registry;
mod sweep_limits;
mod sweep_merge;

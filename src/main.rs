//! `trustcbr`: the command-line front end. Argument parsing and glue only; the work is
//! done by the `trust` and `domains` libraries.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use domains::{Scenario, UgvDomain, find_operator, landscape};
use std::path::PathBuf;
use trust::Domain;

/// Trust-guided behavior adaptation with case-based reasoning.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate one run and draw it as SVG.
    Render {
        /// `movement` or `patrol`.
        #[arg(long)]
        scenario: Scenario,
        /// The behavior, e.g. `speed=3.5,padding=0.4` (patrol adds `scan_time`, `scan_distance`).
        #[arg(long)]
        behavior: String,
        /// Seed of the run.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Operator judging the run: a built-in name or a RON file (default: the first
        /// built-in operator of the scenario).
        #[arg(long)]
        operator: Option<String>,
        /// Output SVG file.
        #[arg(short = 'o', long, default_value = "run.svg")]
        output: PathBuf,
    },
    /// Estimate, for every behavior, how often an operator lets a run complete; write
    /// `landscape.svg` (heatmap) and `landscape.csv`.
    Landscape {
        /// `movement` or `patrol`.
        #[arg(long)]
        scenario: Scenario,
        /// Operator: a built-in name or a RON file.
        #[arg(long)]
        operator: String,
        /// Runs per behavior.
        #[arg(long, default_value_t = 100)]
        runs: u32,
        /// The two components of the heatmap, across then up.
        #[arg(long, default_value = "speed,padding")]
        components: String,
        /// Master seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Output directory.
        #[arg(long, default_value = ".")]
        out: PathBuf,
    },
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Render {
            scenario,
            behavior,
            seed,
            operator,
            output,
        } => {
            let domain = UgvDomain::new(scenario);
            let behavior = domain.space().parse(&behavior)?;
            let operator = match operator {
                Some(name) => find_operator(scenario, &name)?,
                None => domains::builtin_operators(scenario).remove(0),
            };
            let svg = domains::render_run(&domain, &behavior, &operator, seed);
            cbr_core::write_atomically(&output, svg.as_bytes())
                .with_context(|| format!("writing {}", output.display()))?;
            println!("wrote {}", output.display());
        }
        Command::Landscape {
            scenario,
            operator,
            runs,
            components,
            seed,
            out,
        } => {
            let domain = UgvDomain::new(scenario);
            let operator = find_operator(scenario, &operator)?;
            let space = domain.space();
            let (x, y) = landscape::axes(space, &components)?;
            let estimate = landscape::estimate(&domain, &operator, runs, seed);
            let title = format!(
                "{scenario}, operator {}, {runs} runs per behavior",
                operator.name
            );
            let svg = estimate.heatmap_svg(space, x, y, &title)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            for (name, bytes) in [
                ("landscape.svg", svg.into_bytes()),
                ("landscape.csv", estimate.csv(space).into_bytes()),
            ] {
                let path = out.join(name);
                cbr_core::write_atomically(&path, &bytes)
                    .with_context(|| format!("writing {}", path.display()))?;
                println!("wrote {}", path.display());
            }
        }
    }
    Ok(())
}

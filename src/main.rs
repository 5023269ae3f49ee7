//! `trustcbr`: the command-line front end. Argument parsing and glue only; the work is
//! done by the `trust` and `domains` libraries.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use domains::suite::PAPER_CONFIG;
use domains::{SuiteConfig, run_suite, suite_table, write_suite_report};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::num::{NonZeroU32, NonZeroUsize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Trust-guided behavior adaptation with case-based reasoning.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Reproduce the paper's seven experiments (the embedded config; see `config`).
    Reproduce(RunOptions),
    /// Run the experiments of a config file (start from `trustcbr config`).
    Run {
        /// The experiment config (RON).
        config: PathBuf,
        #[command(flatten)]
        options: RunOptions,
    },
    /// Print the embedded config of the paper's experiments.
    Config,
}

/// Options shared by `reproduce` and `run`.
#[derive(Args)]
struct RunOptions {
    /// Report folder.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Trials per experiment and strategy (overrides the config).
    #[arg(long)]
    trials: Option<NonZeroU32>,
    /// Master seed (overrides the config).
    #[arg(long)]
    seed: Option<u64>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<NonZeroUsize>,
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Reproduce(options) => {
            run_experiments(SuiteConfig::paper(), Path::new("."), &options)
        }
        Command::Run { config, options } => {
            run_experiments(SuiteConfig::load(&config)?, &config, &options)
        }
        Command::Config => {
            print!("{PAPER_CONFIG}");
            Ok(())
        }
    }
}

/// Runs a suite with progress bars on stderr, prints the table and writes the report.
fn run_experiments(mut config: SuiteConfig, origin: &Path, options: &RunOptions) -> Result<()> {
    if let Some(trials) = options.trials {
        config.trials = trials;
    }
    if let Some(seed) = options.seed {
        config.seed = seed;
    }
    let threads = options.threads.map_or_else(
        || std::thread::available_parallelism().map_or(1, NonZeroUsize::get),
        NonZeroUsize::get,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the worker threads")?;
    // Drawn only when stderr is a terminal.
    let bars = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
    let style =
        ProgressStyle::with_template("{prefix:>26} [{bar:40}] {pos}/{len} trials {elapsed}")
            .expect("a valid template")
            .progress_chars("=> ");
    let progress: Vec<ProgressBar> = config
        .experiments
        .iter()
        .map(|spec| {
            bars.add(
                ProgressBar::new(2 * u64::from(config.trials.get()))
                    .with_style(style.clone())
                    .with_prefix(spec.name()),
            )
        })
        .collect();
    let started = Instant::now();
    let results = pool.install(|| run_suite(&config, origin, &|i| progress[i].inc(1)))?;
    let elapsed = started.elapsed().as_secs_f64();
    for bar in &progress {
        bar.finish();
    }
    println!("{}", suite_table(&config, &results));
    let written = write_suite_report(&options.out, &config, &results, elapsed)?;
    println!(
        "{} experiments x {} trials x 2 strategies on {threads} threads in {elapsed:.1} s; report in {} ({} files)",
        config.experiments.len(),
        config.trials,
        options.out.display(),
        written.len()
    );
    Ok(())
}

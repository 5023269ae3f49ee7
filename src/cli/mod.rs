//! The command-line tool over any [`Catalog`]: argument parsing and glue only; the work is
//! done by the suite, the sweep and the `trust` and `service` libraries.
//!
//! [`main`] is the whole tool: `reproduce`, `run`, `config`, `sweep`, `render`,
//! `simulate`, `landscape`, `competence`, `population`, `serve`, `cases`, `explain` and
//! (with the `console` feature) `console`, for the catalog's scenarios. The shipped
//! `trustcbr` binary is `main(UgvCatalog)`; a user's crate gets the same tool for its own
//! domains with `fn main() -> ExitCode { trustcbr::cli::main(MyCatalog) }`.
//!
//! This module holds the command line's definitions and `main`; each command's handler
//! lives with its family: the suites in `experiments`, the robot-facing commands in
//! `robot`, the looks at one piece of the simulation in `inspect`, trust studies with
//! people in `console`.

use crate::catalog::Catalog;
use crate::limits::{LANDSCAPE_RUNS, RUNS_PER_BEHAVIOR, SIMULATED_COMMANDS, THREADS, TRIALS};
use crate::suite::{EMBEDDED_ORIGIN, SuiteConfig};
use anyhow::Result;
use clap::builder::TypedValueParser;
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use lab::{ArmName, Instance};
use service::Limits;
use std::net::SocketAddr;
use std::num::{NonZeroU32, NonZeroU64, NonZeroUsize};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[cfg(feature = "console")]
mod console;
mod experiments;
mod inspect;
mod robot;

use experiments::{run_experiments, run_file, sweep};
use inspect::{competence, landscape, population, render, simulate};
use robot::{cases, explain, serve};

/// The command line; name, version and description come from the catalog.
#[derive(Parser)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the embedded suite (see `config`).
    Reproduce(RunOptions),
    /// Run the experiments of a config file (start from the output of `config`).
    Run {
        /// The experiment config (RON).
        config: PathBuf,
        #[command(flatten)]
        options: RunOptions,
    },
    /// Print the embedded suite config, to copy and edit.
    Config,
    /// Simulate one run and draw it as SVG.
    Render(RenderArgs),
    /// Simulate commands of one behavior in front of one operator, with no adapter, and
    /// print each as a JSON line: the outcome as a controller reports it (outcome, weight,
    /// duration_s, observed, stated) and the operator's true reason (truth).
    Simulate(SimulateArgs),
    /// Estimate, for every behavior, how often an operator lets a run complete; write
    /// `landscape.svg` (heatmap) and `landscape.csv`.
    Landscape(LandscapeArgs),
    /// Measure how well the robot judges its own competence: its estimates of behaviors
    /// drawn from the space against the simulator's truth; write `competence.md` and
    /// `competence.json`.
    Competence(CompetenceArgs),
    /// Draw an instance of the scenario's prior over operators and write its members as
    /// operator files, `OUT/MEMBER.ron`, which `landscape --operator` and a suite's
    /// `operator_files` read.
    Population(PopulationArgs),
    /// Serve the online adapter to a robot controller over JSON lines (the protocol:
    /// `serve --help`).
    #[command(after_long_help = PROTOCOL_IN_SHORT)]
    Serve(ServeArgs),
    /// Run a suite over several seeds and parameter values and aggregate across seeds
    /// (`sweep FILE.ron`), or merge the folders of its shards (`sweep merge FILE.ron DIR...`).
    Sweep(SweepArgs),
    /// Case bases: export to RON, import from RON, describe.
    #[command(subcommand)]
    Cases(CasesCommand),
    /// Tell one trial of a report: every behavior, its commands, the trust estimate after
    /// each, and the explanation of every switch (replayed from the report's config).
    Explain(ExplainArgs),
    /// Serve a trust study to participants' browsers: a person is the operator
    /// (docs/studies.md); `console export` and `console report` read a study's database.
    #[cfg(feature = "console")]
    Console(console::ConsoleArgs),
}

/// The protocol `serve` speaks, in short, for `serve --help`: a plug-in's user has the tool,
/// not trustcbr's source, so the help says where the whole text is for every tool built on
/// this library.
const PROTOCOL_IN_SHORT: &str = r#"The protocol, in short: one JSON object per line each way, one reply line per request line.
  {"request": "begin"}    starts an episode (with "behavior": {"NAME": VALUE, ...} in real
                          units, or the server draws one)
  {"outcome": "completed" | "failed" | "interrupted", "weight": 1.0, "duration_s": 8.5,
   "observed": [...], "stated": CAUSE}
                          after every command; the reply's "ok" is "keep", "switch" (use its
                          "behavior" from now on) or "settled" (and "alert" with --mission)
  {"request": "config"}   the behavior space, the causes and the observations served
  {"request": "state" | "explain" | "cases" | "abandon"}
An error is answered {"error": "..."} and changes nothing.

The protocol in full: the page `service::protocol` of the rustdoc of the `service` crate
(`cargo doc -p service --open` where this tool is built), which is docs/protocol.md in the
trustcbr source."#;

#[derive(Args)]
struct ExplainArgs {
    /// A report folder written by `reproduce`, `run` or `sweep` (its `config.ron` is read).
    report: PathBuf,
    /// The experiment, by its name in the report (`summary.json` lists them).
    #[arg(long, value_parser = text())]
    experiment: String,
    /// The arm, by name (e.g. `case-based`).
    #[arg(long, value_parser = text())]
    arm: String,
    /// The trial, from 0.
    #[arg(long)]
    trial: u32,
    /// The saved case bases the run started from, if it was given `--cases DIR`.
    #[arg(long, value_name = "DIR")]
    cases: Option<PathBuf>,
}

#[derive(Subcommand)]
enum CasesCommand {
    /// Write a case base (with its domain and behavior space) to a RON file.
    Export {
        /// The case base: an SQLite file, a postgres:// URL or a RON file.
        #[arg(value_parser = text())]
        cases: String,
        /// The RON file to write (`*.ron`): absent, or an earlier export to replace; never
        /// the case base itself nor any other file.
        out: PathBuf,
    },
    /// Append the cases of a RON file to a case base (created when absent).
    Import {
        /// The RON case file.
        input: PathBuf,
        /// The case base: an SQLite file or a postgres:// URL.
        #[arg(value_parser = text())]
        cases: String,
        /// The domain the cases were learned in: a scenario name or a RON domain file.
        #[arg(long, value_parser = text())]
        domain: String,
    },
    /// Describe a case base: its domain, behavior space and cases.
    Info {
        /// The case base: an SQLite file, a postgres:// URL or a RON file.
        #[arg(value_parser = text())]
        cases: String,
    },
}

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
struct SweepArgs {
    #[command(subcommand)]
    merge: Option<SweepCommand>,
    /// The sweep config (RON).
    file: Option<PathBuf>,
    /// The sweep's folder: its `sweep.ron`, its run files (`runs/`) and its report folder
    /// (`report/`).
    #[arg(long, default_value = "sweep")]
    out: PathBuf,
    /// Run only shard I of N (every N-th run, from the I-th) and write its run files; merge
    /// the shard folders with `sweep merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    /// Worker threads, 1 to 256 (default: one per core).
    #[arg(long, value_parser = at_most::<NonZeroUsize>(THREADS.max))]
    threads: Option<NonZeroUsize>,
}

#[derive(Subcommand)]
enum SweepCommand {
    /// Combine the run files of shard folders into the sweep's report.
    Merge {
        /// The sweep config the shards ran.
        file: PathBuf,
        /// The shard folders.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// The folder of the merged report, which is written into its `report/` (as a
        /// sweep's is).
        #[arg(long, default_value = "sweep")]
        out: PathBuf,
    },
}

/// Parses `I/N` with `1 <= I <= N`.
fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    let (i, n) = text
        .split_once('/')
        .ok_or_else(|| format!("`{text}` is not I/N (e.g. 2/8)"))?;
    let i: usize = i
        .trim()
        .parse()
        .map_err(|_| format!("`{i}` is not a number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("`{n}` is not a number"))?;
    if n == 0 || i == 0 || i > n {
        return Err(format!("shard {i}/{n}: I must be 1 to N, and N at least 1"));
    }
    Ok((i, n))
}

#[derive(Args)]
struct RenderArgs {
    /// The scenario, by the tool's name for it (an unknown name is refused with the list).
    #[arg(long, value_parser = text())]
    scenario: String,
    /// The behavior: every component of the scenario's space as NAME=VALUE, comma-separated
    /// (`config` shows the components).
    #[arg(long, value_parser = text())]
    behavior: String,
    /// Seed of the run.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Operator judging the run: a built-in name or an operator file (default: the first
    /// built-in operator of the scenario).
    #[arg(long, value_parser = text())]
    operator: Option<String>,
    /// Output SVG file (`--out` too, as the other commands name theirs).
    #[arg(short = 'o', long, visible_alias = "out", default_value = "run.svg")]
    output: PathBuf,
}

#[derive(Args)]
struct SimulateArgs {
    /// The scenario, by the tool's name for it (an unknown name is refused with the list).
    #[arg(long, value_parser = text())]
    scenario: String,
    /// Operator judging the commands: a built-in name or an operator file.
    #[arg(long, value_parser = text())]
    operator: String,
    /// The behavior: every component of the scenario's space as NAME=VALUE, comma-separated
    /// (`config` shows the components).
    #[arg(long, value_parser = text())]
    behavior: String,
    /// Seed: the commands are drawn one after the other from its stream (the first is
    /// Python's `trustcbr.simulate(..., seed=N)`).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Commands to simulate, 1 to 1000000.
    #[arg(long, default_value_t = NonZeroU64::MIN, value_parser = at_most::<NonZeroU64>(SIMULATED_COMMANDS.max))]
    count: NonZeroU64,
    /// The operator's attention, in [0, 1]: the chance it notices a problem it would react
    /// to (1, the default: the paper's attentive operator; a problem it overlooks lets the
    /// command go on, named as `overlooked`).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    attention: f64,
}

#[derive(Args)]
struct LandscapeArgs {
    /// The scenario, by the tool's name for it (an unknown name is refused with the list).
    #[arg(long, value_parser = text())]
    scenario: String,
    /// Operator: a built-in name or an operator file.
    #[arg(long, value_parser = text())]
    operator: String,
    /// Runs per behavior, 1 to 10000.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(RUNS_PER_BEHAVIOR.min as i64..=RUNS_PER_BEHAVIOR.max as i64))]
    runs: u32,
    /// The two components of the heatmap, across then up (default: the first two).
    #[arg(long, value_parser = text())]
    components: Option<String>,
    /// Master seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output directory.
    #[arg(long, default_value = ".")]
    out: PathBuf,
}

#[derive(Args)]
struct CompetenceArgs {
    /// The scenario, by the tool's name for it (an unknown name is refused with the list).
    #[arg(long, value_parser = text())]
    scenario: String,
    /// The operator in front of whom the robot runs its commands (its interruptions cut
    /// them short): a built-in name or an operator file.
    #[arg(long, value_parser = text())]
    operator: String,
    /// Behaviors drawn uniformly from the space, 1 to 100000.
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    behaviors: u32,
    /// After how many commands of a behavior the robot's estimate is taken, increasing,
    /// each at most 10000 (0: its models and its record of other behaviors alone).
    #[arg(long, default_value = "0,10,50", value_delimiter = ',', value_parser = clap::value_parser!(u32).range(0..=10_000))]
    seen: Vec<u32>,
    /// Whole commands per behavior behind its truth, 1 to 100000.
    #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    truth_runs: u32,
    /// The standard: the most any part may fall short per command, in [0, 1].
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    standard: f64,
    /// Master seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output directory.
    #[arg(long, default_value = ".")]
    out: PathBuf,
}

#[derive(Args)]
struct PopulationArgs {
    /// The scenario, by the tool's name for it (an unknown name is refused with the list).
    #[arg(long, value_parser = text())]
    scenario: String,
    /// The instance: `dev-K` to develop on (seed K), `eval-K` to evaluate on (seed
    /// 1000000000 + K); K from 0 to 999999.
    #[arg(long)]
    instance: Instance,
    /// Output folder: created if missing; it may hold only this population's files (the
    /// same command again rewrites them).
    #[arg(long, default_value = "population")]
    out: PathBuf,
    /// Write each member's first draw, without the screen against members no behavior
    /// satisfies (to see what the screen removes).
    #[arg(long)]
    unscreened: bool,
}

/// A parser of an argument that is text: a name, a URL, or a name that may be a file's
/// (`--operator`, `--domain`, a case base). One that is not UTF-8 is refused as clap
/// refuses any bad value, naming the argument (clap's own parser says only that some
/// argument was not UTF-8); a path given alone (`--out`, a config file) may be any bytes.
fn text() -> impl TypedValueParser<Value = String> {
    clap::builder::OsStringValueParser::new().try_map(|value| {
        value.into_string().map_err(|_| {
            "not UTF-8: names, URLs and files named beside names are read as text (a path given alone, such as --out or a config file, may be any bytes)"
        })
    })
}

/// The command line as given, whatever its bytes: a path need not be UTF-8
/// (`std::env::args` would panic on one that is not).
fn command_line() -> Vec<String> {
    std::env::args_os()
        .map(|arg| arg.to_string_lossy().into_owned())
        .collect()
}

/// One name of `--arms`, read: an empty one is a stray comma, refused as the option's
/// fault, and so are suffixes written twice or out of order.
fn arm_name(name: &str) -> Result<ArmName, String> {
    if name.is_empty() {
        Err("an empty arm name (a stray comma?)".to_owned())
    } else {
        ArmName::parse(name).map_err(|e| e.to_string())
    }
}

/// Options shared by `reproduce` and `run`.
#[derive(Args)]
struct RunOptions {
    /// Report folder.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Trials per experiment and arm, 1 to 100000 (overrides the config).
    #[arg(long, value_parser = at_most::<NonZeroU32>(TRIALS.max))]
    trials: Option<NonZeroU32>,
    /// The arms to compare, by name, comma-separated (overrides the config), e.g.
    /// `random-walk,case-based`.
    #[arg(long, value_delimiter = ',', value_parser = text().try_map(|name| arm_name(&name)))]
    arms: Option<Vec<ArmName>>,
    /// Save the case base each case-reusing arm ends every experiment with, as
    /// `DIR/EXPERIMENT/ARM.ron`.
    #[arg(long, value_name = "DIR")]
    save_cases: Option<PathBuf>,
    /// Start case-reusing arms from the case bases saved in DIR by `--save-cases`.
    #[arg(long, value_name = "DIR")]
    cases: Option<PathBuf>,
    /// Master seed (overrides the config).
    #[arg(long)]
    seed: Option<u64>,
    /// Runs per cell of the operator landscapes behind the final behaviors, 0 (none) to
    /// 10000 (overrides the config).
    #[arg(long, value_parser = clap::value_parser!(u32).range(LANDSCAPE_RUNS.min as i64..=LANDSCAPE_RUNS.max as i64))]
    landscape_runs: Option<u32>,
    /// Worker threads, 1 to 256 (default: one per core).
    #[arg(long, value_parser = at_most::<NonZeroUsize>(THREADS.max))]
    threads: Option<NonZeroUsize>,
}

/// A parser of a count from 1 to `max`.
fn at_most<T: TryFrom<NonZeroU64> + Clone + Send + Sync + 'static>(
    max: u64,
) -> impl TypedValueParser<Value = T> {
    clap::value_parser!(u64).range(1..=max).try_map(|n| {
        NonZeroU64::new(n)
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| format!("{n} does not fit this machine"))
    })
}

#[derive(Args)]
struct ServeArgs {
    /// A scenario name (the tool lists them), or a RON domain file declaring a behavior space
    /// (and optionally the adapter config).
    #[arg(long, value_parser = text())]
    domain: String,
    /// The case base: an SQLite file (created when absent), a postgres:// URL, or a RON
    /// file (served read-only).
    #[arg(long, value_parser = text())]
    cases: String,
    /// The arm whose strategy is served: a built-in arm or one the tool's catalog adds (the
    /// same names as `--arms`), e.g. `case-based+conditioned` (its searcher, its retriever,
    /// whether it reuses cases); `domain` serves the domain's own adapter config. The
    /// default is the recommended arm (README, "Which arm").
    #[arg(long, value_name = "NAME", value_parser = text(), default_value = lab::RECOMMENDED_ARM)]
    arm: String,
    /// Mission mode: after an episode settles, keep answering outcomes for the settled
    /// behavior, adapt again when its trust falls, and alert when the operator trusts it
    /// while the robot's own record says it should not (a domain file's deprecated
    /// `adapter: (mode: mission)` does the same). The default is the paper's episode mode.
    #[arg(long)]
    mission: bool,
    /// With --mission, the robot judges its own competence (a scenario's parts and models,
    /// docs/missions.md#overtrust-second-design): at most AT_MOST per command in every
    /// part, in [0, 1]; a settled behavior the operator trusts while the robot is surely
    /// short of it draws an `overtrust` reply once; with `--arm NAME+competent`, episodes
    /// pass over such a behavior once and search on.
    #[arg(
        long,
        value_name = "AT_MOST",
        requires = "mission",
        allow_negative_numbers = true
    )]
    competence: Option<f64>,
    /// With --mission, a change detector beside the thresholds: a settled behavior is also
    /// given up when a sequential test of its own record finds its rate of untrustworthy
    /// commands has risen (a CUSUM allowing one false alarm per 8,000 watched commands;
    /// docs/missions.md#a-change-detector).
    #[arg(long, requires = "mission")]
    detect_changes: bool,
    /// Listen on this loopback address (e.g. 127.0.0.1:7878; port 0 picks one) instead of
    /// stdin/stdout. Each connection is its own controller, served concurrently.
    #[arg(long)]
    listen: Option<SocketAddr>,
    /// Seed of the adapter's search and of the behaviors the server draws (TCP connection
    /// k, from 0, uses seed + k).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// TCP: connections served at once; more are refused with an error line.
    #[arg(long, default_value_t = NonZeroUsize::new(Limits::default().max_connections).expect("the default is > 0"))]
    max_connections: NonZeroUsize,
    /// TCP: seconds a connection may stay silent, or take to send a line once begun, before
    /// it is closed; more than 0, at most 86400 (a day).
    #[arg(long, default_value_t = Limits::default().read_timeout.as_secs_f64(), allow_negative_numbers = true)]
    idle_timeout: f64,
    /// TCP: seconds a reply may wait for the controller to read it before the connection
    /// is closed; more than 0, at most 86400 (a day).
    #[arg(long, default_value_t = Limits::default().write_timeout.as_secs_f64(), allow_negative_numbers = true)]
    write_timeout: f64,
}

/// Runs the command-line tool over `catalog` with the process's arguments, printing any
/// error to stderr; returns the process's exit code.
pub fn main<C: Catalog>(catalog: C) -> ExitCode {
    let tool = catalog.tool();
    let matches = Cli::command()
        .name(tool.name.clone())
        .bin_name(tool.name.clone())
        .version(tool.version.clone())
        .about(tool.about.clone())
        .get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        #[cfg(feature = "console")]
        Command::Console(args) => console::console(&catalog, args),
        Command::Reproduce(options) => SuiteConfig::embedded(&catalog)
            .map_err(Into::into)
            .and_then(|suite| {
                run_experiments(&catalog, suite, Path::new(EMBEDDED_ORIGIN), &options)
            }),
        Command::Run { config, options } => run_file(&catalog, &config, &options),
        Command::Config => {
            print!("{}", catalog.default_suite());
            Ok(())
        }
        Command::Render(args) => render(&catalog, &args),
        Command::Simulate(args) => simulate(&catalog, &args),
        Command::Landscape(args) => landscape(&catalog, &args),
        Command::Competence(args) => competence(&catalog, &args),
        Command::Population(args) => population(&catalog, &args),
        Command::Serve(args) => serve(&catalog, &args),
        Command::Sweep(args) => sweep(&catalog, &args),
        Command::Cases(command) => cases(&catalog, &command),
        Command::Explain(args) => explain(&catalog, &args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

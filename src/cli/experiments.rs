//! The commands that run suites: `reproduce` and `run` (experiment and mission suites)
//! and `sweep` (a suite over seeds, in shards).

use crate::catalog::Catalog;
use crate::mission_suite::{MissionSuiteConfig, is_mission_suite};
use crate::progress::Progress;
use crate::run::{
    MissionSettings, RunSettings, missions_per_plan, run_missions_with_report, run_with_report,
    worker_pool,
};
use crate::suite::{StartingCases, SuiteConfig, suite_best_arms, suite_table};
use anyhow::{Context, Result};
use std::path::Path;
use std::time::Instant;

use super::{RunOptions, SweepArgs, SweepCommand, command_line};

/// Runs the suite in the file `path`: an experiment suite, or a mission suite (a
/// `missions` field).
pub(super) fn run_file<C: Catalog>(catalog: &C, path: &Path, options: &RunOptions) -> Result<()> {
    if is_mission_suite(&files::read_text(path)?) {
        let config = MissionSuiteConfig::load(catalog, path)?;
        return run_mission_file(catalog, config, path, options);
    }
    let suite = SuiteConfig::load(catalog, path)?;
    run_experiments(catalog, suite, path, options)
}

/// Runs a mission suite with progress bars on stderr and writes its report; options that
/// only experiments have are refused.
pub(super) fn run_mission_file<C: Catalog>(
    catalog: &C,
    mut config: MissionSuiteConfig,
    origin: &Path,
    options: &RunOptions,
) -> Result<()> {
    let experiments_only = [
        ("--trials", options.trials.is_some()),
        ("--landscape-runs", options.landscape_runs.is_some()),
        ("--cases", options.cases.is_some()),
        ("--save-cases", options.save_cases.is_some()),
    ];
    if let Some((flag, _)) = experiments_only.iter().find(|(_, given)| *given) {
        anyhow::bail!(
            "{flag} applies to experiment suites; {} is a mission suite (its plans set `count` and `commands`)",
            origin.display()
        );
    }
    if let Some(seed) = options.seed {
        config.seed = seed;
    }
    if let Some(arms) = &options.arms {
        config.arms = arms.clone();
    }
    let progress = Progress::new("mission", &missions_per_plan(&config));
    let settings = MissionSettings {
        out: Some(options.out.clone()),
        threads: options.threads,
        command_line: command_line(),
    };
    let ran = run_missions_with_report(
        catalog,
        config,
        origin,
        &settings,
        &|i| progress.tick(i),
        &|| Ok(()),
    )?;
    let (config, written) = (&ran.config, &ran.written);
    let (threads, elapsed) = (ran.threads, ran.elapsed_s);
    print!("{}", ran.table_md());
    println!(
        "{} mission plans x {} arms on {threads} threads in {elapsed:.1} s; report in {} ({} files)",
        config.missions.len(),
        config.arms.len(),
        options.out.display(),
        written.len()
    );
    Ok(())
}

/// Runs a suite with progress bars on stderr, prints the table and writes the report.
pub(super) fn run_experiments<C: Catalog>(
    catalog: &C,
    mut config: SuiteConfig,
    origin: &Path,
    options: &RunOptions,
) -> Result<()> {
    if let Some(trials) = options.trials {
        config.trials = trials;
    }
    if let Some(seed) = options.seed {
        config.seed = seed;
    }
    if let Some(runs) = options.landscape_runs {
        config.landscape_runs = runs;
    }
    if let Some(arms) = &options.arms {
        config.arms = arms.clone();
    }
    let settings = RunSettings {
        out: Some(options.out.clone()),
        starting: options
            .cases
            .as_ref()
            .map(|dir| StartingCases { dir: dir.clone() }),
        save_cases: options.save_cases.clone(),
        threads: options.threads,
        // As given, whatever its bytes: a path need not be UTF-8 (`std::env::args` would
        // panic on one that is not).
        command_line: command_line(),
    };
    let per_experiment = config.arms.len() as u64 * u64::from(config.trials.get());
    let parts: Vec<(String, u64)> = config
        .experiments
        .iter()
        .map(|spec| (spec.name(), per_experiment))
        .collect();
    let progress = Progress::new("trial", &parts)
        .with_afterwards("finishing the report's landscapes and limits");
    let ran = run_with_report(catalog, config, origin, &settings, &|i| progress.tick(i))?;
    let (config, results) = (&ran.config, &ran.results);
    println!("{}", suite_table(config, results));
    print!("{}", suite_best_arms(config, results));
    println!(
        "Every arm, with what it costs the operator: table.md and report.html in the report.\n"
    );
    println!(
        "{} experiments x {} trials x {} arms on {} threads in {:.1} s; report in {} ({} files)",
        config.experiments.len(),
        config.trials,
        config.arms.len(),
        ran.threads,
        ran.elapsed_s,
        options.out.display(),
        ran.written.len()
    );
    if let Some(dir) = &options.save_cases {
        println!("saved {} case bases in {}", ran.saved.len(), dir.display());
    }
    Ok(())
}

/// Runs, merges or lists a sweep of a suite over seeds.
pub(super) fn sweep<C: Catalog>(catalog: &C, args: &SweepArgs) -> Result<()> {
    use crate::sweep::{
        REPORT_DIR, Sweep, merge, prepare_dir, remove_earlier_sweep, write_config, write_run,
    };
    if let Some(SweepCommand::Merge { file, dirs, out }) = &args.merge {
        let sweep = Sweep::load(catalog, file)?;
        let text = files::read_text(file)?;
        prepare_dir(out)?;
        let written = merge(&sweep, &text, dirs, out)?;
        println!(
            "merged {} runs from {} folders; report in {} ({} files)",
            sweep.runs().len(),
            dirs.len(),
            out.join(REPORT_DIR).display(),
            written.len()
        );
        return Ok(());
    }
    let file = args.file.as_ref().with_context(|| {
        format!(
            "name the sweep config: {} sweep FILE.ron",
            catalog.tool().name
        )
    })?;
    let sweep = Sweep::load(catalog, file)?;
    let text = files::read_text(file)?;
    prepare_dir(&args.out)?;
    let runs = match args.shard {
        Some((i, n)) => sweep.shard(i, n),
        None => sweep.runs(),
    };
    let (pool, threads) = worker_pool(args.threads)?;
    let progress = Progress::new(
        "trial",
        &[(
            format!("sweep ({} runs)", runs.len()),
            sweep.trials_in(&runs),
        )],
    );
    let started = Instant::now();
    remove_earlier_sweep(&args.out, &text)?;
    write_config(&args.out, &text)?;
    for &run in &runs {
        let summary = pool.install(|| sweep.run(catalog, run, &|| progress.tick(0)))?;
        write_run(&args.out, &sweep, run, &summary)?;
    }
    let elapsed = started.elapsed().as_secs_f64();
    if args.shard.is_some() {
        println!(
            "{} runs of {} on {threads} threads in {elapsed:.1} s; run files in {} (merge with `{} sweep merge {} DIR...`)",
            runs.len(),
            sweep.runs().len(),
            args.out.display(),
            catalog.tool().name,
            file.display()
        );
        return Ok(());
    }
    let written = merge(&sweep, &text, std::slice::from_ref(&args.out), &args.out)?;
    println!(
        "{} cells x {} seeds on {threads} threads in {elapsed:.1} s; report in {} ({} files)",
        sweep.cells.len(),
        sweep.config.seeds.len(),
        args.out.join(REPORT_DIR).display(),
        written.len()
    );
    Ok(())
}

//! The commands that look at one piece of the simulation: `render`, `simulate`,
//! `landscape`, `competence` and `population`.

use crate::catalog::{Catalog, domain_of, find_operator, resolve_readings};
use crate::limits::{COMPETENCE_COMMANDS, COMPETENCE_ESTIMATES};
use crate::own_files;
use crate::progress::Progress;
use crate::simulate::command_json;
use anyhow::{Context, Result};
use lab::reference::landscape;
use lab::report::heatmap;
use lab::{Domain, Simulation};
use std::io::Write;
use std::path::Path;

use super::{CompetenceArgs, LandscapeArgs, PopulationArgs, RenderArgs, SimulateArgs};

/// Draws one simulated run of a behavior as an SVG.
pub(super) fn render<C: Catalog>(catalog: &C, args: &RenderArgs) -> Result<()> {
    let domain = domain_of(catalog, &args.scenario)?;
    let behavior = domain.space().parse(&args.behavior)?;
    let readings = resolve_readings(catalog, &Default::default())?;
    let (_, operator) = match &args.operator {
        Some(name) => find_operator(catalog, &args.scenario, name, &readings)?,
        None => catalog
            .operators(&args.scenario, &readings)
            .into_iter()
            .next()
            .with_context(|| {
                format!(
                    "{} has no built-in operator: name one with --operator",
                    args.scenario
                )
            })?,
    };
    let svg = catalog
        .render(&domain, &behavior, &operator, args.seed)
        .with_context(|| {
            format!(
                "{} draws no pictures of {} runs",
                catalog.tool().name,
                args.scenario
            )
        })?;
    files::write_no_follow(&args.output, svg.as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    println!("wrote {}", args.output.display());
    Ok(())
}

/// Prints `--count` simulated commands of one behavior, one JSON line each.
pub(super) fn simulate<C: Catalog>(catalog: &C, args: &SimulateArgs) -> Result<()> {
    let domain = domain_of(catalog, &args.scenario)?;
    let readings = resolve_readings(catalog, &Default::default())?;
    let (_, operator) = find_operator(catalog, &args.scenario, &args.operator, &readings)?;
    let behavior = domain.space().parse(&args.behavior)?;
    let simulation = Simulation::new(&domain, behavior, &operator, args.attention, args.seed)
        .context("--attention")?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for command in simulation.take(usize::try_from(args.count.get())?) {
        writeln!(out, "{}", command_json(&domain, &command?))?;
    }
    out.flush()?;
    Ok(())
}

/// Estimates and draws an operator's landscape over two components.
pub(super) fn landscape<C: Catalog>(catalog: &C, args: &LandscapeArgs) -> Result<()> {
    let domain = domain_of(catalog, &args.scenario)?;
    let readings = resolve_readings(catalog, &Default::default())?;
    let (operator_name, operator) =
        find_operator(catalog, &args.scenario, &args.operator, &readings)?;
    files::output::ensure_writable_dir(&args.out)?;
    own_files::check_all(&args.out, &own_files::LANDSCAPE)?;
    let space = domain.space();
    let components = match &args.components {
        Some(names) => names.clone(),
        None => space
            .components()
            .iter()
            .take(2)
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(","),
    };
    let (x, y) = landscape::axes(space, &components)?;
    let progress = Progress::new(
        "behavior",
        &[(format!("landscape ({} runs each)", args.runs), space.size())],
    );
    let every_component: Vec<usize> = (0..space.components().len()).collect();
    let estimate = landscape::estimate(
        &domain,
        &[&operator],
        &every_component,
        args.runs,
        args.seed,
        &|| progress.tick(0),
    )?;
    let title = format!(
        "{}, operator {}, {} runs per behavior",
        args.scenario, operator_name, args.runs
    );
    let others: Vec<&str> = (0..space.components().len())
        .filter(|&c| c != x && c != y)
        .map(|c| space.components()[c].name.as_str())
        .collect();
    let subtitle = if others.is_empty() {
        format!("{}every behavior", own_files::LANDSCAPE_SUBTITLE)
    } else {
        format!(
            "{}each pair of values, the mean over every {}",
            own_files::LANDSCAPE_SUBTITLE,
            others.join(", ")
        )
    };
    let svg_path = args.out.join("landscape.svg");
    let svg = heatmap::landscape_svg(space, &estimate, (x, y), &title, &subtitle, &svg_path)?;
    let csv = estimate.csv(space, domain.causes());
    for ((name, rule), text) in own_files::LANDSCAPE.iter().zip([svg, csv]) {
        let path = args.out.join(name);
        rule.write(&path, text.as_bytes())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Measures the robot's competence estimates against the truth and writes the report.
pub(super) fn competence<C: Catalog>(catalog: &C, args: &CompetenceArgs) -> Result<()> {
    let domain = domain_of(catalog, &args.scenario)?;
    let readings = resolve_readings(catalog, &Default::default())?;
    let (operator_name, operator) =
        find_operator(catalog, &args.scenario, &args.operator, &readings)?;
    let measured = check_competence_cost(args, domain.space().size())?;
    files::output::ensure_writable_dir(&args.out)?;
    own_files::check_all(&args.out, &own_files::COMPETENCE)?;
    let settings = lab::reference::competence_truth::CompetenceSettings {
        behaviors: args.behaviors,
        seen: args.seen.clone(),
        truth_runs: args.truth_runs,
        seed: args.seed,
        standard: trust::CompetenceStandard::uniform(args.standard).context("--standard")?,
    };
    let progress = Progress::new(
        "behavior",
        &[(
            format!("competence ({} truth runs each)", args.truth_runs),
            measured,
        )],
    );
    let accuracy = lab::reference::competence_truth::measure(
        &domain,
        &operator_name,
        &operator,
        &settings,
        &|| progress.tick(0),
    )?;
    let json = serde_json::to_string_pretty(&accuracy.json())? + "\n";
    for ((name, rule), text) in own_files::COMPETENCE
        .iter()
        .zip([accuracy.markdown(), json])
    {
        let path = args.out.join(name);
        rule.write(&path, text.as_bytes())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Refuses a competence measure whose whole cost is above its limits, before any work:
/// the commands it simulates ([`COMPETENCE_COMMANDS`]: each behavior measured runs the
/// largest of `--seen` commands and `--truth-runs` whole ones) and the estimates it
/// writes ([`COMPETENCE_ESTIMATES`]: one per behavior and number of `--seen`). A space
/// of `space_size` behaviors measures at most that many; returns how many are measured.
pub(super) fn check_competence_cost(args: &CompetenceArgs, space_size: u64) -> Result<u64> {
    let behaviors = u64::from(args.behaviors).min(space_size);
    let most_seen = args.seen.iter().copied().max().unwrap_or(0);
    let per_behavior = u64::from(most_seen) + u64::from(args.truth_runs);
    let measured = if behaviors < u64::from(args.behaviors) {
        format!("{behaviors} behaviors, all of the space,")
    } else {
        format!("{behaviors} behaviors")
    };
    COMPETENCE_COMMANDS.check_total(
        "--behaviors x (the largest --seen + --truth-runs)",
        behaviors * per_behavior,
        format!(
            " in all ({measured} x ({most_seen} commands seen + {} truth runs))",
            args.truth_runs
        ),
    )?;
    COMPETENCE_ESTIMATES.check_total(
        "--behaviors x --seen",
        behaviors * args.seen.len() as u64,
        format!(
            " in competence.json ({measured} x {} numbers of --seen)",
            args.seen.len()
        ),
    )?;
    Ok(behaviors)
}

/// Writes the members of an instance of the catalog's prior as operator files.
pub(super) fn population<C: Catalog>(catalog: &C, args: &PopulationArgs) -> Result<()> {
    domain_of(catalog, &args.scenario)?;
    files::output::ensure_writable_dir(&args.out)?;
    let members = catalog.prior(&args.scenario, &args.instance, !args.unscreened)?;
    let files: Vec<String> = members.iter().map(|m| format!("{}.ron", m.name)).collect();
    for (member, file) in members.iter().zip(&files) {
        anyhow::ensure!(
            Path::new(file).file_name() == Some(file.as_ref())
                && !member.name.is_empty()
                && !member.name.starts_with('.'),
            "the prior named a member `{}`, which is not a plain file name",
            member.name
        );
    }
    // A folder holding other files (another instance's members) would mix populations.
    if let Some(name) =
        lab::folder::foreign_entry(&args.out, None, |name| files.iter().any(|f| f == name))?
    {
        anyhow::bail!(
            "{}: the folder holds `{name}`, which is not a member of {} ({}); give an empty or new folder",
            args.out.display(),
            args.instance,
            args.scenario
        );
    }
    // A file of a member's name is replaced only when it is that member's, written
    // earlier; every one is checked before any is written.
    let readings = &resolve_readings(catalog, &Default::default())?;
    let what: Vec<String> = members
        .iter()
        .map(|m| own_files::member_file(&m.name, &args.scenario))
        .collect();
    let rules: Vec<_> = members
        .iter()
        .zip(&files)
        .zip(&what)
        .map(|((member, file), what)| {
            let path = args.out.join(file);
            let is_own = move |_: &[u8]| {
                own_files::is_member_file(catalog, &args.scenario, readings, &path, &member.name)
            };
            (is_own, what)
        })
        .collect();
    let rules: Vec<files::OwnFile<'_>> = rules
        .iter()
        .map(|(is_own, what)| files::OwnFile {
            what,
            remedy: "give --out an empty or new folder, or move the file away",
            is_own,
        })
        .collect();
    for (rule, file) in rules.iter().zip(&files) {
        rule.check(&args.out.join(file))?;
    }
    for ((rule, member), file) in rules.iter().zip(&members).zip(&files) {
        let path = args.out.join(file);
        rule.write(&path, member.text.as_bytes())?;
        println!("wrote {}", path.display());
    }
    println!(
        "{} members of instance {} (seed {}), {}{}",
        members.len(),
        args.instance,
        args.instance.seed(),
        args.scenario,
        if args.unscreened { ", unscreened" } else { "" }
    );
    Ok(())
}

//! The robot-facing commands: `serve` (an adapter behind the JSON-lines protocol),
//! `cases` (a case base's exchange) and `explain` (one trial's story from a report).

use crate::catalog::Catalog;
use crate::served::{Spelling, check_preference, judging_competence, served_domain, serving_arm};
use crate::suite::{StartingCases, trace_report_trial};
use anyhow::{Context, Result};
use service::{Limits, Location, Session, SharedCases, exchange, transport};
use std::io::Write;
use std::sync::Arc;
use std::time::Duration;

use super::{CasesCommand, ExplainArgs, ServeArgs};

/// Prints the story of one trial of a report folder, replayed from its `config.ron` once
/// the report shows that the replay is the trial that ran ([`check_replay`]).
pub(super) fn explain<C: Catalog>(catalog: &C, args: &ExplainArgs) -> Result<()> {
    if let Some(dir) = &args.cases {
        anyhow::ensure!(dir.is_dir(), "--cases {}: no such folder", dir.display());
    }
    let starting = args
        .cases
        .as_ref()
        .map(|dir| StartingCases { dir: dir.clone() });
    let replayed = trace_report_trial(
        catalog,
        &args.report,
        starting.as_ref(),
        &args.experiment,
        &args.arm,
        args.trial,
    )?;
    for warning in &replayed.warnings {
        eprintln!("warning: {warning}");
    }
    print!(
        "{}",
        lab::report::timeline::story(&replayed.timeline, &replayed.space)
    );
    Ok(())
}

/// Serves an adapter over the JSON-lines protocol, on stdin and stdout or over TCP.
pub(super) fn serve<C: Catalog>(catalog: &C, args: &ServeArgs) -> anyhow::Result<()> {
    // Every option is checked, and the address bound, before the case base is opened: a
    // refused command creates no case base. The timeouts are checked whatever the
    // transport: an option that is wrong is refused, even where it would not act.
    let limits = Limits {
        max_connections: args.max_connections.get(),
        read_timeout: timeout("--idle-timeout", args.idle_timeout)?,
        write_timeout: timeout("--write-timeout", args.write_timeout)?,
    };
    let mut domain = served_domain(catalog, &args.domain)?;
    domain = serving_arm(catalog, domain, &args.arm, Spelling::CommandLine)?;
    if args.mission {
        domain = domain.in_mission_mode();
    }
    if args.detect_changes {
        domain = domain.detecting_changes(trust::ChangeDetector::default());
    }
    if let Some(at_most) = args.competence {
        domain = judging_competence(catalog, domain, at_most, Spelling::CommandLine)?;
    }
    check_preference(&domain, Spelling::CommandLine)?;
    let listening = match args.listen {
        None => None,
        Some(addr) => Some((transport::listen(addr)?, limits)),
    };
    let location = Location::parse(&args.cases);
    let cases = Arc::new(SharedCases::open(&domain, &location)?);
    let loaded = cases.current(|memory, _| memory.base().len())?;
    eprintln!(
        "{} serve: {} behaviors, {loaded} cases loaded from {}",
        catalog.tool().name,
        domain.space.size(),
        cases.location()
    );
    if !cases.writable() {
        eprintln!(
            "{} is a RON case file: served read-only, no case is retained (import it into a database with `{} cases import`)",
            cases.location(),
            catalog.tool().name
        );
    }
    match listening {
        None => {
            let mut session = Session::new(domain, cases, args.seed)?;
            let (stdin, stdout) = (std::io::stdin().lock(), std::io::stdout().lock());
            transport::serve(&mut session, stdin, stdout)?;
        }
        Some((listener, limits)) => {
            let bound = listener.local_addr().context("reading the bound address")?;
            // Tests and controllers read this line to learn the port when 0 was asked for.
            eprintln!("listening on {bound}");
            std::io::stderr().flush().ok();
            let log = Box::new(|m: &str| eprintln!("{m}"));
            transport::serve_tcp(domain, cases, args.seed, &listener, limits, log)?;
        }
    }
    Ok(())
}

/// The timeout `option` gives, `seconds`: more than 0 and at most
/// [`transport::MAX_TIMEOUT`].
pub(super) fn timeout(option: &str, seconds: f64) -> Result<Duration> {
    Duration::try_from_secs_f64(seconds)
        .ok()
        .filter(|d| !d.is_zero() && *d <= transport::MAX_TIMEOUT)
        .with_context(|| {
            format!(
                "{option} must be a number of seconds more than 0 and at most {} (a day), got {}",
                transport::MAX_TIMEOUT.as_secs(),
                crate::limits::shown(seconds)
            )
        })
}

/// Exports, imports, merges or describes a case base.
pub(super) fn cases<C: Catalog>(catalog: &C, command: &CasesCommand) -> Result<()> {
    match command {
        CasesCommand::Export { cases, out } => {
            let written = exchange::export(&Location::parse(cases), out)?;
            println!("wrote {written} cases to {}", out.display());
        }
        CasesCommand::Import {
            input,
            cases,
            domain,
        } => {
            let domain = served_domain(catalog, domain)?;
            let location = Location::parse(cases);
            let imported = exchange::import(input, &location, &domain)?;
            println!(
                "imported {} cases from {} into {}",
                imported.cases,
                input.display(),
                location.shown()
            );
            if imported.already_held > 0 {
                eprintln!(
                    "warning: {} of them were already in {} (the same evaluated pairs and solution): is {} imported twice? It now holds them twice",
                    imported.already_held,
                    location.shown(),
                    input.display()
                );
            }
        }
        CasesCommand::Info { cases } => println!("{}", exchange::info(&Location::parse(cases))?),
    }
    Ok(())
}

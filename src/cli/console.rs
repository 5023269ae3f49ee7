//! `console`: a trust study served to participants' browsers (docs/studies.md), and
//! `console export` / `console report`, which read a study's database.

use crate::catalog::Catalog;
use crate::served::{Spelling, served_domain, serving_arm};
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use console::participant::Conduct;
use console::{Study, StudyError, server};
use std::io::Write;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The environment variable that holds the researcher's admin token.
const ADMIN_TOKEN_VAR: &str = "TRUSTCBR_CONSOLE_ADMIN_TOKEN";
/// The shortest admin token a researcher may set.
const MIN_ADMIN_TOKEN: usize = 16;

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(super) struct ConsoleArgs {
    #[command(subcommand)]
    action: Option<ConsoleAction>,
    /// The study file (RON): domain, conditions, assignment, ratings, consent
    /// (domains/studies/pilot.ron is an example).
    #[arg(long, required = true)]
    study: Option<PathBuf>,
    /// The study's database: an SQLite file (made when absent) or a postgres:// URL
    /// (several consoles, one study). It holds one study: another is refused.
    #[arg(long, required = true, value_parser = super::text())]
    db: Option<String>,
    /// The address to serve on (port 0 picks one). Loopback unless --public.
    #[arg(long, default_value = "127.0.0.1:8080")]
    listen: SocketAddr,
    /// Serve on a non-loopback address, to participants on other machines; needs the
    /// admin token in TRUSTCBR_CONSOLE_ADMIN_TOKEN (at least 16 characters).
    #[arg(long)]
    public: bool,
}

#[derive(Subcommand)]
enum ConsoleAction {
    /// Write a study's records: events.jsonl, ratings.csv and episodes.jsonl (each
    /// participant's episode as a line of a report's trials.jsonl).
    Export {
        /// The study's database (an SQLite file or a postgres:// URL).
        #[arg(value_parser = super::text())]
        db: String,
        /// The folder to write (made when absent).
        out: PathBuf,
    },
    /// Tell one participant's session: each behavior, its commands, the adapter's
    /// explanations and the ratings, after replaying it through the adapter.
    Explain {
        /// The study's database (an SQLite file or a postgres:// URL).
        #[arg(value_parser = super::text())]
        db: String,
        /// The participant's pseudonym (P001, P002, ...).
        #[arg(value_parser = super::text())]
        participant: String,
    },
    /// Write a study's report: per condition, behaviors evaluated, stops, and the rank
    /// correlation of the robot's trust estimate with the participants' ratings.
    Report {
        /// The study's database (an SQLite file or a postgres:// URL).
        #[arg(value_parser = super::text())]
        db: String,
        /// The folder to write report.md and report.json in (made when absent).
        out: PathBuf,
    },
}

/// Runs `console` and its subcommands.
pub(super) fn console<C: Catalog>(catalog: &C, args: ConsoleArgs) -> Result<()> {
    match args.action {
        Some(ConsoleAction::Export { db, out }) => {
            let n = console::export::export(&db, &out)?;
            println!("wrote {} ({n} participants)", out.display());
            Ok(())
        }
        Some(ConsoleAction::Explain { db, participant }) => explain(catalog, &db, &participant),
        Some(ConsoleAction::Report { db, out }) => {
            console::report::report(&db, &out)?;
            println!("wrote {}", out.join("report.md").display());
            Ok(())
        }
        None => {
            let study = args.study.context("--study is required")?;
            let db = args.db.context("--db is required")?;
            serve_study(catalog, &study, &db, args.listen, args.public)
        }
    }
}

/// The conduct of the study at `path` over the database at `db`: every check is made
/// before the database is opened, so a refused study stores nothing.
fn conduct<C: Catalog>(catalog: &C, path: &Path, db: &str) -> Result<Conduct> {
    let (study, text) = Study::load(path)?;
    let (stage, conditions) = served(catalog, &study, &text, path)?;
    let database = console::db::open(db, &study, &text, &path.display().to_string())?;
    Ok(Conduct {
        study,
        conditions,
        stage,
        db: Arc::from(database),
    })
}

/// The stage `study` is shown on and each condition's served domain, refused with the
/// study file's place (`text`, read from `path`) when the catalog cannot show its domain
/// or serve an arm.
fn served<C: Catalog>(
    catalog: &C,
    study: &Study,
    text: &str,
    path: &Path,
) -> Result<(Arc<dyn console::Stage>, Vec<service::DomainDefinition>)> {
    let refuse = |field: String, needle: &str, reason: String| {
        StudyError::at(text, path, field, needle, reason)
    };
    let stage = catalog.stage(&study.domain).ok_or_else(|| {
        refuse(
            "domain".into(),
            &format!("\"{}\"", study.domain),
            format!(
                "`{}` is not a scenario {} can show a person: allowed {}",
                study.domain,
                catalog.tool().name,
                catalog
                    .scenarios()
                    .into_iter()
                    .filter(|s| catalog.stage(s).is_some())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    })?;
    let domain = served_domain(catalog, &study.domain)?;
    let mut conditions = Vec::new();
    for (i, condition) in study.conditions.iter().enumerate() {
        let served = serving_arm(
            catalog,
            domain.clone(),
            &condition.arm,
            Spelling::CommandLine,
        )
        .map_err(|e| {
            refuse(
                format!("conditions[{i}].arm"),
                &format!("\"{}\"", condition.arm),
                // The arm is the study's field, not a flag.
                format!("{e:#}")
                    .replacen("--arm: ", "", 1)
                    .replace("--arm ", "`arm` "),
            )
        })?;
        conditions.push(served);
    }
    Ok((stage, conditions))
}

/// Prints the story of one participant's session, replayed through the adapter first so
/// that a record the adapter no longer decides alike is refused, not told.
fn explain<C: Catalog>(catalog: &C, db: &str, wanted: &str) -> Result<()> {
    let recorded = console::export::Recorded::open(db)?;
    let text = recorded.db.study_text()?;
    let origin = PathBuf::from(format!("{db} (its study)"));
    let (stage, conditions) = served(catalog, &recorded.study, &text, &origin)?;
    let conduct = Conduct {
        study: recorded.study,
        conditions,
        stage,
        db: Arc::from(recorded.db),
    };
    let participants = conduct.db.participants()?;
    let participant = participants
        .iter()
        .find(|p| p.pseudonym() == wanted)
        .with_context(|| {
            format!(
                "{db} has no participant {wanted} (it has {})",
                match participants.len() {
                    0 => "none".to_owned(),
                    n => format!("P001 to {}", participants[n - 1].pseudonym()),
                }
            )
        })?;
    let events = conduct.db.events(participant.number)?;
    conduct.replay(participant, &events)?;
    print!(
        "{}",
        console::story::story(&conduct.study, participant, &events)
    );
    Ok(())
}

/// Serves the study until the process is stopped.
fn serve_study<C: Catalog>(
    catalog: &C,
    path: &Path,
    db: &str,
    listen: SocketAddr,
    public: bool,
) -> Result<()> {
    let given = std::env::var(ADMIN_TOKEN_VAR).ok();
    if let Some(token) = &given {
        anyhow::ensure!(
            token.chars().count() >= MIN_ADMIN_TOKEN,
            "{ADMIN_TOKEN_VAR}: at least {MIN_ADMIN_TOKEN} characters"
        );
    }
    server::check_listen(listen, public, given.is_some()).map_err(anyhow::Error::msg)?;
    let conduct = conduct(catalog, path, db)?;
    let admin_token = given.clone().unwrap_or_else(server::new_token);
    let router = server::router(conduct, admin_token.clone());
    server::run(listen, router, |addr| {
        if given.is_none() {
            eprintln!("admin token: {admin_token}");
        }
        eprintln!("the researcher's page: http://{addr}/admin");
        let mut out = std::io::stdout().lock();
        writeln!(out, "listening on http://{addr}")?;
        out.flush()
    })
    .with_context(|| format!("serving the study on {listen}"))
}

//! `trustcbr`: the command-line front end. Argument parsing and glue only; the work is
//! done by the `trust`, `domains` and `service` libraries.

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use service::{CaseStore, DomainDefinition, Session, transport};
use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;

/// Trust-guided behavior adaptation with case-based reasoning.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Serve the online adapter to a robot controller over JSON lines (docs/protocol.md).
    Serve(ServeArgs),
}

#[derive(Args)]
struct ServeArgs {
    /// `movement`, `patrol`, or a RON domain file declaring a behavior space (and
    /// optionally the adapter config).
    #[arg(long)]
    domain: String,
    /// The case base: loaded if it exists, created at the first retained case, rewritten
    /// atomically after every retained case.
    #[arg(long)]
    cases: PathBuf,
    /// Listen on this loopback address (e.g. 127.0.0.1:7878; port 0 picks one) instead of
    /// stdin/stdout. One controller connection at a time.
    #[arg(long)]
    listen: Option<SocketAddr>,
    /// Seed of the adapter's search and of the behaviors the server draws.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Serve(args) => serve(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn serve(args: &ServeArgs) -> anyhow::Result<()> {
    let domain = DomainDefinition::resolve(&args.domain)?;
    let (store, cases) = CaseStore::open(&args.cases, &domain.space)?;
    let loaded = cases.len();
    let mut session = Session::new(domain, store, cases, args.seed)?;
    eprintln!(
        "trustcbr serve: {} behaviors, {loaded} cases loaded from {}",
        session.adapter().space().size(),
        args.cases.display()
    );
    match args.listen {
        None => {
            let (stdin, stdout) = (std::io::stdin().lock(), std::io::stdout().lock());
            transport::serve(&mut session, stdin, stdout)?;
        }
        Some(addr) => {
            let listener = transport::listen(addr)?;
            let bound = listener.local_addr().context("reading the bound address")?;
            // Tests and controllers read this line to learn the port when 0 was asked for.
            eprintln!("listening on {bound}");
            std::io::stderr().flush().ok();
            transport::serve_tcp(&mut session, &listener, &mut |m| eprintln!("{m}"))?;
        }
    }
    Ok(())
}

//! `trustcbr`: the command-line front end. Argument parsing and glue only; the work is
//! done by the `trust` and `domains` libraries.

use clap::Parser;

/// Trust-guided behavior adaptation with case-based reasoning.
#[derive(Parser)]
#[command(version, about)]
struct Cli {}

fn main() {
    Cli::parse();
}

//! `warehouse`: the trustcbr command-line tool over the warehouse picking scenario.

use std::process::ExitCode;

fn main() -> ExitCode {
    trustcbr::cli::main(warehouse::WarehouseCatalog)
}

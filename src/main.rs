//! `trustcbr`: the command-line tool over the built-in UGV scenarios.

fn main() -> std::process::ExitCode {
    trustcbr::cli::main(trustcbr::UgvCatalog)
}

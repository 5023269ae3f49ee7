//! The files `competence`, `landscape` and `population` write into a folder the user
//! names, and how each is recognized as the tool's own: only such a file (or none) is
//! replaced, never through a symbolic link ([`files::OwnFile`]).
//!
//! - `competence.md` begins with its title (`lab::reference::competence_truth::MARKDOWN_TITLE`);
//!   `competence.json` is a JSON object with every key the tool writes.
//! - `landscape.csv`'s header holds `runs,completed,p_complete`; `landscape.svg` is an SVG
//!   whose subtitle begins [`LANDSCAPE_SUBTITLE`].
//! - a population's `MEMBER.ron` reads back, as the scenario's operator file, as an
//!   operator named `MEMBER` ([`member_file`]).

use crate::catalog::{Catalog, Readings};
use files::OwnFile;
use std::path::Path;

/// What the user can do when a file of `competence` or `landscape` is refused.
const REMEDY: &str = "give --out another folder, or move the file away";

/// How the subtitle of every `landscape.svg` begins.
pub const LANDSCAPE_SUBTITLE: &str = "P(complete) of ";

/// The files `competence` writes, by name, with the rule for replacing each.
pub const COMPETENCE: [(&str, OwnFile<'static>); 2] = [
    (
        "competence.md",
        OwnFile {
            what: "a competence report written by `trustcbr competence`",
            remedy: REMEDY,
            is_own: &lab::reference::competence_truth::is_competence_markdown,
        },
    ),
    (
        "competence.json",
        OwnFile {
            what: "a competence report written by `trustcbr competence`",
            remedy: REMEDY,
            is_own: &lab::reference::competence_truth::is_competence_json,
        },
    ),
];

/// The files `landscape` writes, by name, with the rule for replacing each.
pub const LANDSCAPE: [(&str, OwnFile<'static>); 2] = [
    (
        "landscape.svg",
        OwnFile {
            what: "a landscape figure written by `trustcbr landscape`",
            remedy: REMEDY,
            is_own: &is_landscape_svg,
        },
    ),
    (
        "landscape.csv",
        OwnFile {
            what: "a landscape table written by `trustcbr landscape`",
            remedy: REMEDY,
            is_own: &lab::reference::landscape::is_landscape_csv,
        },
    ),
];

/// Whether `bytes` are a `landscape.svg`: an SVG holding [`LANDSCAPE_SUBTITLE`].
fn is_landscape_svg(bytes: &[u8]) -> bool {
    let subtitle = LANDSCAPE_SUBTITLE.as_bytes();
    bytes.starts_with(b"<svg") && bytes.windows(subtitle.len()).any(|w| w == subtitle)
}

/// The check of the files `files` (name, rule) in `dir`, before any work: each absent or
/// the tool's own.
pub fn check_all(dir: &Path, files: &[(&str, OwnFile<'_>)]) -> Result<(), files::ReplaceError> {
    files
        .iter()
        .try_for_each(|(name, rule)| rule.check(&dir.join(name)))
}

/// Whether the file `path` is the population member `member` of `scenario` written
/// earlier: it reads back, as `catalog` reads the scenario's operator files, as an
/// operator of that name.
pub fn is_member_file<C: Catalog>(
    catalog: &C,
    scenario: &str,
    readings: &Readings,
    path: &Path,
    member: &str,
) -> bool {
    catalog
        .load_operator(scenario, path, readings)
        .is_ok_and(|(name, _)| name == member)
}

/// What a population member's file is, as messages name it.
pub fn member_file(member: &str, scenario: &str) -> String {
    format!(
        "an operator file of {scenario} for the member `{member}` written by `trustcbr population`"
    )
}

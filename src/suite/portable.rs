//! A report that reruns by itself: every operator file its config names is copied into
//! the report's `operators/` folder, and the `config.ron` the report holds names the
//! copies, so `trustcbr run REPORT/config.ron` runs from the report alone, wherever it
//! is. Experiment suites and mission suites share it: each hands over its
//! [`ExperimentSpec`]s (an experiment's, a mission plan's operators).

use super::SuiteError;
use files::name::file_stems;
use files::{read_text, write_file_in};
use std::path::{Path, PathBuf};

/// The folder of a report that holds copies of the operator files its config names.
const REPORT_OPERATORS: &str = "operators";

/// An operator file a report copies: where it is read, and its path in the report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct OperatorCopy {
    /// The file, resolved against the config's directory.
    pub source: PathBuf,
    /// Its copy, relative to the report folder (`operators/NAME.ron`).
    pub copy: PathBuf,
}

/// Rewrites the lists of operator files `lists` (relative to `origin`'s directory) to name
/// their copies in a report, one copy per distinct file (named after its file stem, made
/// unique), and returns the copies to make.
pub(crate) fn relocate_operator_files<'a>(
    lists: impl IntoIterator<Item = &'a mut Vec<PathBuf>>,
    origin: &Path,
) -> Vec<OperatorCopy> {
    let base = origin.parent().unwrap_or(Path::new("."));
    let mut lists: Vec<&'a mut Vec<PathBuf>> = lists.into_iter().collect();
    let mut sources: Vec<PathBuf> = Vec::new();
    for file in lists.iter().flat_map(|files| files.iter()) {
        let source = base.join(file);
        if !sources.contains(&source) {
            sources.push(source);
        }
    }
    let stems = file_stems(sources.iter().map(|p| {
        p.file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
    }));
    let copies: Vec<OperatorCopy> = sources
        .into_iter()
        .zip(stems)
        .map(|(source, stem)| OperatorCopy {
            source,
            copy: Path::new(REPORT_OPERATORS).join(format!("{stem}.ron")),
        })
        .collect();
    for files in &mut lists {
        for file in files.iter_mut() {
            let source = base.join(&*file);
            file.clone_from(
                &copies
                    .iter()
                    .find(|c| c.source == source)
                    .expect("every file was collected")
                    .copy,
            );
        }
    }
    copies
}

/// Copies each operator file of `copies` into the report folder `dir`; returns the files
/// written.
pub(crate) fn copy_operator_files(
    dir: &Path,
    copies: &[OperatorCopy],
) -> Result<Vec<PathBuf>, SuiteError> {
    copies
        .iter()
        .map(|c| Ok(write_file_in(dir, &c.copy, &read_text(&c.source)?)?))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::ExperimentSpec;

    fn spec(files: &[&str]) -> ExperimentSpec {
        ExperimentSpec {
            scenario: "movement".into(),
            operator: "random".into(),
            operator_files: files.iter().map(PathBuf::from).collect(),
            builtin_operators: Vec::new(),
            population: None,
            feedback: None,
            goal_changes: None,
            contexts: None,
            stated: None,
        }
    }

    #[test]
    fn each_distinct_file_is_copied_once_under_a_unique_name() {
        let mut specs = [
            spec(&["ops/a/dispatcher.ron", "ops/b/dispatcher.ron"]),
            spec(&["ops/a/dispatcher.ron", "/abs/hasty.ron"]),
        ];
        let copies = relocate_operator_files(
            specs.iter_mut().map(|spec| &mut spec.operator_files),
            Path::new("suites/x.ron"),
        );
        let pairs: Vec<(&str, &str)> = copies
            .iter()
            .map(|c| (c.source.to_str().unwrap(), c.copy.to_str().unwrap()))
            .collect();
        assert_eq!(
            pairs,
            [
                ("suites/ops/a/dispatcher.ron", "operators/dispatcher.ron"),
                ("suites/ops/b/dispatcher.ron", "operators/dispatcher-2.ron"),
                ("/abs/hasty.ron", "operators/hasty.ron"),
            ]
        );
        assert_eq!(
            specs[0].operator_files,
            [
                PathBuf::from("operators/dispatcher.ron"),
                PathBuf::from("operators/dispatcher-2.ron")
            ]
        );
        assert_eq!(
            specs[1].operator_files,
            [
                PathBuf::from("operators/dispatcher.ron"),
                PathBuf::from("operators/hasty.ron")
            ]
        );
    }
}

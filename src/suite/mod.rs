//! The experiment suite over a catalog's domains.
//!
//! A suite config (RON) names experiments by scenario and operator, the arms to compare,
//! the trials, seed, adapter parameters and the domain's readings; [`run_suite`] turns it
//! into [`ExperimentPlan`](lab::ExperimentPlan)s for the generic runner in `lab`, over the
//! domains a [`Catalog`](crate::Catalog) builds, and [`write_suite_report`] writes the report folder. The
//! catalog embeds the suite `reproduce` runs ([`Catalog::default_suite`](crate::Catalog::default_suite)). Each
//! experiment's learned case bases can be saved ([`save_case_bases`]) and an arm can start
//! from them ([`StartingCases`]).
//!
//! One idea per file: the config as written (`config`) and its checks (`validate`); the
//! plans a config makes over the catalog's domains (`plan`); running them (`run`);
//! replaying one trial (`trace`) and what a report records so `explain` replays it
//! faithfully (`replay`); the report's estimates beside the run (`estimates`) and the
//! report itself (`report`), which reruns by itself with copies of its operator files
//! (`portable`, which mission reports share); case bases saved and read back
//! (`saved_cases`).

pub(crate) mod config;
mod estimates;
mod plan;
mod portable;
mod replay;
mod report;
mod run;
mod saved_cases;
mod trace;
mod validate;

pub use config::{EMBEDDED_ORIGIN, ExperimentSpec, Population, RANDOM_OPERATOR, SuiteConfig};
pub(crate) use config::{arm_name_lists, arm_names, contexts_written, some_arm_names};
pub use estimates::ReportEstimates;
pub use plan::arm_named;
pub(crate) use portable::{copy_operator_files, relocate_operator_files};
pub(crate) use replay::report_replay;
pub use replay::{ReplayError, check_replay};
pub use report::{
    PAPER_TABLE_HEADING, report_benchmark, report_entries, suite_best_arms, suite_table,
    write_suite_report,
};
pub use run::{SuiteResults, run_suite, run_suite_with_report};
pub use saved_cases::{StartingCases, check_save_targets, save_case_bases};
pub use trace::{
    Replayable, ReplayedTrial, TraceError, replayable_config, trace_report_trial, trace_suite_trial,
};
pub(crate) use validate::{check_adapter, check_arms, check_distinct, over};

use crate::catalog::CatalogError;
use crate::config_file::{ConfigFileError, from_config_file_errors};
use lab::PlanError;
use lab::report::ReportError;
use service::StoreError;
use service::store::ron_file::CaseBaseError;
use std::path::{Path, PathBuf};
use trust::ConfigError;

/// Why a suite cannot be run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SuiteError {
    /// A file cannot be read or written (the config, an operator file copied into the
    /// report, a folder of saved case bases), the config does not parse, or a value of it
    /// is out of range.
    #[error(transparent)]
    File(#[from] ConfigFileError),
    /// An operator file is invalid.
    #[error(transparent)]
    Operator(#[from] CatalogError),
    /// The adapter parameters are invalid.
    #[error("adapter: {0}")]
    Adapter(ConfigError),
    /// The experiments cannot be run as planned.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A case base could not be saved.
    #[error(transparent)]
    Cases(#[from] CaseBaseError),
    /// A saved case base cannot be read, or was learned in another behavior space.
    #[error(transparent)]
    SavedCases(Box<StoreError>),
    /// The report could not be written.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// A name cannot become the file name it would be (an arm's saved case base).
    #[error(transparent)]
    Name(#[from] files::name::NameError),
    /// `--save-cases` would write over a file that is not a case base saved earlier.
    #[error(
        "{}: exists and is not a case base saved earlier ({reason}); --save-cases writes over nothing else: give another folder, or move the file",
        path.display()
    )]
    SaveOver {
        /// The file.
        path: PathBuf,
        /// What it is.
        reason: String,
    },
}

from_config_file_errors!(SuiteError);

// Boxed: a store's error is large, and every result of a suite carries this type.
impl From<StoreError> for SuiteError {
    fn from(error: StoreError) -> Self {
        Self::SavedCases(Box::new(error))
    }
}

// By hand rather than `#[from]`, which would also expose the reason as the error's
// source and have it printed twice in a chain.
impl From<ConfigError> for SuiteError {
    fn from(reason: ConfigError) -> Self {
        SuiteError::Adapter(reason)
    }
}

/// A [`ConfigFileError::Invalid`] of `field` in the file `origin`, as a [`SuiteError`].
pub(crate) fn invalid(origin: &Path, field: String, message: String) -> SuiteError {
    ConfigFileError::invalid(origin, field, message).into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UgvCatalog;
    use crate::catalog::{Catalog, OperatorOf, Readings};
    use lab::Arm;
    use trust::RetrieverKind;

    /// The UGV catalog with one arm of its own: uniform search under another name.
    struct WithOwnArm;

    impl Catalog for WithOwnArm {
        type Domain = domains::UgvDomain;
        fn tool(&self) -> crate::ToolInfo {
            crate::tool_info!()
        }
        fn scenarios(&self) -> Vec<String> {
            UgvCatalog.scenarios()
        }
        fn domain(&self, scenario: &str) -> Option<Self::Domain> {
            UgvCatalog.domain(scenario)
        }
        fn operators(
            &self,
            scenario: &str,
            readings: &Readings,
        ) -> Vec<(String, OperatorOf<Self>)> {
            UgvCatalog.operators(scenario, readings)
        }
        fn load_operator(
            &self,
            scenario: &str,
            path: &Path,
            readings: &Readings,
        ) -> Result<(String, OperatorOf<Self>), CatalogError> {
            UgvCatalog.load_operator(scenario, path, readings)
        }
        fn arms(&self, _: RetrieverKind) -> Vec<Arm> {
            vec![Arm::search_only("mine", |_| {
                Box::new(trust::search::Uniform::new())
            })]
        }
        fn default_suite(&self) -> &str {
            UgvCatalog.default_suite()
        }
    }

    #[test]
    fn a_catalog_s_own_arms_are_named_like_built_in_ones() {
        let origin = Path::new("own.ron");
        let config = SuiteConfig::from_ron(
            &WithOwnArm,
            "(seed: 1, trials: 3, arms: [\"random-walk\", \"mine\"], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
            origin,
        )
        .unwrap();
        let results = run_suite(&WithOwnArm, &config, origin, None, &|_| ()).unwrap();
        let names: Vec<&str> = results.results[0]
            .arms
            .iter()
            .map(|a| a.name.as_str())
            .collect();
        assert_eq!(names, ["random-walk", "mine"]);
        let err = SuiteConfig::from_ron(
            &WithOwnArm,
            "(seed: 1, trials: 3, arms: [\"yours\"], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        let known = format!(
            "(known: {}, mine; each also as NAME+context-blind, NAME+ignores-statements, NAME+learned-start and NAME+competent)",
            lab::builtin_arm_names().join(", ")
        );
        assert!(
            err.contains("arms[0]") && err.contains("unknown arm `yours`") && err.ends_with(&known),
            "{err}"
        );
    }

    #[test]
    fn an_arm_may_start_from_the_memory_s_guess() {
        let origin = Path::new("learned.ron");
        let parse = |arms: &str| {
            SuiteConfig::from_ron(
                &WithOwnArm,
                &format!(
                    "(seed: 1, trials: 4, arms: {arms}, experiments: [(scenario: \"movement\", operator: \"random\")])"
                ),
                origin,
            )
        };
        // Plain names are read as they always were; an arm's options are read as the
        // name of the arm they make, for a built-in arm or the catalog's own.
        let config = parse(
            "[\"case-based\", (name: \"case-based\", initial: learned), (name: \"uniform\", initial: random), (name: \"mine\", initial: learned), \"conditioned+learned-start\"]",
        )
        .unwrap();
        assert_eq!(
            config.arms,
            [
                "case-based",
                "case-based+learned-start",
                "uniform",
                "mine+learned-start",
                "conditioned+learned-start"
            ]
        );
        let back = SuiteConfig::from_ron(&WithOwnArm, &config.to_ron(), origin).unwrap();
        assert_eq!(back, config);
        let json = SuiteConfig::from_json(
            &WithOwnArm,
            r#"{"seed": 1, "trials": 4, "arms": ["uniform", {"name": "uniform", "initial": "learned"}], "experiments": [{"scenario": "movement", "operator": "random"}]}"#,
            origin,
        )
        .unwrap();
        assert_eq!(json.arms, ["uniform", "uniform+learned-start"]);
        // A bad value is refused where it stands, with the allowed ones.
        let err = parse("[\"uniform\",\n  (name: \"case-based\", initial: fast)]")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("learned.ron:2:")
                && err.contains("field `initial`")
                && err.contains("`random`")
                && err.contains("`learned`"),
            "{err}"
        );
        for (arms, expected) in [
            (
                "[(name: \"case-based+learned-start\", initial: learned)]",
                "write the arm `case-based` and set `initial`",
            ),
            ("[(name: \"case-based\", start: learned)]", "start"),
            ("[(initial: learned)]", "missing field `name`"),
            ("[(name: \"x\", name: \"y\")]", "duplicate field `name`"),
            ("[3]", "an arm's name as a string"),
            (
                "[\"case-based+learned-start\", (name: \"case-based\", initial: learned)]",
                "arms[1]: `case-based+learned-start` is listed twice",
            ),
            (
                "[(name: \"annealing\", initial: learned)]",
                "unknown arm `annealing+learned-start`",
            ),
        ] {
            let err = parse(arms).unwrap_err().to_string();
            assert!(err.contains(expected), "{arms}: {err}");
        }

        // Every name works where arm names do: the run, the reference, a replayed trial,
        // saved case bases read back.
        let config = parse(
            "[\"case-based\", (name: \"case-based\", initial: learned), (name: \"mine\", initial: learned)], reference: \"case-based+learned-start\"",
        )
        .unwrap();
        assert_eq!(config.reference(), "case-based+learned-start");
        let results = run_suite(&WithOwnArm, &config, origin, None, &|_| ()).unwrap();
        let result = &results.results[0];
        let names: Vec<&str> = result.arms.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "case-based",
                "case-based+learned-start",
                "mine+learned-start"
            ]
        );
        for arm in &result.arms {
            // Trial 0 of every arm starts from the same random behavior.
            assert_eq!(arm.trials[0].initial, result.arms[0].trials[0].initial);
            assert!(!arm.trials[0].learned_start);
        }
        let learned = &result.arms[1];
        let replayed = trace_suite_trial(
            &WithOwnArm,
            &config,
            origin,
            None,
            &result.name,
            "case-based+learned-start",
            3,
        )
        .unwrap()
        .0;
        assert_eq!(replayed.record, learned.trials[3]);
        let dir = tempfile::tempdir().unwrap();
        let written = save_case_bases(dir.path(), &config, &results).unwrap();
        // Every arm reads cases: the plain one reuses them, the others start from them.
        assert_eq!(written.len(), 3);
        assert!(written[2].ends_with("movement-random/mine+learned-start.ron"));
        let starting = StartingCases {
            dir: dir.path().to_owned(),
        };
        let again = run_suite(&WithOwnArm, &config, origin, Some(&starting), &|_| ()).unwrap();
        let mine = &again.results[0].arms[2];
        assert_eq!(
            mine.starting_cases,
            result.arms[2].final_cases.as_ref().unwrap().len()
        );
        if mine.starting_cases > 0 {
            assert!(mine.trials[0].learned_start);
        }
    }
}

//! The domain to serve: a behavior space and the adapter configuration.
//!
//! Either a domain the tool's catalog builds (for `trustcbr`, `movement` and `patrol`: the
//! paper's spaces with the paper's adapter defaults) or a RON file declaring a space, and
//! optionally the adapter config, without writing Rust:
//!
//! ```ron
//! (
//!     space: (components: [
//!         (name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 20)),
//!         (name: "planner", values: Categorical(labels: ["astar", "rrt"])),
//!     ]),
//!     adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.95),
//! )
//! ```
//!
//! Every field is checked while it is read, so an error names the file, the line:column of
//! the offending value, and the field, and shows the line.

use cbr_core::{BehaviorSpace, FileError, RonError, parse_ron, read_text};
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;
use trust::AdapterConfig;

/// A domain ready to serve.
#[derive(Clone, Debug)]
pub struct DomainDefinition {
    /// How the domain was named (a scenario name or the file path).
    pub name: String,
    /// The behavior space.
    pub space: Arc<BehaviorSpace>,
    /// The adapter configuration (the paper's defaults unless the file sets it).
    pub adapter: AdapterConfig,
}

/// The layout of a domain file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DomainFile {
    space: BehaviorSpace,
    #[serde(default)]
    adapter: AdapterConfig,
}

/// Why a domain could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum DomainError {
    /// The name is neither a built-in domain nor an existing file.
    #[error("`{name}` is neither a built-in domain ({known}) nor an existing file")]
    Unknown {
        /// The name given.
        name: String,
        /// The built-in domains, comma-separated.
        known: String,
    },
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file is not a valid domain.
    #[error(transparent)]
    Parse(#[from] RonError),
}

impl DomainDefinition {
    /// A built-in domain: `space` under the paper's adapter defaults.
    pub fn builtin(name: &str, space: Arc<BehaviorSpace>) -> Self {
        Self {
            name: name.to_owned(),
            space,
            adapter: AdapterConfig::default(),
        }
    }

    /// Resolves a built-in domain's name (`builtin` finds it; `known` lists them for the
    /// error), or else a path to a RON domain file.
    pub fn resolve(
        name: &str,
        known: &[String],
        builtin: impl FnOnce(&str) -> Option<Self>,
    ) -> Result<Self, DomainError> {
        if let Some(domain) = builtin(name) {
            return Ok(domain);
        }
        if !Path::new(name).exists() {
            return Err(DomainError::Unknown {
                name: name.to_owned(),
                known: known.join(", "),
            });
        }
        Self::load(Path::new(name))
    }

    /// Reads and checks a RON domain file.
    pub fn load(path: &Path) -> Result<Self, DomainError> {
        let text = read_text(path)?;
        Self::from_ron(&text, path)
    }

    /// Parses a domain from RON text; `origin` names the source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, DomainError> {
        let file: DomainFile = parse_ron(text, origin)?;
        Ok(Self {
            name: origin.display().to_string(),
            space: Arc::new(file.space),
            adapter: file.adapter,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const GOOD: &str = r#"(
    space: (components: [
        (name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 20)),
        (name: "planner", values: Categorical(labels: ["astar", "rrt"])),
    ]),
    adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.9),
)"#;

    /// The error for `GOOD` with `from` replaced by `to`: `(line, column, message, shown)`,
    /// after checking that the error as shown starts with `robot.ron:line:column: message`.
    fn error_after(from: &str, to: &str) -> (usize, usize, String, String) {
        assert!(GOOD.contains(from), "{from}");
        let text = GOOD.replacen(from, to, 1);
        let error = DomainDefinition::from_ron(&text, Path::new("robot.ron")).unwrap_err();
        let shown = error.to_string();
        let DomainError::Parse(RonError {
            line,
            column,
            message,
            ..
        }) = error
        else {
            panic!("expected a parse error, got {shown}");
        };
        assert!(
            shown.starts_with(&format!("robot.ron:{line}:{column}: {message}\n")),
            "{shown}"
        );
        (line, column, message, shown)
    }

    #[test]
    fn a_good_file_loads() {
        let d = DomainDefinition::from_ron(GOOD, Path::new("robot.ron")).unwrap();
        assert_eq!(d.space.size(), 40);
        assert_eq!(d.adapter.thresholds.trustworthy, 3.0);
        assert_eq!(d.adapter.lambda, 0.9);
        // The adapter section is optional: the paper's defaults.
        let without = GOOD.replace(
            "adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.9),",
            "",
        );
        let d = DomainDefinition::from_ron(&without, Path::new("robot.ron")).unwrap();
        assert_eq!(d.adapter, AdapterConfig::default());
    }

    #[test]
    fn syntax_error_gives_file_line_column_and_excerpt() {
        let (line, column, _, shown) = error_after("step: 0.5", "step 0.5");
        assert_eq!(line, 3);
        assert!(column > 1);
        assert!(
            shown.starts_with(&format!("robot.ron:3:{column}: ")),
            "{shown}"
        );
        assert!(shown.contains("3 |         (name: \"speed\""), "{shown}");
    }

    #[test]
    fn unknown_field_is_named_where_it_is() {
        let (line, _, message, _) = error_after("unit: \"m/s\"", "unit: \"m/s\", colour: \"red\"");
        assert_eq!(line, 3);
        assert!(message.contains("colour"), "{message}");
        let (line, _, message, _) = error_after("lambda: 0.9", "lambda: 0.9, tau: 1");
        assert_eq!(line, 6);
        assert!(message.contains("tau"), "{message}");
    }

    #[test]
    fn negative_step_is_named_at_its_value() {
        let (line, column, message, _) = error_after("step: 0.5", "step: -0.5");
        assert_eq!(
            message,
            "field `step` must be a finite number > 0, got -0.5"
        );
        let text = GOOD.lines().nth(2).unwrap();
        // The column points just past the value.
        assert_eq!(line, 3);
        assert_eq!(
            column,
            text.find("step: 0.5").unwrap() + "step: -0.5".len() + 1
        );
    }

    #[test]
    fn lambda_outside_the_unit_interval_is_named() {
        for bad in ["0.0", "1.5", "-0.2"] {
            let (line, _, message, _) = error_after("lambda: 0.9", &format!("lambda: {bad}"));
            assert_eq!(line, 6);
            assert!(
                message.starts_with("field `lambda`: lambda must be in (0, 1]"),
                "{message}"
            );
        }
    }

    #[test]
    fn reversed_thresholds_are_named() {
        let (line, _, message, _) = error_after(
            "trustworthy: 3.0, untrustworthy: -3.0",
            "trustworthy: -3.0, untrustworthy: 3.0",
        );
        assert_eq!(line, 6);
        assert!(
            message.contains("untrustworthy < 0 < trustworthy"),
            "{message}"
        );
    }

    #[test]
    fn empty_components_are_named() {
        let (line, _, message, _) = error_after("count: 20", "count: 0");
        assert_eq!(line, 3);
        assert!(
            message.starts_with("field `count` must be at least 1"),
            "{message}"
        );
        let (line, _, message, _) = error_after(r#"labels: ["astar", "rrt"]"#, "labels: []");
        assert_eq!(line, 4);
        assert!(
            message.starts_with("field `labels` must name at least one value"),
            "{message}"
        );
        let (_, _, message, _) =
            error_after(r#"labels: ["astar", "rrt"]"#, r#"labels: ["rrt", "rrt"]"#);
        assert!(message.contains("label `rrt` appears twice"), "{message}");
    }

    #[test]
    fn a_grid_that_overflows_is_refused_at_load() {
        let (_, _, message, _) = error_after(
            "min: 0.5, step: 0.5, count: 20",
            "min: 1e308, step: 1e308, count: 20",
        );
        assert!(
            message.starts_with("component `speed`: the grid overflows: `min` 1e308"),
            "{message}"
        );
    }

    /// Every RON block of `docs/protocol.md` is a domain file that loads as written.
    #[test]
    fn the_documented_domain_file_loads() {
        let doc = include_str!("../../docs/protocol.md");
        let blocks: Vec<&str> = doc
            .split("```ron\n")
            .skip(1)
            .map(|rest| rest.split("```").next().unwrap())
            .collect();
        assert_eq!(blocks.len(), 1);
        let d = DomainDefinition::from_ron(blocks[0], Path::new("protocol.md")).unwrap();
        assert_eq!(d.adapter.retriever, trust::RetrieverKind::InvertedIndex);
        assert_eq!(d.space.size(), 8 * 10 * 3);
    }

    /// Resolves `name` with `movement` as the only built-in domain.
    fn resolve(name: &str) -> Result<DomainDefinition, DomainError> {
        DomainDefinition::resolve(name, &["movement".to_owned()], |n| {
            (n == "movement")
                .then(|| DomainDefinition::builtin(n, domains::spaces::movement_space()))
        })
    }

    #[test]
    fn builtin_names_and_missing_files() {
        assert_eq!(resolve("movement").unwrap().space.size(), 400);
        let err = resolve("/nonexistent/robot.ron").unwrap_err();
        assert_eq!(
            err.to_string(),
            "`/nonexistent/robot.ron` is neither a built-in domain (movement) nor an existing file"
        );
        let dir = tempfile::tempdir().unwrap();
        let err = resolve(dir.path().to_str().unwrap()).unwrap_err();
        assert!(matches!(err, DomainError::Io(_)), "{err}");
    }

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in any::<String>()) {
            let _ = DomainDefinition::from_ron(&text, Path::new("x.ron"));
        }

        #[test]
        fn arbitrary_files_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("x.ron");
            std::fs::write(&path, &bytes).unwrap();
            let _ = DomainDefinition::load(&path);
        }

        #[test]
        fn mangled_good_files_never_panic(cut in 0..GOOD.len(), insert in "[(),:\\[\\]a-z0-9. -]{0,4}") {
            let mut text = GOOD.to_owned();
            let cut = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            text.insert_str(cut, &insert);
            let _ = DomainDefinition::from_ron(&text, Path::new("x.ron"));
        }
    }
}

//! Reading RON text with errors that point at the place: file, line:column, what is wrong,
//! and the offending line with a caret under the column.
//!
//! Every RON input of the workspace (case bases, configs, operators, domain files) is read
//! through [`crate::read_text`] and [`parse_ron`], so every one reports its errors the same
//! way.

use serde::de::DeserializeOwned;
use std::fmt;
use std::path::{Path, PathBuf};

/// A RON document that does not parse into the expected type.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct RonError {
    /// The file (or a name for the source).
    pub path: PathBuf,
    /// 1-based line of the problem.
    pub line: usize,
    /// 1-based column of the problem.
    pub column: usize,
    /// What is wrong there, naming the field where the parser knows it.
    pub message: String,
    /// The offending line with a caret under the column (empty past the end of the text).
    pub excerpt: String,
}

impl fmt::Display for RonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.path.display(),
            self.line,
            self.column,
            self.message
        )?;
        if !self.excerpt.is_empty() {
            write!(f, "\n{}", self.excerpt)?;
        }
        Ok(())
    }
}

/// Parses `text` as RON into `T`; `origin` names the source in errors.
pub fn parse_ron<T: DeserializeOwned>(text: &str, origin: &Path) -> Result<T, RonError> {
    ron::from_str(text).map_err(|e| RonError {
        path: origin.to_owned(),
        line: e.position.line,
        column: e.position.col,
        // ron 0.8 writes "named `x`in `Outer`"; restore the space.
        message: e.code.to_string().replace("`in `", "` in `"),
        excerpt: excerpt(text, e.position.line, e.position.col),
    })
}

/// The 1-based `line` of `text` with a caret under the 1-based `column`.
fn excerpt(text: &str, line: usize, column: usize) -> String {
    let Some(source) = text.lines().nth(line.saturating_sub(1)) else {
        return String::new();
    };
    let gutter = line.to_string();
    let indent: String = source
        .chars()
        .take(column.saturating_sub(1))
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    format!(
        "{gutter} | {source}\n{} | {indent}^",
        " ".repeat(gutter.len())
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Point {
        x: f64,
        y: f64,
    }

    #[test]
    fn errors_show_the_place() {
        let err = parse_ron::<Point>("(\n  x: 1.0,\n  z: 2.0,\n)", Path::new("p.ron")).unwrap_err();
        assert_eq!((err.line, err.column), (3, 4));
        assert_eq!(
            err.to_string(),
            "p.ron:3:4: Unexpected field named `z` in `Point`, expected either `x` or `y` instead\n3 |   z: 2.0,\n  |    ^"
        );
    }

    #[test]
    fn an_error_past_the_end_has_no_excerpt() {
        let err = parse_ron::<Point>("(x: 1.0,\n", Path::new("p.ron")).unwrap_err();
        assert!(err.to_string().starts_with("p.ron:"), "{err}");
    }
}

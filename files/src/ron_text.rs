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
    /// The offending line with a caret under the column (empty past the end of the text);
    /// of a line longer than [`EXCERPT_CHARS`], the window around the column, its cut ends
    /// marked `…`.
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
        message: match e.code {
            // ron's own message suggests a crate to its programmers.
            ron::Error::ExceededRecursionLimit => format!(
                "nested more than {RECURSION_LIMIT} levels deep; no input of this program nests so deep"
            ),
            // ron 0.8 writes "named `x`in `Outer`"; restore the space.
            code => code.to_string().replace("`in `", "` in `"),
        },
        excerpt: excerpt(text, e.position.line, e.position.col),
    })
}

/// How deep ron lets a document nest (its default).
const RECURSION_LIMIT: usize = 128;

/// The most characters of the offending line an excerpt shows.
pub const EXCERPT_CHARS: usize = 120;

/// The 1-based `line` of `text` with a caret under the 1-based `column`: the whole line,
/// or the [`EXCERPT_CHARS`] around the column, with `…` where the line is cut.
fn excerpt(text: &str, line: usize, column: usize) -> String {
    let Some(source) = text.lines().nth(line.saturating_sub(1)) else {
        return String::new();
    };
    let chars: Vec<char> = source.chars().collect();
    let at = column.saturating_sub(1).min(chars.len());
    let start = at
        .saturating_sub(EXCERPT_CHARS / 2)
        .min(chars.len().saturating_sub(EXCERPT_CHARS));
    let end = chars.len().min(start + EXCERPT_CHARS);
    let cut_before = if start > 0 { "…" } else { "" };
    let cut_after = if end < chars.len() { "…" } else { "" };
    let shown: String = chars[start..end].iter().collect();
    let indent: String = cut_before
        .chars()
        .chain(chars[start..at].iter().copied())
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    let gutter = line.to_string();
    format!(
        "{gutter} | {cut_before}{shown}{cut_after}\n{} | {indent}^",
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
    fn deep_nesting_is_refused_in_the_users_terms() {
        let text = format!("{}{}", "[".repeat(300), "]".repeat(300));
        let err = parse_ron::<ron::Value>(&text, Path::new("deep.ron")).unwrap_err();
        assert_eq!(
            err.message,
            "nested more than 128 levels deep; no input of this program nests so deep"
        );
        assert!(!err.to_string().contains("serde_stacker"), "{err}");
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
    fn a_long_line_shows_a_window_around_the_column() {
        let padding = " ".repeat(200_000);
        let text = format!("(x: 1.0,{padding}z: 2.0,{padding}y: 3.0)");
        let err = parse_ron::<Point>(&text, Path::new("p.ron")).unwrap_err();
        let (shown, caret) = err.excerpt.split_once('\n').unwrap();
        assert!(
            shown.starts_with("1 | …") && shown.ends_with('…'),
            "{shown}"
        );
        assert_eq!(shown.chars().count(), "1 | ".len() + EXCERPT_CHARS + 2);
        // The caret stands under the character at the column (just past the unknown
        // field's name, as for a short line).
        let under = caret.chars().count() - 1;
        assert_eq!(shown.chars().nth(under), Some(':'), "{shown}\n{caret}");
        assert_eq!(shown.chars().nth(under - 1), Some('z'), "{shown}\n{caret}");
        // Near either end of the line, that end is shown uncut.
        let text = format!("(x: 1.0, z: 2.0,{padding} y: 3.0)");
        let err = parse_ron::<Point>(&text, Path::new("p.ron")).unwrap_err();
        assert!(err.excerpt.starts_with("1 | (x: 1.0, z"), "{}", err.excerpt);
        assert!(err.excerpt.lines().next().unwrap().ends_with('…'));
    }

    proptest::proptest! {
        /// Any line and column give an excerpt of at most the window, the caret within it.
        #[test]
        fn excerpts_are_bounded(source in "[a-z \t…é]{0,400}", column in 0usize..500) {
            let shown = excerpt(&source, 1, column);
            if let Some((line, caret)) = shown.split_once('\n') {
                proptest::prop_assert!(line.chars().count() <= "1 | ".len() + EXCERPT_CHARS + 2);
                proptest::prop_assert!(caret.chars().count() <= line.chars().count() + 1);
            }
        }
    }

    #[test]
    fn an_error_past_the_end_has_no_excerpt() {
        let err = parse_ron::<Point>("(x: 1.0,\n", Path::new("p.ron")).unwrap_err();
        assert!(err.to_string().starts_with("p.ron:"), "{err}");
    }
}

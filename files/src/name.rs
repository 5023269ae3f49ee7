//! Names a user gives that end up in file names, in one place, so that no name escapes the
//! folder it is written in or read from.
//!
//! Two kinds of names reach a path:
//! - a *file name* is used as it is, as one file or folder name (an arm's saved case base
//!   is `DIR/EXPERIMENT/ARM.ron`), and is checked by [`check_file_name`], which every
//!   writer and reader of such a file calls through [`file_in`]: 1 to
//!   [`MAX_NAME_BYTES`] bytes, no `/` or `\`, no control character, not starting with `.`
//!   (which also rules out `.` and `..`, and the hidden temporary files of an interrupted
//!   write);
//! - a *label* (an experiment's or a mission plan's name, which hold `/`) is only ever
//!   turned into a file name by [`file_stems`], which keeps `[A-Za-z0-9_-]` alone; a label
//!   is checked by [`check_label`]: 1 to [`MAX_LABEL_BYTES`] bytes, no control character
//!   (it is printed in tables and pages).

use std::path::{Path, PathBuf};

/// The longest file name a user may give, in bytes (with an extension such as `.ron` it
/// stays far below the 255 bytes file systems allow).
pub const MAX_NAME_BYTES: usize = 100;

/// The longest label a user may give, in bytes.
pub const MAX_LABEL_BYTES: usize = 200;

/// A name that cannot be used where it is given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} name `{}` {problem}", name.escape_debug())]
pub struct NameError {
    /// What it names: `arm`, `operator`, `population`, `plan`.
    pub what: &'static str,
    /// The name given.
    pub name: String,
    /// What is wrong with it, and what is allowed.
    pub problem: String,
}

/// Checks that `name`, naming a `what`, can be used as one file name as it is.
pub fn check_file_name(what: &'static str, name: &str) -> Result<(), NameError> {
    let problem = if name.is_empty() {
        Some("is empty".to_owned())
    } else if name.len() > MAX_NAME_BYTES {
        Some(format!(
            "is {} bytes long; at most {MAX_NAME_BYTES}",
            name.len()
        ))
    } else if let Some(c) = name
        .chars()
        .find(|c| matches!(c, '/' | '\\') || c.is_control())
    {
        Some(format!(
            "holds {}, which a file name may not",
            shown_char(c)
        ))
    } else if name.starts_with('.') {
        Some("starts with `.`, which a file name may not".to_owned())
    } else {
        None
    };
    match problem {
        None => Ok(()),
        Some(problem) => Err(NameError {
            what,
            name: name.to_owned(),
            problem: format!(
                "{problem} (it names a file: 1 to {MAX_NAME_BYTES} bytes, no `/`, `\\` or control character, not starting with `.`)"
            ),
        }),
    }
}

/// Checks that `name`, labelling a `what`, can be shown in tables and turned into a file
/// name by [`file_stems`].
pub fn check_label(what: &'static str, name: &str) -> Result<(), NameError> {
    let problem = if name.is_empty() {
        Some("is empty".to_owned())
    } else if name.len() > MAX_LABEL_BYTES {
        Some(format!(
            "is {} bytes long; at most {MAX_LABEL_BYTES}",
            name.len()
        ))
    } else {
        name.chars()
            .find(|c| c.is_control())
            .map(|c| format!("holds {}, which a name may not", shown_char(c)))
    };
    match problem {
        None => Ok(()),
        Some(problem) => Err(NameError {
            what,
            name: name.to_owned(),
            problem,
        }),
    }
}

/// A character as a message shows it: `/`, or a control character by its code.
fn shown_char(c: char) -> String {
    if c.is_control() {
        format!("the control character U+{:04X}", u32::from(c))
    } else {
        format!("`{c}`")
    }
}

/// The path of the file `name` (a `what`, checked by [`check_file_name`]) with
/// `extension` in `dir`: the one way a user's name becomes a path.
pub fn file_in(
    dir: &Path,
    what: &'static str,
    name: &str,
    extension: &str,
) -> Result<PathBuf, NameError> {
    check_file_name(what, name)?;
    Ok(dir.join(format!("{name}.{extension}")))
}

/// The longest stem [`file_stems`] makes before its `-2`, `-3`: with the longest prefix
/// and extension a report adds (`benchmark-...-ecdf.svg`), a file name stays well within
/// the 255 bytes a file system allows.
pub const MAX_STEM_BYTES: usize = 120;

/// A file-name stem per label (experiment names): every character outside
/// `[A-Za-z0-9_-]` replaced by `-` (an empty label is `-`), a stem longer than
/// [`MAX_STEM_BYTES`] cut and ended with a hash of the whole label (a label derived from
/// a number such as `1e-300` spells out hundreds of digits), and `-2`, `-3`, ... added
/// where two would collide.
pub fn file_stems(names: impl IntoIterator<Item = impl AsRef<str>>) -> Vec<String> {
    let mut stems: Vec<String> = Vec::new();
    for name in names {
        let base: String = name
            .as_ref()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    c
                } else {
                    '-'
                }
            })
            .collect();
        let base = if base.is_empty() {
            "-".to_owned()
        } else if base.len() > MAX_STEM_BYTES {
            // ASCII alone by now, so any byte is a character boundary.
            let hash = fnv1a(name.as_ref().as_bytes());
            format!("{}-{hash:016x}", &base[..MAX_STEM_BYTES - 17])
        } else {
            base
        };
        let mut stem = base.clone();
        let mut k = 2;
        while stems.contains(&stem) {
            stem = format!("{base}-{k}");
            k += 1;
        }
        stems.push(stem);
    }
    stems
}

/// The 64-bit FNV-1a hash of `bytes`: stable across versions and platforms, so a long
/// label's stem is the same in every run.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn names_that_would_leave_their_folder_are_refused() {
        for (name, problem) in [
            ("../../victim", "holds `/`"),
            ("..", "starts with `.`"),
            (".hidden", "starts with `.`"),
            ("a\\b", "holds `\\`"),
            ("", "is empty"),
            ("tab\there", "holds the control character U+0009"),
        ] {
            let err = check_file_name("arm", name).unwrap_err().to_string();
            assert!(
                err.starts_with("arm name `") && err.contains(problem),
                "{name:?}: {err}"
            );
        }
        let long = "x".repeat(MAX_NAME_BYTES + 1);
        assert!(check_file_name("arm", &long).is_err());
        for name in [
            "case-based+learned-start",
            "case-based+py",
            "My arm (v2)",
            "família",
        ] {
            check_file_name("arm", name).unwrap();
        }
        assert_eq!(
            file_in(Path::new("d"), "arm", "uniform", "ron").unwrap(),
            Path::new("d/uniform.ron")
        );
        check_label("plan", "movement/paper").unwrap();
        assert!(check_label("plan", "").is_err());
        assert!(check_label("plan", "a\u{1b}[31m").is_err());
    }

    #[test]
    fn stems_are_distinct_and_plain() {
        assert_eq!(
            file_stems(["movement/balanced", "movement/balanced", "a.b", "..", ""]),
            ["movement-balanced", "movement-balanced-2", "a-b", "--", "-"]
        );
    }

    proptest! {
        /// Whatever a user writes, a checked file name is one entry of its folder.
        #[test]
        fn a_checked_name_stays_in_its_folder(name in any::<String>()) {
            if let Ok(path) = file_in(Path::new("/base"), "arm", &name, "ron") {
                prop_assert_eq!(path.parent(), Some(Path::new("/base")));
                prop_assert!(path.file_name().is_some());
            }
            for stem in file_stems([&name]) {
                prop_assert!(!stem.is_empty());
                prop_assert!(stem.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'));
            }
        }
    }

    #[test]
    fn a_long_label_gets_a_short_stem_of_its_own() {
        let tiny = format!("movement/balanced/g{}", 1e-300_f64);
        let other = format!("movement/balanced/g{}", 2e-300_f64);
        let stems = file_stems([&tiny, &other, &tiny]);
        assert!(
            stems.iter().all(|s| s.len() <= MAX_STEM_BYTES + 2),
            "{stems:?}"
        );
        assert!(stems[0].starts_with("movement-balanced-g0-000"));
        assert_ne!(
            stems[0], stems[1],
            "labels alike for 103 bytes keep their own stems"
        );
        assert_eq!(stems[2], format!("{}-2", stems[0]));
        assert_eq!(
            file_stems([&tiny]),
            stems[..1],
            "the same stem in every run"
        );
    }
}

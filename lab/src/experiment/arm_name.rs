//! An arm's name as a typed value: the arm it is built on and the options its suffixes add.
//!
//! A name such as `case-based+conditioned+context-blind+learned-start` is read once, where
//! it enters (a config, the command line, Python, a saved report), into an [`ArmName`]:
//! its base (`case-based+conditioned`, a built-in arm or a user's own) and its
//! [`NameOptions`]. Everything after reads the options, never the string. The suffixes are
//! written each at most once, in one order:
//! `NAME[+context-blind][+ignores-statements][+learned-start][+competent]`.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// What follows the name of an arm that is not told the robot's context, as the paper's
/// robot is not ([`crate::Arm::blind_to_context`]): `case-based+context-blind`.
pub const CONTEXT_BLIND: &str = "+context-blind";

/// What follows the name of an arm that does not hear what operators state up front
/// ([`crate::Arm::ignoring_statements`]): `case-based+cause-aware+ignores-statements`.
pub const IGNORES_STATEMENTS: &str = "+ignores-statements";

/// What ends the name of an arm that starts each episode from the memory's guess
/// ([`Initial::Learned`]): `case-based+conditioned+learned-start`.
pub const LEARNED_START: &str = "+learned-start";

/// What ends the name of an arm that prefers behaviors the robot judges competent
/// ([`crate::Arm::preferring_competent`]): `case-based+conditioned+competent`.
pub const PREFERS_COMPETENT: &str = "+competent";

/// The suffixes in the order a name writes them.
const SUFFIXES: [&str; 4] = [
    CONTEXT_BLIND,
    IGNORES_STATEMENTS,
    LEARNED_START,
    PREFERS_COMPETENT,
];

/// How each episode of an arm starts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Initial {
    /// The trial's uniformly random behavior (the paper's protocol).
    #[default]
    Random,
    /// The case memory's best guess for an operator it does not yet know
    /// ([`trust::start`]); the trial's random behavior while the memory is empty.
    Learned,
}

/// What the suffixes of an arm's name add to the arm it is built on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NameOptions {
    /// Not told the robot's context ([`CONTEXT_BLIND`]).
    pub context_blind: bool,
    /// Not hearing what operators state up front ([`IGNORES_STATEMENTS`]).
    pub ignores_statements: bool,
    /// How each episode starts ([`LEARNED_START`]).
    pub initial: Initial,
    /// Passing over trusted behaviors the robot is sure are not competent
    /// ([`PREFERS_COMPETENT`]).
    pub prefers_competent: bool,
}

impl NameOptions {
    /// The suffixes, in order (empty for an arm with none).
    pub fn suffixes(self) -> String {
        SUFFIXES
            .into_iter()
            .filter(|suffix| self.has(suffix))
            .collect()
    }

    /// Whether the option `suffix` (one of [`SUFFIXES`]) is on.
    fn has(self, suffix: &str) -> bool {
        match suffix {
            CONTEXT_BLIND => self.context_blind,
            IGNORES_STATEMENTS => self.ignores_statements,
            LEARNED_START => self.initial == Initial::Learned,
            _ => self.prefers_competent,
        }
    }

    /// The same options with `suffix` (one of [`SUFFIXES`]) on.
    fn with(mut self, suffix: &str) -> Self {
        match suffix {
            CONTEXT_BLIND => self.context_blind = true,
            IGNORES_STATEMENTS => self.ignores_statements = true,
            LEARNED_START => self.initial = Initial::Learned,
            _ => self.prefers_competent = true,
        }
        self
    }
}

/// An arm's name, read: the arm it is built on ([`ArmName::base`]) and what its suffixes
/// add ([`ArmName::options`]). Written and read back as the plain name.
///
/// ```
/// use lab::{ArmName, Initial};
///
/// let name: ArmName = "case-based+conditioned+learned-start".parse().unwrap();
/// assert_eq!(name.base(), "case-based+conditioned");
/// assert_eq!(name.options().initial, Initial::Learned);
/// assert_eq!(name.to_string(), "case-based+conditioned+learned-start");
/// ```
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct ArmName {
    /// The whole name, base then suffixes.
    name: String,
    /// The length of the base at the front of `name`.
    base_len: usize,
    options: NameOptions,
}

/// A name whose suffixes are written twice or out of order.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.message())]
pub struct ArmNameError {
    /// The name as written.
    pub name: String,
    /// The suffix written twice or out of order.
    pub suffix: &'static str,
    /// Whether it was written twice (else out of order).
    pub twice: bool,
    /// The arm the name evidently means: its base with every suffix it writes, once each,
    /// in order.
    pub meant: ArmName,
}

impl ArmNameError {
    fn message(&self) -> String {
        let (name, suffix, write) = (&self.name, self.suffix, &self.meant);
        if self.twice {
            format!("`{name}` says {suffix} twice; write `{write}`")
        } else {
            format!(
                "`{name}` writes {suffix} out of order (NAME{}); write `{write}`",
                SUFFIXES.concat()
            )
        }
    }
}

impl ArmName {
    /// `name` read: its suffixes peeled off from the end, each at most once and in order
    /// (a name with none is an arm of its own, built in or a user's).
    pub fn parse(name: &str) -> Result<Self, ArmNameError> {
        let mut base = name;
        let mut options = NameOptions::default();
        // The place in SUFFIXES of the last suffix peeled: each earlier one must sit before.
        let mut last = SUFFIXES.len();
        let mut fault = None;
        while let Some((place, suffix)) = SUFFIXES
            .iter()
            .enumerate()
            .find(|(_, suffix)| base.ends_with(*suffix))
        {
            if fault.is_none() && place >= last {
                fault = Some((*suffix, options.has(suffix)));
            }
            last = last.min(place);
            options = options.with(suffix);
            base = &base[..base.len() - suffix.len()];
        }
        let read = Self::new(base, options);
        match fault {
            None => Ok(read),
            Some((suffix, twice)) => Err(ArmNameError {
                name: name.to_owned(),
                suffix,
                twice,
                meant: read,
            }),
        }
    }

    /// The arm `base` with `options` (`base` is taken as it is, suffixes or not: a name to
    /// read is [`ArmName::parse`]'s).
    pub fn new(base: &str, options: NameOptions) -> Self {
        Self {
            name: format!("{base}{}", options.suffixes()),
            base_len: base.len(),
            options,
        }
    }

    /// The name of the arm it is built on.
    pub fn base(&self) -> &str {
        &self.name[..self.base_len]
    }

    /// What the suffixes add.
    pub fn options(&self) -> NameOptions {
        self.options
    }

    /// The same base with `options`.
    pub fn with_options(&self, options: NameOptions) -> Self {
        Self::new(self.base(), options)
    }

    /// The whole name, as written in reports.
    pub fn as_str(&self) -> &str {
        &self.name
    }

    /// `names` written one after the other with `separator` between them.
    pub fn join(names: &[ArmName], separator: &str) -> String {
        names
            .iter()
            .map(ArmName::as_str)
            .collect::<Vec<_>>()
            .join(separator)
    }
}

impl fmt::Display for ArmName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

impl fmt::Debug for ArmName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.name, f)
    }
}

impl PartialOrd for ArmName {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// By the whole name, as a report sorts names.
impl Ord for ArmName {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.name.cmp(&other.name)
    }
}

impl FromStr for ArmName {
    type Err = ArmNameError;
    fn from_str(name: &str) -> Result<Self, ArmNameError> {
        Self::parse(name)
    }
}

impl AsRef<str> for ArmName {
    fn as_ref(&self) -> &str {
        &self.name
    }
}

impl PartialEq<str> for ArmName {
    fn eq(&self, other: &str) -> bool {
        self.name == other
    }
}

impl PartialEq<&str> for ArmName {
    fn eq(&self, other: &&str) -> bool {
        self.name == *other
    }
}

impl Serialize for ArmName {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name)
    }
}

impl<'de> Deserialize<'de> for ArmName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Self::parse(&name).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(name: &str) -> Result<(String, NameOptions), String> {
        ArmName::parse(name)
            .map(|n| (n.base().to_owned(), n.options()))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn suffixes_are_read_in_one_order_and_a_wrong_one_says_what_to_write() {
        assert_eq!(
            read("mine+context-blind+competent"),
            Ok((
                "mine".to_owned(),
                NameOptions {
                    context_blind: true,
                    ignores_statements: false,
                    initial: Initial::Random,
                    prefers_competent: true,
                }
            ))
        );
        let all = NameOptions {
            context_blind: true,
            ignores_statements: true,
            initial: Initial::Learned,
            prefers_competent: true,
        };
        assert_eq!(
            all.suffixes(),
            "+context-blind+ignores-statements+learned-start+competent"
        );
        assert_eq!(NameOptions::default().suffixes(), "");
        for (name, expected) in [
            (
                "hedged+learned-start+ignores-statements",
                "`hedged+learned-start+ignores-statements` writes +learned-start out of order (NAME+context-blind+ignores-statements+learned-start+competent); write `hedged+ignores-statements+learned-start`",
            ),
            (
                "uniform+learned-start+context-blind",
                "`uniform+learned-start+context-blind` writes +learned-start out of order (NAME+context-blind+ignores-statements+learned-start+competent); write `uniform+context-blind+learned-start`",
            ),
            (
                "uniform+competent+learned-start",
                "`uniform+competent+learned-start` writes +competent out of order (NAME+context-blind+ignores-statements+learned-start+competent); write `uniform+learned-start+competent`",
            ),
            (
                "uniform+context-blind+context-blind",
                "`uniform+context-blind+context-blind` says +context-blind twice; write `uniform+context-blind`",
            ),
            (
                "uniform+learned-start+learned-start+competent",
                "`uniform+learned-start+learned-start+competent` says +learned-start twice; write `uniform+learned-start+competent`",
            ),
        ] {
            assert_eq!(read(name), Err(expected.to_owned()), "{name}");
        }
    }

    #[test]
    fn a_wrong_name_still_says_every_option_it_writes() {
        let err = ArmName::parse("case-based+context-blind+competent+context-blind").unwrap_err();
        assert_eq!(err.meant.as_str(), "case-based+context-blind+competent");
        assert_eq!((err.suffix, err.twice), (PREFERS_COMPETENT, false));
    }

    #[test]
    fn a_name_is_written_and_read_back_as_itself() {
        for name in [
            "random-walk",
            "mine",
            "case-based+cause-aware+ignores-statements+learned-start",
            "learned-start",
        ] {
            let read = ArmName::parse(name).unwrap();
            assert_eq!(read.to_string(), name);
            let json = serde_json::to_string(&read).unwrap();
            assert_eq!(json, format!("\"{name}\""));
            assert_eq!(serde_json::from_str::<ArmName>(&json).unwrap(), read);
        }
        let bad = serde_json::from_str::<ArmName>("\"x+competent+competent\"").unwrap_err();
        assert!(bad.to_string().contains("says +competent twice"), "{bad}");
    }
}

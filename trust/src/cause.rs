//! Causes of failure as the domain names them.
//!
//! A failed or interrupted command may carry a [`Cause`]: a short name such as
//! `too-slow` or `dropped-item`. This crate knows no particular cause; every domain
//! declares its own (the lab's `Domain::causes`), each as a [`DeclaredCause`] with an
//! optional default weight, and outcomes carry those names. A cause is a small `Copy`
//! value (the name is held inline), so outcomes stay `Copy` and the cause-aware search
//! compares and hashes causes without allocating.
//!
//! The rule for a name ([`CAUSE_RULE`]): 1 to 32 bytes of lower-case kebab-case, that is
//! words of `a-z` and `0-9` joined by single hyphens (`too-slow`, `dropped-item`,
//! `404`). [`Cause::new`] checks it at run time; [`Cause::from_static`] in a `const`
//! checks it at compile time:
//!
//! ```
//! use trust::Cause;
//! const TOO_SLOW: Cause = Cause::from_static("too-slow");
//! assert_eq!(TOO_SLOW.as_str(), "too-slow");
//! assert_eq!(Cause::new("too-slow"), Ok(TOO_SLOW));
//! assert!(Cause::new("Too slow").is_err());
//! ```
//!
//! ```compile_fail
//! // A bad name in a `const` does not compile.
//! const BAD: trust::Cause = trust::Cause::from_static("Too slow");
//! ```
//!
//! In serde formats a cause is a plain string, checked as it is read, so a RON or JSON
//! error points at the offending value.

use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The longest cause name, in bytes.
pub const MAX_CAUSE_LEN: usize = 32;

/// The rule every cause name follows, as error messages state it.
pub const CAUSE_RULE: &str = "a cause is 1 to 32 bytes of lower-case kebab-case: words of a-z and 0-9 joined by single hyphens, e.g. `too-slow`";

/// Why a command failed or was interrupted: a name the domain declares (see the module
/// documentation for the rule). Ordered, compared and hashed by its name.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Cause {
    /// The name's bytes, padded with zeros. Every name byte is non-zero, so comparing the
    /// padded arrays orders causes as their names.
    bytes: [u8; MAX_CAUSE_LEN],
    len: u8,
}

/// A cause name that breaks the rule ([`CAUSE_RULE`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CauseError {
    /// No name.
    #[error("a cause name is empty; {CAUSE_RULE}")]
    Empty,
    /// More than [`MAX_CAUSE_LEN`] bytes.
    #[error("cause `{name}` is {len} bytes long; {CAUSE_RULE}")]
    TooLong {
        /// The name given.
        name: String,
        /// Its length in bytes.
        len: usize,
    },
    /// A character outside `a-z`, `0-9` and `-`.
    #[error("cause `{name}` has {found:?} at byte {at}; {CAUSE_RULE}")]
    Character {
        /// The name given.
        name: String,
        /// The offending character.
        found: char,
        /// Its byte offset.
        at: usize,
    },
    /// A hyphen first, last or next to another.
    #[error("cause `{name}` has a hyphen at its start, its end or next to another; {CAUSE_RULE}")]
    Hyphen {
        /// The name given.
        name: String,
    },
}

/// What is wrong with `name`, if anything (`const`, so [`Cause::from_static`] can check a
/// name at compile time). Returns the problem and the byte offset it was found at.
const fn problem(name: &[u8]) -> Option<(Problem, usize)> {
    if name.is_empty() {
        return Some((Problem::Empty, 0));
    }
    if name.len() > MAX_CAUSE_LEN {
        return Some((Problem::TooLong, MAX_CAUSE_LEN));
    }
    let mut i = 0;
    while i < name.len() {
        let b = name[i];
        if b == b'-' {
            if i == 0 || i == name.len() - 1 || name[i - 1] == b'-' {
                return Some((Problem::Hyphen, i));
            }
        } else if !(b.is_ascii_lowercase() || b.is_ascii_digit()) {
            return Some((Problem::Character, i));
        }
        i += 1;
    }
    None
}

#[derive(Clone, Copy)]
enum Problem {
    Empty,
    TooLong,
    Character,
    Hyphen,
}

impl Cause {
    /// The cause named `name`, checked against [`CAUSE_RULE`].
    pub fn new(name: &str) -> Result<Self, CauseError> {
        match problem(name.as_bytes()) {
            None => Ok(Self::inline(name.as_bytes())),
            Some((Problem::Empty, _)) => Err(CauseError::Empty),
            Some((Problem::TooLong, _)) => Err(CauseError::TooLong {
                name: shortened(name),
                len: name.len(),
            }),
            Some((Problem::Character, at)) => Err(CauseError::Character {
                name: name.to_owned(),
                found: name[at..].chars().next().unwrap_or('?'),
                at,
            }),
            Some((Problem::Hyphen, _)) => Err(CauseError::Hyphen {
                name: name.to_owned(),
            }),
        }
    }

    /// The cause named `name`, for names written in the code. In a `const` a name that
    /// breaks [`CAUSE_RULE`] is a compile-time error.
    ///
    /// # Panics
    /// When `name` breaks the rule (at compile time in a `const`).
    pub const fn from_static(name: &'static str) -> Self {
        match problem(name.as_bytes()) {
            None => Self::inline(name.as_bytes()),
            Some(_) => panic!(
                "not a cause name: a cause is 1 to 32 bytes of lower-case kebab-case (a-z, 0-9, single hyphens between words)"
            ),
        }
    }

    /// Copies a checked name inline.
    const fn inline(name: &[u8]) -> Self {
        let mut bytes = [0u8; MAX_CAUSE_LEN];
        let mut i = 0;
        while i < name.len() {
            bytes[i] = name[i];
            i += 1;
        }
        Self {
            bytes,
            len: name.len() as u8,
        }
    }

    /// The cause's name as written in configs and protocols (e.g. `too-slow`).
    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..usize::from(self.len)])
            .expect("a cause name is ASCII, checked at construction")
    }
}

/// `name`, cut after about 40 bytes (a name too long to be a cause may be very long).
fn shortened(name: &str) -> String {
    match name.char_indices().nth(40) {
        Some((end, _)) => format!("{}...", &name[..end]),
        None => name.to_owned(),
    }
}

impl fmt::Display for Cause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Debug for Cause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Cause({:?})", self.as_str())
    }
}

impl std::str::FromStr for Cause {
    type Err = CauseError;

    fn from_str(s: &str) -> Result<Self, CauseError> {
        Self::new(s)
    }
}

impl Serialize for Cause {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Cause {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct CauseVisitor;

        impl Visitor<'_> for CauseVisitor {
            type Value = Cause;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a cause name as a string, such as \"too-slow\"")
            }

            fn visit_str<E: de::Error>(self, v: &str) -> Result<Cause, E> {
                Cause::new(v).map_err(E::custom)
            }
        }

        deserializer.deserialize_str(CauseVisitor)
    }
}

/// A cause a domain declares: its name and, optionally, the weight an outcome with this
/// cause has when nothing else gives one (how a domain uses it is the domain's: the UGV
/// domain's operators fall back on it before their own `default` weight).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeclaredCause {
    /// The cause's name.
    pub name: Cause,
    /// Its default weight: finite and `>= 0` (checked when read); written as a plain
    /// number (`default_weight: 0.5`) or left out.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "serialize_default_weight",
        deserialize_with = "deserialize_default_weight"
    )]
    pub default_weight: Option<f64>,
}

/// A declared default weight that is negative or not a number.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "the default weight of cause `{cause}` must be a finite number >= 0, got {}",
    cbr_core::Shown(*.weight)
)]
pub struct DefaultWeightError {
    /// The cause.
    pub cause: Cause,
    /// The weight given.
    pub weight: f64,
}

fn serialize_default_weight<S: Serializer>(
    weight: &Option<f64>,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    match weight {
        Some(w) => serializer.serialize_f64(*w),
        None => serializer.serialize_none(),
    }
}

fn deserialize_default_weight<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Option<f64>, D::Error> {
    let weight = f64::deserialize(deserializer)?;
    if weight.is_finite() && weight >= 0.0 {
        Ok(Some(weight))
    } else {
        Err(de::Error::custom(format_args!(
            "`default_weight` must be a finite number >= 0, got {}",
            cbr_core::Shown(weight)
        )))
    }
}

impl DeclaredCause {
    /// A cause declared without a default weight.
    pub const fn new(name: Cause) -> Self {
        Self {
            name,
            default_weight: None,
        }
    }

    /// A cause declared with a default weight (checked: finite and `>= 0`).
    pub fn with_default_weight(name: Cause, weight: f64) -> Result<Self, DefaultWeightError> {
        if weight.is_finite() && weight >= 0.0 {
            Ok(Self {
                name,
                default_weight: Some(weight),
            })
        } else {
            Err(DefaultWeightError {
                cause: name,
                weight,
            })
        }
    }
}

/// A cause that is not among those declared.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "cause `{cause}` is not declared (declared: {})",
    list_causes(declared)
)]
pub struct UndeclaredCause {
    /// The cause given.
    pub cause: Cause,
    /// The causes declared.
    pub declared: Vec<Cause>,
}

/// `a, b, c`, or `none` for an empty list.
pub fn list_causes(causes: &[Cause]) -> String {
    if causes.is_empty() {
        return "none".to_owned();
    }
    causes
        .iter()
        .map(Cause::as_str)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The declaration of `cause` in `declared`, or an error listing the declared causes.
pub fn find_declared(
    declared: &[DeclaredCause],
    cause: Cause,
) -> Result<&DeclaredCause, UndeclaredCause> {
    declared
        .iter()
        .find(|d| d.name == cause)
        .ok_or_else(|| UndeclaredCause {
            cause,
            declared: declared.iter().map(|d| d.name).collect(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const TOO_SLOW: Cause = Cause::from_static("too-slow");
    const DROPPED: Cause = Cause::from_static("dropped-item");

    #[test]
    fn names_follow_the_rule() {
        for good in ["a", "too-slow", "404", "x1-y2-z3", &"a".repeat(32)] {
            assert_eq!(Cause::new(good).unwrap().as_str(), good);
        }
        assert_eq!(Cause::new(""), Err(CauseError::Empty));
        let long = "a".repeat(33);
        assert_eq!(
            Cause::new(&long).unwrap_err().to_string(),
            format!("cause `{long}` is 33 bytes long; {CAUSE_RULE}")
        );
        let huge = "b".repeat(10_000);
        assert_eq!(
            Cause::new(&huge).unwrap_err(),
            CauseError::TooLong {
                name: format!("{}...", &huge[..40]),
                len: 10_000
            }
        );
        assert_eq!(
            Cause::new("Too-slow"),
            Err(CauseError::Character {
                name: "Too-slow".into(),
                found: 'T',
                at: 0
            })
        );
        assert!(matches!(
            Cause::new("too_slow"),
            Err(CauseError::Character {
                found: '_',
                at: 3,
                ..
            })
        ));
        assert!(matches!(
            Cause::new("trop-lenté"),
            Err(CauseError::Character {
                found: 'é',
                at: 9,
                ..
            })
        ));
        for bad in ["-a", "a-", "a--b", "-"] {
            assert!(
                matches!(Cause::new(bad), Err(CauseError::Hyphen { .. })),
                "{bad}"
            );
        }
    }

    #[test]
    fn causes_order_as_their_names_and_stay_small() {
        let mut names = ["too-slow", "dropped-item", "a", "ab", "a-b", "b", "9"];
        let mut causes: Vec<Cause> = names.iter().map(|n| Cause::new(n).unwrap()).collect();
        causes.sort();
        names.sort_unstable();
        let sorted: Vec<&str> = causes.iter().map(Cause::as_str).collect();
        assert_eq!(sorted, names);
        assert!(std::mem::size_of::<Cause>() <= 33);
        assert_eq!(
            format!("{DROPPED} {DROPPED:?}"),
            "dropped-item Cause(\"dropped-item\")"
        );
    }

    #[test]
    fn serde_reads_and_checks_plain_strings() {
        assert_eq!(serde_json::to_string(&TOO_SLOW).unwrap(), "\"too-slow\"");
        assert_eq!(
            serde_json::from_str::<Cause>("\"too-slow\"").unwrap(),
            TOO_SLOW
        );
        let err = serde_json::from_str::<Cause>("\"Too slow\"").unwrap_err();
        assert!(
            err.to_string()
                .contains("cause `Too slow` has 'T' at byte 0"),
            "{err}"
        );
        let err = ron::from_str::<DeclaredCause>("(name: \"a--b\")").unwrap_err();
        assert_eq!(err.position.line, 1);
        assert!(err.code.to_string().contains("hyphen"), "{err}");
        let d: DeclaredCause = ron::from_str("(name: \"too-slow\", default_weight: 0.5)").unwrap();
        assert_eq!(
            d,
            DeclaredCause::with_default_weight(TOO_SLOW, 0.5).unwrap()
        );
        let d: DeclaredCause = ron::from_str("(name: \"too-slow\")").unwrap();
        assert_eq!(d, DeclaredCause::new(TOO_SLOW));
        for d in [
            DeclaredCause::new(DROPPED),
            DeclaredCause::with_default_weight(DROPPED, 2.5).unwrap(),
        ] {
            let text = ron::to_string(&d).unwrap();
            assert_eq!(ron::from_str::<DeclaredCause>(&text).unwrap(), d, "{text}");
        }
        for bad in ["-1.0", "inf", "NaN"] {
            let text = format!("(name: \"too-slow\", default_weight: {bad})");
            let err = ron::from_str::<DeclaredCause>(&text).unwrap_err();
            assert!(err.code.to_string().contains("finite number >= 0"), "{err}");
        }
        assert!(ron::from_str::<DeclaredCause>("(name: \"a\", colour: 1)").is_err());
        assert!(DeclaredCause::with_default_weight(TOO_SLOW, -0.5).is_err());
    }

    #[test]
    fn an_undeclared_cause_lists_the_declared_ones() {
        let declared = [DeclaredCause::new(TOO_SLOW), DeclaredCause::new(DROPPED)];
        assert_eq!(find_declared(&declared, DROPPED).unwrap().name, DROPPED);
        let err = find_declared(&declared, Cause::from_static("overheated")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "cause `overheated` is not declared (declared: too-slow, dropped-item)"
        );
        let err = find_declared(&[], TOO_SLOW).unwrap_err();
        assert_eq!(
            err.to_string(),
            "cause `too-slow` is not declared (declared: none)"
        );
    }

    proptest! {
        /// Every valid name round-trips through `new`, `as_str` and serde.
        #[test]
        fn valid_names_round_trip(name in "[a-z0-9]{1,8}(-[a-z0-9]{1,7}){0,2}") {
            let cause = Cause::new(&name).unwrap();
            prop_assert_eq!(cause.as_str(), name.as_str());
            let json = serde_json::to_string(&cause).unwrap();
            prop_assert_eq!(serde_json::from_str::<Cause>(&json).unwrap(), cause);
        }

        /// Arbitrary text is either a valid name or refused, never a panic.
        #[test]
        fn arbitrary_text_is_checked(name in any::<String>()) {
            if let Ok(cause) = Cause::new(&name) {
                prop_assert_eq!(cause.as_str(), name.as_str());
            }
        }
    }
}

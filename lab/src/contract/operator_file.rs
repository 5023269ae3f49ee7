//! Operator files: a domain's operator model read from RON and checked before any run,
//! with errors that name the file, the operator and what to fix.
//!
//! A domain's operator type has the standard fields ([`StandardFields`]: a name, a
//! patience, [`OutcomeWeights`] and a feedback channel, most simply declared with
//! [`standard_operator!`](crate::standard_operator)) and implements [`OperatorData`]:
//! the ranges of its own fields (through a [`RangeCheck`]) and, optionally, rules of the
//! domain's own. [`load`] and [`from_ron`] then check an operator in one order, stopping
//! at the first problem:
//!
//! 1. the text is read ([`files::read_text`]: [`OperatorFileError::Io`]) and parsed as the
//!    type ([`files::parse_ron`]: [`OperatorFileError::Syntax`], at line:column);
//! 2. every field the type's [`OperatorData::validate`] checks is in its range, then the
//!    standard `give_up_factor` (at least 1) ([`OperatorFileError::Range`]: the first one
//!    out of range, in the order checked);
//! 3. the weights are finite and at least 0 and name only the causes the domain declares
//!    ([`OutcomeWeights::check`], which fills in the declared default weights:
//!    [`OperatorFileError::Weights`]);
//! 4. when the type names the causes its robot perceives itself
//!    ([`OperatorData::PERCEIVED`]), the weights name only those
//!    ([`check_perceived_weights`]: [`OperatorFileError::Unperceived`]);
//! 5. the domain's own rules hold ([`OperatorData::check_rules`], its own error in
//!    [`OperatorFileError::Rule`]).
//!
//! Every error after parsing starts `FILE: operator `NAME`: `.
//!
//! [`shipped`] reads the operators a crate embeds in its binary the same way, and
//! [`named`] pairs operators with their names, as a catalog lists them.
//!
//! ```
//! use lab::contract::operator_file::{self, OperatorData, RangeCheck};
//! use serde::Deserialize;
//! use std::convert::Infallible;
//! use std::path::Path;
//! use trust::{Cause, DeclaredCause};
//!
//! lab::standard_operator! {
//!     /// A courier's operator: how long a delivery may take, and how often it interrupts
//!     /// a late one.
//!     #[derive(Debug, Deserialize)]
//!     struct Dispatcher {
//!         t_complete: f64,
//!         p_deadline: f64,
//!     }
//! }
//!
//! impl OperatorData for Dispatcher {
//!     type Invalid = Infallible;
//!
//!     fn validate(&self, check: &mut RangeCheck) {
//!         check.positive("t_complete", self.t_complete);
//!         check.probability("p_deadline", self.p_deadline);
//!     }
//! }
//!
//! let causes = [DeclaredCause::new(Cause::from_static("late"))];
//! let origin = Path::new("ops/night.ron");
//! let night: Dispatcher = operator_file::from_ron(
//!     r#"(name: "night", t_complete: 600.0, p_deadline: 0.2, weights: (by_cause: {"late": 2.0}))"#,
//!     origin,
//!     &causes,
//! )?;
//! assert_eq!(night.weights.of(Cause::from_static("late")), 2.0);
//!
//! let err = operator_file::from_ron::<Dispatcher>(
//!     r#"(name: "night", t_complete: 600.0, p_deadline: 1.2)"#,
//!     origin,
//!     &causes,
//! )
//! .unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     "ops/night.ron: operator `night`: `p_deadline` must be a probability in [0, 1], got 1.2"
//! );
//!
//! // The operators a crate ships in its binary (`include_str!` of its files), in order,
//! // and paired with their names as a catalog lists them; a bad one names its file.
//! let day = ("operators/day.ron", r#"(name: "day", t_complete: 300.0, p_deadline: 0.9)"#);
//! let shipped: Vec<Dispatcher> = operator_file::shipped(&[day], &causes)?;
//! assert_eq!(operator_file::named(shipped)[0].0, "day");
//! let bad = ("operators/bad.ron", r#"(name: "bad", t_complete: -1.0, p_deadline: 0.9)"#);
//! let err = operator_file::shipped::<Dispatcher>(&[day, bad], &causes).unwrap_err();
//! assert!(err.to_string().starts_with("operators/bad.ron: operator `bad`: `t_complete`"));
//! # Ok::<(), lab::contract::operator_file::OperatorFileError>(())
//! ```

use files::{FileError, RonError, parse_ron, read_text};
use serde::de::DeserializeOwned;
use std::convert::Infallible;
use std::fmt;
use std::path::{Path, PathBuf};
use trust::cause::list_causes;
use trust::{Cause, DeclaredCause, OutcomeWeights, WeightsError};

use crate::contract::operator::StandardFields;

/// An operator model a domain reads from a file: what [`load`] and [`from_ron`] need to
/// check it beyond its [`StandardFields`].
pub trait OperatorData: DeserializeOwned + StandardFields {
    /// What the domain's own rules ([`OperatorData::check_rules`]) report; a domain
    /// without rules of its own says [`Infallible`].
    type Invalid: std::error::Error + Send + Sync + 'static;

    /// The causes the domain's robot perceives itself, when the domain holds its
    /// operators to the rule that a weight names only those ([`check_perceived_weights`]:
    /// what a command is worth then never depends on something the robot cannot know
    /// happened); `None`, the default, lets the weights name any declared cause. The rule
    /// is checked after the declared default weights are filled in, so a domain that keeps
    /// it declares default weights only for causes in this list.
    const PERCEIVED: Option<&'static [Cause]> = None;

    /// Checks the ranges of the operator's own fields through `check`, in the order a
    /// reader should fix them: the first field out of range is the one reported. The
    /// standard fields are checked by the loader after these; nothing by default.
    fn validate(&self, check: &mut RangeCheck) {
        let _ = check;
    }

    /// The domain's own rules, given the causes the scenario `declared` (for example,
    /// that a preference which is on has its cause declared); none by default.
    fn check_rules(&self, declared: &[DeclaredCause]) -> Result<(), Self::Invalid> {
        let _ = declared;
        Ok(())
    }
}

/// The range a field must be in, as an error states it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Allowed {
    /// A probability: in `[0, 1]`.
    Probability,
    /// A finite number greater than 0.
    Positive,
    /// A finite number at least 0.
    NonNegative,
    /// A finite number at least this.
    AtLeast(f64),
}

impl fmt::Display for Allowed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Probability => f.write_str("a probability in [0, 1]"),
            Self::Positive => f.write_str("a finite number > 0"),
            Self::NonNegative => f.write_str("a finite number >= 0"),
            Self::AtLeast(min) => write!(f, "a finite number >= {min}"),
        }
    }
}

/// A field out of its range.
#[derive(Clone, Debug, PartialEq)]
struct OutOfRange {
    field: String,
    allowed: Allowed,
    value: f64,
}

/// The range checks of an operator's fields ([`OperatorData::validate`]): each call checks
/// one field, named as the file writes it (`p_collision`, `comfort.p`), and the first field
/// out of range is the one the loader reports; later calls change nothing.
#[derive(Debug, Default)]
pub struct RangeCheck {
    first: Option<OutOfRange>,
}

impl RangeCheck {
    /// `value` must be a probability, in `[0, 1]`.
    pub fn probability(&mut self, field: &str, value: f64) {
        self.require(
            field,
            value,
            Allowed::Probability,
            (0.0..=1.0).contains(&value),
        );
    }

    /// `value` must be a finite number greater than 0.
    pub fn positive(&mut self, field: &str, value: f64) {
        self.require(
            field,
            value,
            Allowed::Positive,
            value.is_finite() && value > 0.0,
        );
    }

    /// `value` must be a finite number at least 0.
    pub fn non_negative(&mut self, field: &str, value: f64) {
        let ok = value.is_finite() && value >= 0.0;
        self.require(field, value, Allowed::NonNegative, ok);
    }

    /// `value` must be a finite number at least `min`.
    pub fn at_least(&mut self, field: &str, value: f64, min: f64) {
        let ok = value.is_finite() && value >= min;
        self.require(field, value, Allowed::AtLeast(min), ok);
    }

    fn require(&mut self, field: &str, value: f64, allowed: Allowed, ok: bool) {
        if !ok && self.first.is_none() {
            self.first = Some(OutOfRange {
                field: field.to_owned(),
                allowed,
                value,
            });
        }
    }
}

/// `weights.by_cause` names a cause the robot does not perceive itself.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "`weights.by_cause.{cause}`: weights may name only causes the robot perceives itself ({})",
    list_causes(perceived)
)]
pub struct UnperceivedWeight {
    /// The cause named.
    pub cause: Cause,
    /// The causes the robot perceives itself.
    pub perceived: Vec<Cause>,
}

/// The rule that an operator's weights name only causes the robot perceives itself: the
/// first cause of `weights.by_cause` (in name order) that is not in `perceived` breaks it.
///
/// ```
/// use lab::contract::operator_file::check_perceived_weights;
/// use trust::{Cause, OutcomeWeights};
///
/// let bump = Cause::from_static("bump");
/// let late = Cause::from_static("late");
/// let weights = OutcomeWeights {
///     by_cause: [(bump, 2.0), (late, 1.5)].into_iter().collect(),
///     ..OutcomeWeights::default()
/// };
/// assert!(check_perceived_weights(&weights, &[bump, late]).is_ok());
/// let err = check_perceived_weights(&weights, &[bump]).unwrap_err();
/// assert_eq!(err.cause, late);
/// assert_eq!(
///     err.to_string(),
///     "`weights.by_cause.late`: weights may name only causes the robot perceives itself (bump)"
/// );
/// ```
pub fn check_perceived_weights(
    weights: &OutcomeWeights,
    perceived: &[Cause],
) -> Result<(), UnperceivedWeight> {
    match weights.by_cause.keys().find(|c| !perceived.contains(c)) {
        Some(&cause) => Err(UnperceivedWeight {
            cause,
            perceived: perceived.to_vec(),
        }),
        None => Ok(()),
    }
}

/// Why an operator file cannot be used; `E` is what the domain's own rules report
/// ([`OperatorData::Invalid`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OperatorFileError<E = Infallible> {
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file is not a valid operator in RON (the error names line:column).
    #[error(transparent)]
    Syntax(#[from] RonError),
    /// A field is out of its allowed range.
    #[error(
        "{file}: operator `{operator}`: `{field}` must be {allowed}, got {}",
        cbr_core::Shown(*.value)
    )]
    Range {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The field, e.g. `p_collision` or `comfort.p`.
        field: String,
        /// The allowed range.
        allowed: Allowed,
        /// The value given.
        value: f64,
    },
    /// A weight is out of range, or `weights.by_cause` names a cause the scenario does not
    /// declare.
    #[error("{file}: operator `{operator}`: {reason}")]
    Weights {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// What is wrong with the weights.
        reason: WeightsError,
    },
    /// `weights.by_cause` names a cause the robot does not perceive itself.
    #[error("{file}: operator `{operator}`: {reason}")]
    Unperceived {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The cause, and those allowed.
        reason: UnperceivedWeight,
    },
    /// A rule of the domain's own is broken.
    #[error("{file}: operator `{operator}`: {reason}")]
    Rule {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The domain's error (boxed: a domain's error may be large, and every loader's
        /// result carries this type).
        reason: Box<E>,
    },
}

/// Parses and checks an operator for a scenario that declares `causes` (see the
/// [module documentation](self) for the order); `origin` names the source in errors.
pub fn from_ron<O: OperatorData>(
    text: &str,
    origin: &Path,
    causes: &[DeclaredCause],
) -> Result<O, OperatorFileError<O::Invalid>> {
    let mut operator: O = parse_ron(text, origin)?;
    let file = || origin.to_owned();
    let name = |operator: &O| operator.name().to_owned();
    let mut check = RangeCheck::default();
    operator.validate(&mut check);
    check.at_least("give_up_factor", operator.give_up_factor(), 1.0);
    if let Some(OutOfRange {
        field,
        allowed,
        value,
    }) = check.first
    {
        return Err(OperatorFileError::Range {
            file: file(),
            operator: name(&operator),
            field,
            allowed,
            value,
        });
    }
    if let Err(reason) = operator.weights_mut().check(causes) {
        return Err(OperatorFileError::Weights {
            file: file(),
            operator: name(&operator),
            reason,
        });
    }
    if let Some(perceived) = O::PERCEIVED
        && let Err(reason) = check_perceived_weights(operator.weights_mut(), perceived)
    {
        return Err(OperatorFileError::Unperceived {
            file: file(),
            operator: name(&operator),
            reason,
        });
    }
    operator
        .check_rules(causes)
        .map_err(|reason| OperatorFileError::Rule {
            file: file(),
            operator: name(&operator),
            reason: Box::new(reason),
        })?;
    Ok(operator)
}

/// Reads an operator file (a regular file of at most [`files::MAX_CONFIG_BYTES`]) and
/// checks it as [`from_ron`] does.
pub fn load<O: OperatorData>(
    path: &Path,
    causes: &[DeclaredCause],
) -> Result<O, OperatorFileError<O::Invalid>> {
    from_ron(&read_text(path)?, path, causes)
}

/// Operators a crate ships inside its binary: each `(origin, text)` is an operator file's
/// name and its text (`include_str!`), read and checked as [`from_ron`] reads a file
/// (its errors name `origin`), in order.
///
/// # Errors
///
/// The first shipped file that is not a valid operator, with [`from_ron`]'s error: the
/// crate's own data, so its tests should read them all.
pub fn shipped<O: OperatorData>(
    files: &[(&str, &str)],
    causes: &[DeclaredCause],
) -> Result<Vec<O>, OperatorFileError<O::Invalid>> {
    files
        .iter()
        .map(|(origin, text)| from_ron(text, Path::new(origin), causes))
        .collect()
}

/// [`shipped`] over operator files embedded from the calling crate: each path, relative to
/// the crate's root (its `Cargo.toml`'s folder), is read at compile time
/// (`include_str!`) and names the file in errors, and the list is checked against
/// `causes`:
/// `lab::shipped_operators!(&CAUSES, ["operators/night.ron", "operators/day.ron"])` is a
/// `Result<Vec<O>, OperatorFileError<..>>` of the operators in that order.
#[macro_export]
macro_rules! shipped_operators {
    ($causes:expr, [$($path:literal),+ $(,)?]) => {
        $crate::contract::operator_file::shipped(
            &[$((
                $path,
                ::std::include_str!(::std::concat!(::std::env!("CARGO_MANIFEST_DIR"), "/", $path)),
            )),+],
            $causes,
        )
    };
}

/// Operators paired with their names ([`StandardFields::name`]), as a catalog lists them.
pub fn named<O: StandardFields>(operators: impl IntoIterator<Item = O>) -> Vec<(String, O)> {
    operators.into_iter().map(with_name).collect()
}

/// One operator paired with its name, as a catalog's `load_operator` returns it.
pub fn with_name<O: StandardFields>(operator: O) -> (String, O) {
    (operator.name().to_owned(), operator)
}

/// The operator named `name` among `operators` (a family's poles, among the shipped
/// operators); `None` when none is.
pub fn find<O: StandardFields>(operators: impl IntoIterator<Item = O>, name: &str) -> Option<O> {
    operators
        .into_iter()
        .find(|operator| operator.name() == name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    const LATE: Cause = Cause::from_static("late");
    const BUMP: Cause = Cause::from_static("bump");
    const GLARE: Cause = Cause::from_static("glare");

    crate::standard_operator! {
        /// An operator with one field of every range, a perceived list, and a rule of its own:
        /// `watch_glare` needs the cause `glare` declared.
        #[derive(Debug, Deserialize)]
        struct Watcher {
            p: f64,
            t: f64,
            gap: f64,
            factor: f64,
            #[serde(default)]
            watch_glare: bool,
        }
    }

    #[derive(Debug, PartialEq, thiserror::Error)]
    #[error("`watch_glare` needs cause `glare` declared")]
    struct GlareUndeclared;

    impl OperatorData for Watcher {
        type Invalid = GlareUndeclared;
        const PERCEIVED: Option<&'static [Cause]> = Some(&[BUMP]);

        fn validate(&self, check: &mut RangeCheck) {
            check.probability("p", self.p);
            check.positive("t", self.t);
            check.non_negative("gap", self.gap);
            check.at_least("factor", self.factor, 1.5);
        }

        fn check_rules(&self, declared: &[DeclaredCause]) -> Result<(), GlareUndeclared> {
            if self.watch_glare && !declared.iter().any(|d| d.name == GLARE) {
                return Err(GlareUndeclared);
            }
            Ok(())
        }
    }

    fn declared() -> Vec<DeclaredCause> {
        vec![DeclaredCause::new(LATE), DeclaredCause::new(BUMP)]
    }

    fn read(fields: &str) -> Result<Watcher, OperatorFileError<GlareUndeclared>> {
        let text = format!("(name: \"w\", {fields})");
        from_ron(&text, Path::new("ops/w.ron"), &declared())
    }

    fn message(fields: &str) -> String {
        read(fields).unwrap_err().to_string()
    }

    const GOOD: &str = "p: 0.5, t: 2.0, gap: 0.0, factor: 1.5";

    #[test]
    fn an_operator_is_found_by_its_name() {
        let ops = || {
            ["a", "b"].map(|name| {
                let text = format!("(name: \"{name}\", {GOOD})");
                from_ron::<Watcher>(&text, Path::new("ops/w.ron"), &declared()).unwrap()
            })
        };
        assert_eq!(find(ops(), "b").map(|w| w.name), Some("b".to_owned()));
        assert!(find(ops(), "c").is_none());
    }

    #[test]
    fn a_good_operator_reads_with_its_weights_checked() {
        let w = read(&format!("{GOOD}, weights: (by_cause: {{\"bump\": 3.0}})")).unwrap();
        assert_eq!(w.weights.of(BUMP), 3.0);
        assert_eq!(w.weights.of(LATE), 1.0);
    }

    #[test]
    fn each_range_is_stated_and_the_first_field_out_of_range_is_reported() {
        for (fields, expected) in [
            (
                "p: 1.5, t: 2.0, gap: 0.0, factor: 1.5",
                "`p` must be a probability in [0, 1], got 1.5",
            ),
            (
                "p: 0.5, t: 0.0, gap: 0.0, factor: 1.5",
                "`t` must be a finite number > 0, got 0",
            ),
            (
                "p: 0.5, t: inf, gap: 0.0, factor: 1.5",
                "`t` must be a finite number > 0, got inf",
            ),
            (
                "p: 0.5, t: 2.0, gap: -0.5, factor: 1.5",
                "`gap` must be a finite number >= 0, got -0.5",
            ),
            (
                "p: 0.5, t: 2.0, gap: 0.0, factor: 1.25",
                "`factor` must be a finite number >= 1.5, got 1.25",
            ),
            // Two fields out of range: the first checked is reported.
            (
                "p: -1.0, t: 2.0, gap: 0.0, factor: 0.0",
                "`p` must be a probability in [0, 1], got -1",
            ),
            (
                "p: NaN, t: 2.0, gap: 0.0, factor: 1.5",
                "`p` must be a probability in [0, 1], got NaN",
            ),
        ] {
            assert_eq!(
                message(fields),
                format!("ops/w.ron: operator `w`: {expected}")
            );
        }
    }

    #[test]
    fn the_standard_patience_defaults_to_2_and_is_checked_after_the_domain_s_own_fields() {
        assert_eq!(read(GOOD).unwrap().give_up_factor(), 2.0);
        assert_eq!(
            read(&format!("{GOOD}, give_up_factor: 3.5"))
                .unwrap()
                .give_up_factor(),
            3.5
        );
        assert_eq!(
            message(&format!("{GOOD}, give_up_factor: 0.9")),
            "ops/w.ron: operator `w`: `give_up_factor` must be a finite number >= 1, got 0.9"
        );
        assert_eq!(
            message("p: 2.0, t: 2.0, gap: 0.0, factor: 1.5, give_up_factor: 0.5"),
            "ops/w.ron: operator `w`: `p` must be a probability in [0, 1], got 2"
        );
    }

    #[test]
    fn syntax_errors_name_line_and_column() {
        let err = from_ron::<Watcher>("(name: \"w\",\n p: 0.5,\n q: 1.0)", Path::new("x.ron"), &[])
            .unwrap_err();
        assert!(matches!(err, OperatorFileError::Syntax(_)));
        assert!(err.to_string().starts_with("x.ron:3:"), "{err}");
    }

    #[test]
    fn weights_are_checked_against_the_declared_causes_before_the_perceived_ones() {
        // `glare` is neither declared nor perceived: the declaration is reported.
        let err = message(&format!("{GOOD}, weights: (by_cause: {{\"glare\": 1.0}})"));
        assert!(
            err.starts_with(
                "ops/w.ron: operator `w`: `weights.by_cause`: cause `glare` is not declared"
            ),
            "{err}"
        );
        let err = message(&format!("{GOOD}, weights: (by_cause: {{\"late\": 1.0}})"));
        assert_eq!(
            err,
            "ops/w.ron: operator `w`: `weights.by_cause.late`: weights may name only causes the robot perceives itself (bump)"
        );
    }

    #[test]
    fn the_domain_s_own_rules_come_last_with_its_own_error() {
        let err = read(&format!("{GOOD}, watch_glare: true")).unwrap_err();
        assert!(
            matches!(err, OperatorFileError::Rule { ref reason, .. } if **reason == GlareUndeclared)
        );
        assert_eq!(
            err.to_string(),
            "ops/w.ron: operator `w`: `watch_glare` needs cause `glare` declared"
        );
        let mut causes = declared();
        causes.push(DeclaredCause::new(GLARE));
        let text = format!("(name: \"w\", {GOOD}, watch_glare: true)");
        assert!(from_ron::<Watcher>(&text, Path::new("w.ron"), &causes).is_ok());
    }

    #[test]
    fn a_file_that_cannot_be_read_is_an_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let err = load::<Watcher>(&dir.path().join("absent.ron"), &declared()).unwrap_err();
        assert!(matches!(err, OperatorFileError::Io(_)), "{err}");
        let path = dir.path().join("w.ron");
        std::fs::write(&path, format!("(name: \"w\", {GOOD})")).unwrap();
        assert_eq!(load::<Watcher>(&path, &declared()).unwrap().t, 2.0);
    }
}

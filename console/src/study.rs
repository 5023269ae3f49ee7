//! The study file: what a study shows its participants and how it assigns them, read from
//! RON and checked before anything is stored (file, line:column, the allowed values).

use files::RonError;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The most conditions a study may compare.
pub const MAX_CONDITIONS: usize = 16;
/// The most commands one participant may be shown.
pub const MAX_COMMANDS: u32 = 500;
/// The most behaviors one participant may evaluate.
pub const MAX_BEHAVIORS: u32 = 200;
/// The fastest a run may be played, as a multiple of its own pace.
pub const MAX_SPEEDUP: f64 = 50.0;

/// A study, as its RON file states it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Study {
    /// Shown at the top of every page.
    pub title: String,
    /// The domain the robot works in: a scenario of the tool's catalog that can be shown
    /// (`movement`, `patrol`).
    pub domain: String,
    /// The conditions compared, each with its own adapter.
    pub conditions: Vec<Condition>,
    /// How participants are assigned to conditions.
    pub assignment: Assignment,
    /// The most commands a participant is shown; the session ends there.
    pub commands: Bounded<1, MAX_COMMANDS>,
    /// The most behaviors a participant evaluates; the session ends when the next one
    /// would exceed it.
    pub behaviors: Bounded<1, MAX_BEHAVIORS>,
    /// When and how participants rate their trust.
    pub rating: Rating,
    /// How many times faster than its own pace a run is played.
    pub speedup: Speedup,
    /// Shown before Start; starting is consenting (docs/studies.md says what it should say).
    pub consent: String,
    /// About how many minutes a session takes, shown beside the consent.
    #[serde(default = "default_minutes")]
    pub minutes: u32,
    /// Whether participants of a condition share one case base or each starts empty.
    pub cases: CaseSharing,
    /// Seeds every participant's adapter and runs (with the participant's number).
    pub seed: u64,
}

fn default_minutes() -> u32 {
    5
}

/// One condition of a study.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    /// Its name in exports and reports.
    pub name: String,
    /// The adapter's arm, as `serve --arm` names it.
    pub arm: String,
    /// Whether the page shows the adapter's explanation of each switch.
    pub explanations: bool,
    /// Whether the page asks why the participant stopped the robot.
    pub statements: bool,
}

/// How participants are assigned to conditions.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub enum Assignment {
    /// In blocks of one participant per condition, each block in an order drawn from
    /// `seed`: after every full block the conditions have equal numbers.
    Counterbalanced {
        /// Seeds the order of each block.
        seed: u64,
    },
}

/// Whether a condition's participants share what their robots learn.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
pub enum CaseSharing {
    /// A fleet: each participant's robot starts from the cases its condition's earlier
    /// participants retained, as they were when the participant pressed Start.
    Shared,
    /// Each participant's robot starts with an empty case base.
    EachEmpty,
}

/// When and on what scale participants rate their trust.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Rating {
    /// When the page asks.
    pub after: RateAfter,
    /// The scale.
    pub scale: Scale,
    /// The question; it must speak of trust (the page's rating control is labelled by it).
    pub question: String,
    /// The label of the scale's low end.
    pub low: String,
    /// The label of the scale's high end.
    pub high: String,
}

/// When the page asks for a rating.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
pub enum RateAfter {
    /// After each behavior: when the robot switches, settles or the session ends.
    EachBehavior,
    /// After every `n` commands (and when the session ends).
    Commands(Bounded<1, MAX_COMMANDS>),
}

/// A rating scale.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
pub enum Scale {
    /// A Likert item of `points` points, 1 to `points`.
    Likert(Bounded<2, 11>),
    /// A slider from 0 to 100.
    Slider,
}

impl Scale {
    /// The lowest and highest value a rating may take.
    pub fn range(self) -> (u32, u32) {
        match self {
            Self::Likert(points) => (1, points.get()),
            Self::Slider => (0, 100),
        }
    }
}

/// A whole number in `[MIN, MAX]`, refused at its place in the file otherwise.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(try_from = "u32", into = "u32")]
pub struct Bounded<const MIN: u32, const MAX: u32>(u32);

impl<const MIN: u32, const MAX: u32> Bounded<MIN, MAX> {
    /// The number.
    pub fn get(self) -> u32 {
        self.0
    }
}

impl<const MIN: u32, const MAX: u32> TryFrom<u32> for Bounded<MIN, MAX> {
    type Error = String;
    fn try_from(value: u32) -> Result<Self, String> {
        if (MIN..=MAX).contains(&value) {
            Ok(Self(value))
        } else {
            Err(format!("{value} is out of range: allowed {MIN} to {MAX}"))
        }
    }
}

impl<const MIN: u32, const MAX: u32> From<Bounded<MIN, MAX>> for u32 {
    fn from(value: Bounded<MIN, MAX>) -> u32 {
        value.0
    }
}

/// How many times faster than its own pace a run is played: in `[1, MAX_SPEEDUP]`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(try_from = "f64", into = "f64")]
pub struct Speedup(f64);

impl Speedup {
    /// The factor.
    pub fn get(self) -> f64 {
        self.0
    }
}

impl TryFrom<f64> for Speedup {
    type Error = String;
    fn try_from(value: f64) -> Result<Self, String> {
        if (1.0..=MAX_SPEEDUP).contains(&value) {
            Ok(Self(value))
        } else {
            Err(format!(
                "speedup {value} is out of range: allowed 1 to {MAX_SPEEDUP}"
            ))
        }
    }
}

impl From<Speedup> for f64 {
    fn from(value: Speedup) -> f64 {
        value.0
    }
}

/// Why a study file was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// The file could not be read.
    #[error(transparent)]
    Read(#[from] files::FileError),
    /// The file does not parse as a study (file, line:column, the field).
    #[error(transparent)]
    Parse(#[from] RonError),
    /// A field parses but is not allowed (file, line:column where it is written).
    #[error("{origin}:{line}:{column}: {field}: {reason}")]
    Invalid {
        /// The file.
        origin: String,
        /// 1-based line of the field's value.
        line: usize,
        /// 1-based column of the field's value.
        column: usize,
        /// The field, as a path (`conditions[1].name`).
        field: String,
        /// What is wrong and what is allowed.
        reason: String,
    },
}

impl StudyError {
    /// `field` of the study `text` (read from `origin`) refused for `reason`, placed at the
    /// first occurrence of `needle` (the field's value as written).
    pub fn at(text: &str, origin: &Path, field: String, needle: &str, reason: String) -> Self {
        let (line, column) = locate(text, needle);
        Self::Invalid {
            origin: origin.display().to_string(),
            line,
            column,
            field,
            reason,
        }
    }
}

impl Study {
    /// Reads and checks the study file at `path`.
    pub fn load(path: &Path) -> Result<(Self, String), StudyError> {
        let text = files::read_text(path)?;
        let study = Self::from_ron(&text, path)?;
        Ok((study, text))
    }

    /// Parses and checks a study from its RON `text`; `origin` names it in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, StudyError> {
        let study: Study = files::parse_ron(text, origin)?;
        study.check(text, origin)?;
        Ok(study)
    }

    /// The checks a type cannot make: at least one condition, distinct names, texts
    /// that are not empty, a question about trust.
    fn check(&self, text: &str, origin: &Path) -> Result<(), StudyError> {
        let invalid = |field: String, needle: &str, reason: String| {
            StudyError::at(text, origin, field, needle, reason)
        };
        if self.conditions.is_empty() || self.conditions.len() > MAX_CONDITIONS {
            return Err(invalid(
                "conditions".into(),
                "conditions",
                format!(
                    "{} conditions: allowed 1 to {MAX_CONDITIONS}",
                    self.conditions.len()
                ),
            ));
        }
        for (i, condition) in self.conditions.iter().enumerate() {
            if let Err(e) = files::name::check_label("a condition's name", &condition.name) {
                return Err(invalid(
                    format!("conditions[{i}].name"),
                    &format!("\"{}\"", condition.name),
                    e.to_string(),
                ));
            }
            if self.conditions[..i]
                .iter()
                .any(|c| c.name == condition.name)
            {
                return Err(invalid(
                    format!("conditions[{i}].name"),
                    &format!("\"{}\"", condition.name),
                    format!("`{}` names two conditions", condition.name),
                ));
            }
        }
        for (field, value) in [
            ("title", &self.title),
            ("consent", &self.consent),
            ("rating.low", &self.rating.low),
            ("rating.high", &self.rating.high),
        ] {
            if value.trim().is_empty() {
                return Err(invalid(
                    field.into(),
                    field.rsplit('.').next().unwrap_or(field),
                    "must not be empty".into(),
                ));
            }
        }
        if !self.rating.question.to_lowercase().contains("trust") {
            return Err(invalid(
                "rating.question".into(),
                "question",
                format!(
                    "`{}` does not ask about trust: the page labels its rating control with the question, and a rating of trust must say so",
                    self.rating.question
                ),
            ));
        }
        Ok(())
    }

    /// The condition of the participant numbered `number` (from 0) under the study's
    /// assignment.
    pub fn condition_of(&self, number: u64) -> usize {
        match self.assignment {
            Assignment::Counterbalanced { seed } => {
                let count = self.conditions.len() as u64;
                let block = number / count;
                let mut order: Vec<usize> = (0..self.conditions.len()).collect();
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(block);
                order.shuffle(&mut rng);
                order[(number % count) as usize]
            }
        }
    }

    /// The seed of the participant numbered `number`'s adapter and runs.
    pub fn participant_seed(&self, number: u64) -> u64 {
        mix(self.seed ^ mix(number.wrapping_add(1)))
    }
}

/// A 64-bit mix (SplitMix64's finaliser): seeds that differ in one bit share no pattern.
pub fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The 1-based line and column of the first `needle` in `text` (1:1 when absent).
fn locate(text: &str, needle: &str) -> (usize, usize) {
    let Some(at) = text.find(needle) else {
        return (1, 1);
    };
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PILOT: &str = include_str!("../../domains/studies/pilot.ron");

    fn parse(text: &str) -> Result<Study, StudyError> {
        Study::from_ron(text, Path::new("study.ron"))
    }

    #[test]
    fn the_pilot_parses() {
        let study = parse(PILOT).unwrap();
        assert_eq!(study.conditions.len(), 2);
        assert_eq!(study.domain, "movement");
    }

    #[test]
    fn a_bound_out_of_range_is_refused_at_its_place() {
        let text = PILOT.replacen("commands: 20", "commands: 0", 1);
        assert_ne!(text, PILOT, "the pilot sets commands: 20");
        let error = parse(&text).unwrap_err().to_string();
        let line = text
            .lines()
            .position(|l| l.contains("commands: 0"))
            .unwrap()
            + 1;
        assert!(error.starts_with(&format!("study.ron:{line}:")), "{error}");
        assert!(
            error.contains("0 is out of range: allowed 1 to 500"),
            "{error}"
        );
    }

    #[test]
    fn two_conditions_of_one_name_are_refused_with_the_field() {
        let study = parse(PILOT).unwrap();
        let (first, second) = (&study.conditions[0].name, &study.conditions[1].name);
        let text = PILOT.replacen(&format!("\"{second}\""), &format!("\"{first}\""), 1);
        let error = parse(&text).unwrap_err().to_string();
        assert!(error.contains("conditions[1].name"), "{error}");
        assert!(error.contains("names two conditions"), "{error}");
    }

    #[test]
    fn a_question_that_does_not_ask_about_trust_is_refused() {
        let study = parse(PILOT).unwrap();
        let text = PILOT.replacen(&study.rating.question, "How was it?", 1);
        let error = parse(&text).unwrap_err().to_string();
        assert!(error.contains("rating.question"), "{error}");
    }

    #[test]
    fn counterbalancing_fills_every_block_with_each_condition_once() {
        let study = parse(PILOT).unwrap();
        let n = study.conditions.len();
        let mut orders = std::collections::HashSet::new();
        for block in 0..20 {
            let mut seen: Vec<usize> = (0..n)
                .map(|k| study.condition_of((block * n + k) as u64))
                .collect();
            orders.insert(seen.clone());
            seen.sort_unstable();
            assert_eq!(seen, (0..n).collect::<Vec<_>>());
        }
        assert!(orders.len() > 1, "blocks are drawn in more than one order");
    }

    #[test]
    fn locate_finds_line_and_column() {
        assert_eq!(locate("a\n  bc\n", "bc"), (2, 3));
        assert_eq!(locate("abc", "zz"), (1, 1));
    }
}

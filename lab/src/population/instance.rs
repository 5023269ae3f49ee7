//! Benchmark instances: a seed range for development and one for evaluation that never
//! meet, so a strategy is developed on instances it is not judged on (as benchmark suites
//! keep their development and test instances apart).
//!
//! An instance is named `dev-K` or `eval-K`; its seed is `K` places into its split's range
//! ([`DEV_SEEDS`], [`EVAL_SEEDS`]). What a seed draws (a population of operators from a
//! domain's prior, ...) is the domain's business; this module only names seeds.
//!
//! This is not the experiment's master seed ([`crate::seeds`]): an instance fixes *what*
//! is to be adapted to, the master seed how the trials on it are drawn.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::ops::Range;
use std::str::FromStr;

/// The seeds of development instances: `dev-K` is seed `K`.
pub const DEV_SEEDS: Range<u64> = 0..1_000_000;

/// The seeds of evaluation instances: `eval-K` is seed `1_000_000_000 + K`. Far from the
/// development range, so no off-by-one or widened loop over development seeds reaches it.
pub const EVAL_SEEDS: Range<u64> = 1_000_000_000..1_001_000_000;

// Neither range is empty, and every development seed comes before every evaluation seed:
// checked when the crate compiles.
const _: () = assert!(DEV_SEEDS.start < DEV_SEEDS.end && EVAL_SEEDS.start < EVAL_SEEDS.end);
const _: () = assert!(DEV_SEEDS.end <= EVAL_SEEDS.start);

/// Which side of the split an instance is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Split {
    /// Instances to develop, tune and debug a strategy on.
    Dev,
    /// Instances a strategy is judged on, and only judged on.
    Eval,
}

impl Split {
    /// Both splits, development first.
    pub const ALL: [Split; 2] = [Split::Dev, Split::Eval];

    /// The split's seeds.
    pub const fn seeds(self) -> Range<u64> {
        match self {
            Split::Dev => DEV_SEEDS,
            Split::Eval => EVAL_SEEDS,
        }
    }

    /// The prefix of its instances' names: `dev` or `eval`.
    pub const fn prefix(self) -> &'static str {
        match self {
            Split::Dev => "dev",
            Split::Eval => "eval",
        }
    }

    /// How many instances the split has.
    pub const fn count(self) -> u64 {
        let seeds = self.seeds();
        seeds.end - seeds.start
    }
}

/// A benchmark instance: a split and a place in it. Written and read as its name
/// (`"dev-17"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(into = "String", try_from = "String")]
pub struct Instance {
    split: Split,
    index: u64,
}

impl Instance {
    /// Instance `index` of `split`; refused beyond the split's count.
    pub fn new(split: Split, index: u64) -> Result<Self, InstanceError> {
        if index >= split.count() {
            return Err(InstanceError::OutOfRange {
                name: format!("{}-{index}", split.prefix()),
                count: split.count(),
            });
        }
        Ok(Self { split, index })
    }

    /// Development instance `index` (`dev-INDEX`).
    pub fn dev(index: u64) -> Result<Self, InstanceError> {
        Self::new(Split::Dev, index)
    }

    /// Evaluation instance `index` (`eval-INDEX`).
    pub fn eval(index: u64) -> Result<Self, InstanceError> {
        Self::new(Split::Eval, index)
    }

    /// Its split.
    pub fn split(&self) -> Split {
        self.split
    }

    /// Its place in the split, from 0.
    pub fn index(&self) -> u64 {
        self.index
    }

    /// Its seed: `index` places into the split's seed range.
    pub fn seed(&self) -> u64 {
        self.split.seeds().start + self.index
    }
}

impl fmt::Display for Instance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}", self.split.prefix(), self.index)
    }
}

impl From<Instance> for String {
    fn from(instance: Instance) -> String {
        instance.to_string()
    }
}

impl TryFrom<String> for Instance {
    type Error = InstanceError;
    fn try_from(name: String) -> Result<Self, InstanceError> {
        name.parse()
    }
}

impl FromStr for Instance {
    type Err = InstanceError;

    /// `dev-K` or `eval-K`, `K` a decimal number without sign or leading zeros.
    fn from_str(name: &str) -> Result<Self, InstanceError> {
        let syntax = || InstanceError::Syntax(name.to_owned());
        let (prefix, index) = name.rsplit_once('-').ok_or_else(syntax)?;
        let split = Split::ALL
            .into_iter()
            .find(|s| s.prefix() == prefix)
            .ok_or_else(syntax)?;
        let canonical = !index.is_empty()
            && index.bytes().all(|b| b.is_ascii_digit())
            && (index == "0" || !index.starts_with('0'));
        if !canonical {
            return Err(syntax());
        }
        // All digits: only too many of them fails to parse, which is out of range too.
        let index: u64 = index.parse().map_err(|_| InstanceError::OutOfRange {
            name: name.to_owned(),
            count: split.count(),
        })?;
        Self::new(split, index)
    }
}

/// An instance name that names no instance.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum InstanceError {
    /// Not `dev-K` or `eval-K`.
    #[error("`{0}` is not an instance name: `dev-K` or `eval-K`, K a number (e.g. dev-17, eval-3)")]
    Syntax(String),
    /// The split has fewer instances.
    #[error("instance `{name}` does not exist: a split has {count} instances, numbered from 0")]
    OutOfRange {
        /// The name given.
        name: String,
        /// The split's count.
        count: u64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn names_and_seeds() {
        let dev = Instance::dev(17).unwrap();
        assert_eq!((dev.to_string(), dev.seed()), ("dev-17".to_owned(), 17));
        let eval = Instance::eval(3).unwrap();
        assert_eq!(
            (eval.to_string(), eval.seed()),
            ("eval-3".to_owned(), 1_000_000_003)
        );
        assert_eq!("eval-3".parse::<Instance>(), Ok(eval));
        assert_eq!("dev-0".parse::<Instance>().unwrap().seed(), 0);
        assert_eq!(
            "dev-999999".parse::<Instance>().unwrap().seed(),
            DEV_SEEDS.end - 1
        );
    }

    #[test]
    fn the_last_dev_instance_comes_before_the_first_eval_instance() {
        let last_dev = Instance::dev(Split::Dev.count() - 1).unwrap();
        let first_eval = Instance::eval(0).unwrap();
        assert!(last_dev.seed() < first_eval.seed());
        assert!(Instance::eval(Split::Eval.count()).is_err());
    }

    #[test]
    fn bad_names_are_refused_with_the_form() {
        for bad in [
            "dev", "dev-", "dev-x", "test-3", "eval--3", "eval-+3", "dev-03", "dev-1.5", "",
        ] {
            assert_eq!(
                bad.parse::<Instance>(),
                Err(InstanceError::Syntax(bad.to_owned())),
                "{bad}"
            );
        }
        let err = "dev-1000000".parse::<Instance>().unwrap_err();
        assert_eq!(
            err.to_string(),
            "instance `dev-1000000` does not exist: a split has 1000000 instances, numbered from 0"
        );
        assert!(matches!(
            "eval-99999999999999999999999".parse::<Instance>(),
            Err(InstanceError::OutOfRange { .. })
        ));
    }

    #[test]
    fn serde_writes_the_name() {
        let instance = Instance::eval(42).unwrap();
        let json = serde_json::to_string(&instance).unwrap();
        assert_eq!(json, "\"eval-42\"");
        assert_eq!(serde_json::from_str::<Instance>(&json).unwrap(), instance);
        assert!(serde_json::from_str::<Instance>("\"dev-x\"").is_err());
    }

    proptest! {
        #[test]
        fn a_name_reads_back_and_seeds_stay_in_their_split(dev: bool, index in 0u64..1_000_000) {
            let split = if dev { Split::Dev } else { Split::Eval };
            let instance = Instance::new(split, index).unwrap();
            prop_assert_eq!(instance.to_string().parse::<Instance>(), Ok(instance));
            prop_assert!(split.seeds().contains(&instance.seed()));
            let other = if dev { Split::Eval } else { Split::Dev };
            prop_assert!(!other.seeds().contains(&instance.seed()));
        }
    }
}

//! The caps the tool applies to the counts it is asked for, with their checks, shared by
//! the command line and the Python package so a count refused by one is refused by the
//! other, with the same message.
//!
//! A [`Limit`] is the range one count may take and why; [`Limit::check`] refuses a count
//! outside it with a [`LimitError`] naming the field, the value and the range.

/// The range one count may take, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// What is counted, in the plural (`trials`, `worker threads`).
    pub counts: &'static str,
    /// The least allowed.
    pub min: u64,
    /// The most allowed.
    pub max: u64,
    /// Why the cap, in a few words (empty when the range says it all).
    pub why: &'static str,
}

/// A count outside its [`Limit`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LimitError {
    /// A count outside its range.
    #[error("{field}: {}", self.problem())]
    Range {
        /// The field or option, e.g. `trials`, `--threads`.
        field: String,
        /// The count given.
        value: u64,
        /// The limit.
        limit: Limit,
    },
}

impl LimitError {
    /// What is wrong and what is allowed, without the field.
    pub fn problem(&self) -> String {
        match self {
            Self::Range { value, limit, .. } => format!(
                "must be {} to {}, got {value}{}",
                limit.min,
                limit.max,
                if limit.why.is_empty() {
                    String::new()
                } else {
                    format!(": {}", limit.why)
                }
            ),
        }
    }
}

impl Limit {
    /// The range as an inclusive range.
    pub const fn range(&self) -> std::ops::RangeInclusive<u64> {
        self.min..=self.max
    }

    /// Refuses `value` of `field` outside the range.
    pub fn check(&self, field: &str, value: u64) -> Result<(), LimitError> {
        if self.range().contains(&value) {
            Ok(())
        } else {
            Err(LimitError::Range {
                field: field.to_owned(),
                value,
                limit: *self,
            })
        }
    }
}

/// Trials per experiment and arm (`trials`, `--trials`, Python `trials=`).
pub const TRIALS: Limit = Limit {
    counts: "trials",
    min: 1,
    max: crate::suite::MAX_TRIALS as u64,
    why: "every trial's record is kept for the report",
};

/// Runs per cell of a report's landscapes (`landscape_runs`, `--landscape-runs`; 0: none).
pub const LANDSCAPE_RUNS: Limit = Limit {
    counts: "runs",
    min: 0,
    max: crate::suite::MAX_LANDSCAPE_RUNS as u64,
    why: "",
};

/// Runs per behavior of `trustcbr landscape --runs` and the Python `landscape(runs=)`.
pub const RUNS_PER_BEHAVIOR: Limit = Limit {
    counts: "runs",
    min: 1,
    max: crate::suite::MAX_LANDSCAPE_RUNS as u64,
    why: "",
};

/// Worker threads (`--threads`, Python `threads=`).
pub const THREADS: Limit = Limit {
    counts: "worker threads",
    min: 1,
    max: 256,
    why: "",
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_outside_its_range_is_named_with_the_range() {
        assert_eq!(THREADS.check("threads", 256), Ok(()));
        assert_eq!(
            THREADS.check("threads", 0).unwrap_err().to_string(),
            "threads: must be 1 to 256, got 0"
        );
        assert_eq!(
            RUNS_PER_BEHAVIOR
                .check("runs", 4_294_967_295)
                .unwrap_err()
                .to_string(),
            "runs: must be 1 to 10000, got 4294967295"
        );
    }
}

//! Every cap the tool applies to what it is asked, in one table: the command line, the
//! suites (experiment and mission suites), the sweeps and the Python package check their
//! counts here, so a count refused by one is refused by all, with the same message.
//!
//! A [`Bound`] is the range one count may take and why; [`Bound::check`] refuses a count
//! outside it and [`Bound::check_total`] an estimate (a suite's trials, a mission suite's
//! commands) above it, each with a [`BoundError`] naming the field, the value or estimate,
//! and the range. [`TABLE`] lists them all (docs/robustness.md shows it). The numbers come
//! from the 2-core, 24 GiB machine of docs/results.md: what a count costs there is said
//! beside each.
//!
//! Not here: the sizes of input files (`files::MAX_CONFIG_BYTES`,
//! `files::MAX_CASE_BASE_BYTES`) and of request lines (`service::MAX_LINE_BYTES`), which
//! their readers own, and how a name may become a file name (`files::name`).

use trust::Thresholds;

/// The range one count may take, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bound {
    /// What is counted, in the plural (`trials`, `worker threads`).
    pub counts: &'static str,
    /// The least allowed.
    pub min: u64,
    /// The most allowed.
    pub max: u64,
    /// Why the cap, in a few words (empty when the range says it all).
    pub why: &'static str,
}

/// A count or an estimate outside its [`Bound`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BoundError {
    /// A count outside its range.
    #[error("{field}: {}", self.problem())]
    Range {
        /// The field or option, e.g. `trials`, `--threads`.
        field: String,
        /// The count given.
        value: u64,
        /// The limit.
        limit: Bound,
    },
    /// An estimate of the whole above its cap.
    #[error("{field}: {}", self.problem())]
    Total {
        /// The field the estimate is charged to, e.g. `missions`.
        field: String,
        /// The estimate.
        estimate: u64,
        /// How it was reached, e.g. ` in all (7 experiments x 2 arms x 500 trials)`.
        detail: String,
        /// The limit.
        limit: Bound,
    },
    /// A threshold beyond [`MAX_THRESHOLD`].
    #[error("{field}: {}", self.problem())]
    Threshold {
        /// The field, e.g. `adapter.thresholds.untrustworthy`.
        field: String,
        /// The value given.
        value: f64,
    },
}

impl BoundError {
    /// The field at fault.
    pub fn field(&self) -> &str {
        match self {
            Self::Range { field, .. }
            | Self::Total { field, .. }
            | Self::Threshold { field, .. } => field,
        }
    }

    /// What is wrong and what is allowed, without the field.
    pub fn problem(&self) -> String {
        let why = |limit: &Bound| {
            if limit.why.is_empty() {
                String::new()
            } else {
                format!(": {}", limit.why)
            }
        };
        match self {
            Self::Range { value, limit, .. } => format!(
                "must be {} to {}, got {value}{}",
                limit.min,
                limit.max,
                why(limit)
            ),
            Self::Total {
                estimate,
                detail,
                limit,
                ..
            } => format!(
                "{estimate} {}{detail}; at most {}{}",
                limit.counts,
                limit.max,
                why(limit)
            ),
            Self::Threshold { value, .. } => format!(
                "must be at most {} from 0 (the paper's are 5 and -5), got {}",
                shown(MAX_THRESHOLD),
                shown(*value)
            ),
        }
    }
}

impl Bound {
    /// The range as an inclusive range.
    pub const fn range(&self) -> std::ops::RangeInclusive<u64> {
        self.min..=self.max
    }

    /// Refuses `value` of `field` outside the range.
    pub fn check(&self, field: &str, value: u64) -> Result<(), BoundError> {
        if self.range().contains(&value) {
            Ok(())
        } else {
            Err(BoundError::Range {
                field: field.to_owned(),
                value,
                limit: *self,
            })
        }
    }

    /// Refuses an `estimate` of the whole above the most allowed; `detail` says how it
    /// was reached (shown right after the estimate and the unit).
    pub fn check_total(
        &self,
        field: &str,
        estimate: u64,
        detail: String,
    ) -> Result<(), BoundError> {
        if estimate <= self.max {
            Ok(())
        } else {
            Err(BoundError::Total {
                field: field.to_owned(),
                estimate,
                detail,
                limit: *self,
            })
        }
    }
}

/// A number as messages show it: plainly, or in scientific notation when its plain form
/// would be long (`1e308`, not a 309-digit integer); the workspace's one helper,
/// [`cbr_core::shown()`].
pub use cbr_core::shown;

/// Trials per experiment and arm (`trials`, `--trials`, Python `trials=`).
pub const TRIALS: Bound = Bound {
    counts: "trials",
    min: 1,
    max: 100_000,
    why: "every trial's record is kept for the report",
};

/// Experiments of a suite, and mission plans of a mission suite: each writes its own
/// figures.
pub const EXPERIMENTS: Bound = Bound {
    counts: "experiments",
    min: 1,
    max: 1_000,
    why: "each is a part of the report with figures of its own",
};

/// Trials of a suite in all (experiments x arms x trials). Every trial's record is kept
/// until the report is written: about 24 KB each (measured: `reproduce --arms
/// random-walk,case-based` peaks at 207 MB with 7,000 trials and 869 MB with 35,000), so
/// this is about 6 GB, and some 3 minutes of the two cores for the paper's arms.
pub const SUITE_TRIALS: Bound = Bound {
    counts: "trials",
    min: 1,
    max: 250_000,
    why: "every trial's record is kept for the report",
};

/// Commands after which a trial is abandoned (`max_commands`): the paper's suite uses the
/// most.
pub const MAX_COMMANDS: Bound = Bound {
    counts: "commands",
    min: 1,
    max: 1_000_000,
    why: "a trial is cut off after at most a million commands",
};

/// Commands of a traced trial kept for the report's timeline (the sample arm traces its
/// first trials; a longer trial is not drawn): 25 traces of at most this many commands,
/// about 300 MB.
pub const TRACED_COMMANDS: Bound = Bound {
    counts: "commands",
    min: 0,
    max: lab::experiment::record::MAX_TRACED_COMMANDS,
    why: "a longer trial is not drawn as the sample timeline",
};

/// Runs per cell of a report's landscapes (`landscape_runs`, `--landscape-runs`; 0: none):
/// the default, 200, costs about 2.5 s of the two cores for `reproduce`'s landscapes, so
/// this about 2 minutes.
pub const LANDSCAPE_RUNS: Bound = Bound {
    counts: "runs",
    min: 0,
    max: 10_000,
    why: "",
};

/// Runs per behavior of `trustcbr landscape --runs` and the Python `landscape(runs=)`,
/// and of the known-operator limit's `limit.runs`: as [`LANDSCAPE_RUNS`], at least one.
pub const RUNS_PER_BEHAVIOR: Bound = Bound {
    counts: "runs",
    min: 1,
    max: 10_000,
    why: "",
};

/// Simulated runs the known-operator limit's estimate may ask for, first (`limit.budget`)
/// and second (`limit.candidates` x `limit.candidate_runs`) estimate each: 50 times the
/// defaults' 160,000 and 12,800, which with the landscapes take about 2.5 s of the two
/// cores for `reproduce`.
pub const LIMIT_RUNS: Bound = Bound {
    counts: "runs",
    min: 0,
    max: 8_000_000,
    why: "",
};

/// Episodes per member the population reference is simulated over
/// (`limit.reference_episodes`): 100 times the default's 1,000, which takes about 12 s of
/// the two cores for patrol's 20 benchmark populations.
pub const REFERENCE_EPISODES: Bound = Bound {
    counts: "episodes",
    min: 0,
    max: 100_000,
    why: "",
};

/// Members of a population drawn from a family (`family.size`): each needs its own
/// landscape for the report's limit.
pub const FAMILY_SIZE: Bound = Bound {
    counts: "members",
    min: 1,
    max: 64,
    why: "each member needs a landscape of its own",
};

/// Operator files of an experiment or mission plan (`operator_files`): as a family's
/// members ([`FAMILY_SIZE`]), each operator needs its landscape and its known-operator
/// limit for the report (1,000 files took 230 s and wrote 1,017 files).
pub const OPERATOR_FILES: Bound = Bound {
    counts: "operator files",
    min: 0,
    max: FAMILY_SIZE.max,
    why: "each operator needs a landscape of its own, as a family's member does",
};

/// Contexts of an experiment's cycle (`contexts.cycle`), each listed once: the report
/// takes every operator in every context of the cycle apart (a landscape and a
/// known-operator limit each, and the conflict of every two of them), so its work and
/// its `summary.json` grow with the square of the cycle (2,001 entries took 20.6 s and
/// 2.69 GB and wrote a 486 MB `summary.json`).
pub const CONTEXT_CYCLE: Bound = Bound {
    counts: "contexts",
    min: 1,
    max: 64,
    why: "the report takes every operator in every context apart, and compares every two",
};

/// Operators in contexts an experiment's report takes apart: the operators that judge its
/// trials x the contexts of its cycle. Each needs a landscape and a known-operator limit,
/// and the report's conflict compares every two (256 make 32,640 pairs).
pub const OPERATORS_IN_CONTEXTS: Bound = Bound {
    counts: "operators in contexts",
    min: 1,
    max: 256,
    why: "each needs a landscape and a known-operator limit, and the report compares every two",
};

/// Commands `trustcbr competence` simulates in all: behaviors x (the largest of `--seen`
/// + `--truth-runs`). The two cores run about a million a second (`--behaviors 100000
/// --truth-runs 100000` would take 155 minutes), so this is about two minutes.
pub const COMPETENCE_COMMANDS: Bound = Bound {
    counts: "commands",
    min: 1,
    max: 100_000_000,
    why: "about two minutes of simulation",
};

/// Estimates `trustcbr competence` writes: behaviors x the numbers of `--seen`, each an
/// entry of `competence.json` of about 1 KB for the UGV's scenarios (measured: 600 of
/// them, the defaults, take 625 KB; `--seen 0,1,..,10000` wrote 115 MB), so about 50 MB.
pub const COMPETENCE_ESTIMATES: Bound = Bound {
    counts: "estimates",
    min: 1,
    max: 50_000,
    why: "each is an entry of competence.json (about 1 KB)",
};

/// Commands `simulate --count` prints, one JSON line each (about 150 bytes for the UGV
/// scenarios, so some 150 MB at most; the two cores simulate them in seconds).
pub const SIMULATED_COMMANDS: Bound = Bound {
    counts: "commands",
    min: 1,
    max: 1_000_000,
    why: "",
};

/// Worker threads (`--threads`, Python `threads=`).
pub const THREADS: Bound = Bound {
    counts: "worker threads",
    min: 1,
    max: 256,
    why: "",
};

/// Runs of a sweep (cells x seeds), counted before any cell is built.
pub const SWEEP_RUNS: Bound = Bound {
    counts: "runs",
    min: 1,
    max: 10_000,
    why: "",
};

/// Trials of a sweep over all its runs: runs go one after the other, so this bounds time,
/// not memory; at the 1,600 trials a second of `reproduce` on the two cores, about 2
/// hours.
pub const SWEEP_TRIALS: Bound = Bound {
    counts: "trials",
    min: 1,
    max: 10_000_000,
    why: "",
};

/// Commands a mission suite simulates in all, with the runs that tell whether a change
/// needed an adaptation ([`TRUTH_RUNS`] per expected change): at about 80,000 a second on
/// the two cores, some 20 minutes.
pub const MISSION_COMMANDS: Bound = Bound {
    counts: "commands",
    min: 1,
    max: 100_000_000,
    why: "about 20 minutes of simulation",
};

/// Missions of a mission suite in all (plans x arms x missions, twice for complacency
/// plans): each keeps its record (about 130 bytes, more with its changes) until the report
/// is written, and is a line of `missions.jsonl`.
pub const MISSIONS: Bound = Bound {
    counts: "missions",
    min: 1,
    max: 1_000_000,
    why: "every mission's record is kept for the report",
};

/// Points a figure draws of a trace (a mission's commands): a longer trace is summarised
/// into this many columns of equal commands (docs/missions.md says what a column keeps).
pub const FIGURE_POINTS: Bound = Bound {
    counts: "points",
    min: 1,
    max: lab::mission::MAX_TRACE_STEPS as u64,
    why: "a longer trace is summarised",
};

/// Runs per (behavior, operator) of the truth of a mission's change (whether the behavior
/// in use is trustworthy for the new operator): a mean weighted outcome of 0.2 is told
/// from 0 with a standard error of about 0.07 at 200 runs.
pub const TRUTH_RUNS: u32 = 200;

use trust::MAX_THRESHOLD;

/// Refuses thresholds farther from 0 than [`MAX_THRESHOLD`]; `field` names them (e.g.
/// `adapter.thresholds`). Their order and sign are [`Thresholds::validate`]'s.
pub fn check_thresholds(field: &str, thresholds: &Thresholds) -> Result<(), BoundError> {
    for (name, value) in [
        ("trustworthy", thresholds.trustworthy),
        ("untrustworthy", thresholds.untrustworthy),
    ] {
        if value.abs() > MAX_THRESHOLD {
            return Err(BoundError::Threshold {
                field: format!("{field}.{name}"),
                value,
            });
        }
    }
    Ok(())
}

/// Every limit, by the name docs/robustness.md gives it.
pub const TABLE: &[(&str, Bound)] = &[
    ("TRIALS", TRIALS),
    ("EXPERIMENTS", EXPERIMENTS),
    ("SUITE_TRIALS", SUITE_TRIALS),
    ("MAX_COMMANDS", MAX_COMMANDS),
    ("TRACED_COMMANDS", TRACED_COMMANDS),
    ("LANDSCAPE_RUNS", LANDSCAPE_RUNS),
    ("RUNS_PER_BEHAVIOR", RUNS_PER_BEHAVIOR),
    ("LIMIT_RUNS", LIMIT_RUNS),
    ("REFERENCE_EPISODES", REFERENCE_EPISODES),
    ("FAMILY_SIZE", FAMILY_SIZE),
    ("OPERATOR_FILES", OPERATOR_FILES),
    ("CONTEXT_CYCLE", CONTEXT_CYCLE),
    ("OPERATORS_IN_CONTEXTS", OPERATORS_IN_CONTEXTS),
    ("COMPETENCE_COMMANDS", COMPETENCE_COMMANDS),
    ("COMPETENCE_ESTIMATES", COMPETENCE_ESTIMATES),
    ("SIMULATED_COMMANDS", SIMULATED_COMMANDS),
    ("THREADS", THREADS),
    ("SWEEP_RUNS", SWEEP_RUNS),
    ("SWEEP_TRIALS", SWEEP_TRIALS),
    ("MISSION_COMMANDS", MISSION_COMMANDS),
    ("MISSIONS", MISSIONS),
    ("FIGURE_POINTS", FIGURE_POINTS),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_outside_its_range_is_named_with_the_range() {
        assert_eq!(TRIALS.check("trials", 100_000), Ok(()));
        assert_eq!(
            TRIALS.check("trials", 100_001).unwrap_err().to_string(),
            "trials: must be 1 to 100000, got 100001: every trial's record is kept for the report"
        );
        assert_eq!(
            THREADS.check("threads", 0).unwrap_err().to_string(),
            "threads: must be 1 to 256, got 0"
        );
        let err = SUITE_TRIALS
            .check_total(
                "trials",
                300_000,
                " in all (1 experiments x 3 arms x 100000 trials)".into(),
            )
            .unwrap_err();
        assert_eq!(err.field(), "trials");
        assert_eq!(
            err.problem(),
            "300000 trials in all (1 experiments x 3 arms x 100000 trials); at most 250000: every trial's record is kept for the report"
        );
    }

    #[test]
    fn thresholds_far_from_zero_are_shown_short() {
        let far = Thresholds {
            trustworthy: 5.0,
            untrustworthy: -1e308,
        };
        assert_eq!(
            check_thresholds("adapter.thresholds", &far)
                .unwrap_err()
                .to_string(),
            "adapter.thresholds.untrustworthy: must be at most 1000000 from 0 (the paper's are 5 and -5), got -1e308"
        );
        assert_eq!(check_thresholds("t", &Thresholds::default()), Ok(()));
        assert_eq!(shown(1e308), "1e308");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(5.0), "5");
    }

    #[test]
    fn every_limit_is_in_the_documented_table() {
        let doc = include_str!("../docs/robustness.md");
        for (name, limit) in TABLE {
            assert!(limit.min <= limit.max, "{name}");
            assert!(
                doc.contains(&format!("`{name}`")),
                "docs/robustness.md lacks {name}"
            );
        }
    }
}

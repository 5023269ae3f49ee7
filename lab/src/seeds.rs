//! Deriving independent, portable random streams from one master seed.
//!
//! Every trial draws from streams named by (master seed, experiment, trial, purpose), so a
//! result depends only on those numbers, never on thread count or scheduling order.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// What a stream is used for; each purpose gets its own stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Purpose {
    /// The trial's operator (random-operator experiments) and initial behavior; the same
    /// for both strategies of a pair.
    Setup = 1,
    /// The simulated runs (outcomes).
    Runs = 2,
    /// The search strategy's choices.
    Search = 3,
    /// The landscape of the operator the final behaviors are drawn over (here "trial" is
    /// the pair of components drawn).
    Landscape = 4,
    /// The operator's feedback channel: whether it explains an untrustworthy command, and
    /// whether rightly (apart from the runs, so a silent channel changes no outcome).
    Feedback = 5,
    /// The landscape of an operator the known-operator limit is solved from (here "trial"
    /// is the operator's place among the experiment's).
    Limit = 6,
    /// The report's bootstrap of an arm's effect size (here "trial" is the arm's place
    /// among the experiment's).
    Bootstrap = 7,
    /// A mission's truth: whether the behavior in use when the operator changed is
    /// trustworthy for the new one (here "trial" numbers the mission's change).
    Truth = 8,
    /// The benchmark report's bootstrap over populations of an arm's ratio to the limit
    /// (here "experiment" is the scenario's place among the benchmark's, "trial" the arm's
    /// place times the metrics plus the metric's: [`crate::population::benchmark`]).
    Benchmark = 9,
    /// The measure of the robot's own competence ([`crate::reference::competence_truth`]): here
    /// "experiment" is 0 for the behaviors drawn, 1 for the commands the robot runs of
    /// behavior "trial", 2 for the truth's whole commands of it.
    Competence = 10,
    /// A mission plan's truth of a behavior's competence (here "experiment" is the plan,
    /// "trial" the behavior's rank in the space).
    CompetenceTruth = 11,
    /// The moments at which the operator's goals change ([`crate::experiment::goal_change`]), drawn
    /// only by experiments with goal changes.
    GoalChange = 12,
    /// Whether a mission's operator trusts the safer behavior an overtrust alert offers
    /// (here "trial" numbers the mission's offer, [`crate::mission::MissionPlan::offer_safer`]).
    Offer = 13,
    /// A mission's context switches ([`crate::mission::ContextSwitches`]): its first
    /// context and when it switches to which, drawn only by plans with switches.
    ContextSwitch = 14,
    /// What the trial's operator states up front ([`crate::contract::stating`]), drawn only by
    /// experiments with `stated`.
    Statements = 15,
    /// The population reference's episodes ([`crate::reference::population_reference`]):
    /// here "experiment" is the member faced, "trial" the episode.
    PopulationReference = 16,
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of the stream for (`master`, `experiment`, `trial`, `purpose`).
pub fn stream_seed(master: u64, experiment: u64, trial: u64, purpose: Purpose) -> u64 {
    [experiment, trial, purpose as u64]
        .iter()
        .fold(mix(master), |acc, &part| {
            mix(acc ^ part.wrapping_mul(0x9e37_79b9_7f4a_7c15))
        })
}

/// The generator for (`master`, `experiment`, `trial`, `purpose`).
pub fn stream(master: u64, experiment: u64, trial: u64, purpose: Purpose) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(stream_seed(master, experiment, trial, purpose))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn streams_differ_by_every_coordinate() {
        let mut seen = HashSet::new();
        for experiment in 0..7 {
            for trial in 0..50 {
                for purpose in [Purpose::Setup, Purpose::Runs, Purpose::Search] {
                    assert!(seen.insert(stream_seed(2014, experiment, trial, purpose)));
                }
            }
        }
        assert_ne!(
            stream_seed(1, 0, 0, Purpose::Setup),
            stream_seed(2, 0, 0, Purpose::Setup)
        );
    }

    #[test]
    fn streams_are_reproducible() {
        assert_eq!(
            stream_seed(2014, 3, 17, Purpose::Runs),
            stream_seed(2014, 3, 17, Purpose::Runs)
        );
    }
}

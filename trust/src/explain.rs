//! Explanations: why the robot gave up a behavior, why it chose the next one, and why it
//! settled, built only from what it was told and what it perceived.
//!
//! **Why a behavior was given up.** An [`Attribution`] watches every command's outcome.
//! Each untrustworthy command (failed or interrupted) is attributed to a reason, one of
//! the domain's declared causes ([`Vocabulary`]):
//! - when the operator stated one, to that reason (it may be wrong: the robot believes
//!   its operator);
//! - otherwise, when the robot perceived something whose name is a declared cause (a
//!   bump is a `collision`), to what it perceived, shared equally when it perceived
//!   several;
//! - otherwise the reason is *inferred*: a probability over the declared causes from what
//!   the robot perceived on that command. A cause the robot would have perceived itself
//!   (one an observation is named after) is ruled out, since it was not perceived. Each
//!   remaining cause scores [`INFERENCE_PRIOR`], plus [`HINT_WEIGHT`] for every perceived
//!   observation the domain says hints at it ([`Hint`]: running behind its own plan hints
//!   at a missed deadline), plus how often operators stated it before when the robot
//!   perceived the same things (learned across episodes from every stated reason). The
//!   scores are normalised.
//!
//! A reason's weight is the number of untrustworthy commands attributed to it (inferred
//! ones count their probability); the reasons are ranked by weight, so the first is the
//! robot's best account. Each carries its evidence: stated `k` times, perceived `k` times,
//! inferred with mean probability `p`.
//!
//! **Why the next behavior.** A reused case says which case, its Algorithm 2 similarity and
//! how many of the behaviors given up in the episode it matched (a behavior of the case
//! at behavior similarity above lambda); a search proposal says what the strategy expects
//! of it or that it explores ([`cbr_core::Searcher::rationale`]).
//!
//! The operator's true reason is never read here: the adapter is handed outcomes only.

use crate::{Cause, Observations, Outcome, Source};
use cbr_core::{Behavior, BehaviorSpace, CaseId, Rationale};
use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// What every inferable cause scores before any evidence (a pseudo-count).
pub const INFERENCE_PRIOR: f64 = 0.5;

/// What a perceived observation adds to the causes it hints at (a pseudo-count: a domain's
/// hint counts as much as a few stated reasons, and stated reasons soon outweigh it).
pub const HINT_WEIGHT: f64 = 2.0;

/// The reasons an explanation lists at most, the most likely first.
pub const MAX_REASONS: usize = 3;

/// A domain's statement that an observation hints at a cause the robot cannot perceive
/// itself (e.g. `behind-plan` hints at `deadline`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hint {
    /// The observation's name.
    pub observation: Cause,
    /// The cause it hints at.
    pub suggests: Cause,
}

/// The names an explanation may use: the domain's declared causes, its observations (bit
/// order) and its hints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Vocabulary {
    /// The declared causes.
    pub causes: Vec<Cause>,
    /// The observations, in bit order.
    pub observations: Vec<Cause>,
    /// Which observations hint at which causes.
    pub hints: Vec<Hint>,
}

/// One reason the robot attributes a given-up behavior's untrustworthy commands to, with
/// its evidence.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AttributedReason {
    /// The reason.
    pub cause: Cause,
    /// Untrustworthy commands attributed to it (inferred ones count their probability).
    pub weight: f64,
    /// Times the operator stated it.
    pub stated: u32,
    /// Untrustworthy commands on which the robot perceived it.
    pub perceived: u32,
    /// Its mean probability over the commands whose reason was inferred (0 when none was).
    pub inferred: f64,
}

impl AttributedReason {
    /// `collision (perceived 3 times)`, `deadline (stated once; inferred, p = 0.62)`.
    pub fn phrase(&self) -> String {
        let times = |k: u32| match k {
            1 => "once".to_owned(),
            2 => "twice".to_owned(),
            k => format!("{k} times"),
        };
        let mut evidence = Vec::new();
        if self.stated > 0 {
            evidence.push(format!("stated {}", times(self.stated)));
        }
        if self.perceived > 0 {
            evidence.push(format!("perceived {}", times(self.perceived)));
        }
        if self.inferred > 0.0 {
            evidence.push(format!("inferred, p = {:.2}", self.inferred));
        }
        format!("{} ({})", self.cause, evidence.join("; "))
    }
}

/// The account of a behavior: its commands, its estimate and the reasons its
/// untrustworthy commands are attributed to. An explanation gives the account of the
/// behavior it gave up ([`Explanation::given_up`]); the adapter gives the account of the
/// behavior in use so far ([`crate::Adaptation::standing`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Account {
    /// The behavior.
    pub behavior: Behavior,
    /// Commands it was used for (since its account last started).
    pub commands: u64,
    /// Those that failed or were interrupted.
    pub untrustworthy: u64,
    /// Its trust estimate (when it was given up, for a behavior given up).
    pub estimate: f64,
    /// The reasons attributed, the most likely first (at most [`MAX_REASONS`]; none when
    /// the domain declares no cause and the operator stated none).
    pub reasons: Vec<AttributedReason>,
}

impl Account {
    /// The reason the robot settles on: the most likely one when it is more likely than
    /// every other (`None` when nothing is attributed or the first reasons tie, so the
    /// order among them is only the order of their names).
    pub fn decided_reason(&self) -> Option<Cause> {
        match self.leading_reasons().as_slice() {
            [only] => Some(*only),
            _ => None,
        }
    }

    /// The reasons that share the first place (one when the robot settles on it; none when
    /// nothing is attributed).
    pub fn leading_reasons(&self) -> Vec<Cause> {
        let Some(first) = self.reasons.first() else {
            return Vec::new();
        };
        self.reasons
            .iter()
            .take_while(|r| r.weight > first.weight - TIE)
            .map(|r| r.cause)
            .collect()
    }
}

/// Weights closer than this tie (they are sums of probabilities).
const TIE: f64 = 1e-9;

/// Why the behavior now in use was chosen, or why the episode ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Next {
    /// The episode switched to `behavior`.
    Switch {
        /// The behavior now in use.
        behavior: Behavior,
        /// Where it came from.
        source: Source,
        /// Why its source chose it: how well a reused case matched (with a case), the
        /// strategy's rationale (with the search).
        grounds: Grounds,
    },
    /// The episode ended on this behavior.
    Kept {
        /// The behavior kept.
        behavior: Behavior,
        /// Whether the operator's trust reached the trustworthy threshold (otherwise every
        /// behavior was tried and the one that resisted longest is kept).
        trustworthy: bool,
        /// Commands the behavior was used for when trusted; when every behavior was tried,
        /// the episode's commands.
        commands: u64,
        /// Its trust estimate at the end (when every behavior was tried, the estimate of
        /// the last behavior given up).
        estimate: f64,
    },
}

/// Why the source of a switch ([`Next::Switch`]) chose its behavior: for a reused case,
/// how well it matched the episode; for the search, the strategy's rationale.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Grounds {
    /// The reused case matched `matched` of the `given_up` behaviors given up in the
    /// episode (a behavior of its problem more similar to one than lambda).
    Matches {
        /// Behaviors given up in the episode that the case matched.
        matched: u32,
        /// Behaviors given up in the episode.
        given_up: u32,
    },
    /// The search strategy's name, and what it expects of the behavior or how it explored.
    Rationale {
        /// The strategy's name.
        strategy: String,
        /// What the strategy expects of it, or how it explored.
        rationale: Rationale,
    },
}

impl Next {
    /// The behavior now in use, or kept.
    pub fn behavior(&self) -> Behavior {
        match self {
            Next::Switch { behavior, .. } | Next::Kept { behavior, .. } => *behavior,
        }
    }

    /// Where the behavior switched to came from (`None`: the episode ended).
    pub fn source(&self) -> Option<Source> {
        match self {
            Next::Switch { source, .. } => Some(*source),
            Next::Kept { .. } => None,
        }
    }
}

/// The explanation of one decision: a switch (a behavior given up and the next one
/// chosen), or the end of an episode.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Explanation {
    /// The account of the behavior given up (`None` when the episode ended on a
    /// trustworthy one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub given_up: Option<Account>,
    /// Why the behavior now in use was chosen, or why the episode ended.
    pub next: Next,
}

impl Explanation {
    /// One plain sentence from the parts, for an operator's screen, with behaviors in the
    /// units of `space`.
    pub fn sentence(&self, space: &BehaviorSpace) -> String {
        self.sentence_naming_cases(space, &|case| case.0.to_string())
    }

    /// [`Explanation::sentence`], with a reused case named by `case_name` (a case store
    /// names its cases by its own ids).
    pub fn sentence_naming_cases(
        &self,
        space: &BehaviorSpace,
        case_name: &dyn Fn(CaseId) -> String,
    ) -> String {
        let mut text = String::new();
        if let Some(given_up) = &self.given_up {
            let _ = write!(
                text,
                "Gave up {} after {} ({} untrustworthy): ",
                space.display(&given_up.behavior),
                plural(given_up.commands, "command"),
                given_up.untrustworthy
            );
            match given_up.reasons.split_first() {
                None => text.push_str("no reason known. "),
                Some((first, rest)) if given_up.decided_reason().is_some() => {
                    let _ = write!(text, "most likely {}", first.phrase());
                    for reason in rest {
                        let _ = write!(text, ", then {}", reason.phrase());
                    }
                    text.push_str(". ");
                }
                Some(_) => {
                    let tied: Vec<String> = given_up
                        .reasons
                        .iter()
                        .map(AttributedReason::phrase)
                        .collect();
                    let _ = write!(text, "no reason stands out: {}. ", tied.join(", "));
                }
            }
        }
        match &self.next {
            Next::Switch {
                behavior,
                source,
                grounds,
            } => {
                let _ = write!(
                    text,
                    "Now {}{}: ",
                    space.display(behavior),
                    changes(space, self.given_up.as_ref().map(|g| g.behavior), behavior),
                );
                match (source, grounds) {
                    (Source::Case { case, similarity }, Grounds::Matches { matched, given_up }) => {
                        let _ = write!(
                            text,
                            "reused case {} (similarity {similarity:.2}, it matches {matched} of the {} given up).",
                            case_name(*case),
                            plural(u64::from(*given_up), "behavior")
                        );
                    }
                    (Source::Case { case, similarity }, Grounds::Rationale { .. }) => {
                        let _ = write!(
                            text,
                            "reused case {} (similarity {similarity:.2}).",
                            case_name(*case)
                        );
                    }
                    (
                        Source::Search,
                        Grounds::Rationale {
                            strategy,
                            rationale,
                        },
                    ) => {
                        let _ = write!(text, "{strategy} search, {}.", rationale.phrase());
                    }
                    (Source::Search, Grounds::Matches { .. }) => text.push_str("search."),
                }
            }
            Next::Kept {
                behavior,
                trustworthy: true,
                commands,
                estimate,
            } => {
                let _ = write!(
                    text,
                    "Keeping {}: trusted after {} (estimate {estimate:+.2}).",
                    space.display(behavior),
                    plural(*commands, "command")
                );
            }
            Next::Kept {
                behavior,
                trustworthy: false,
                ..
            } => {
                let _ = write!(
                    text,
                    "Keeping {}: every behavior has been tried and it resisted longest.",
                    space.display(behavior)
                );
            }
        }
        text
    }
}

/// `1 command`, `3 commands`.
fn plural(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// ` (speed 3.5 -> 2.0)`: the components that changed from `from`, or nothing.
fn changes(space: &BehaviorSpace, from: Option<Behavior>, to: &Behavior) -> String {
    let Some(from) = from else {
        return String::new();
    };
    let changed: Vec<String> = space
        .components()
        .iter()
        .enumerate()
        .filter(|&(k, _)| from.get(k) != to.get(k))
        .map(|(k, c)| {
            format!(
                "{} {} -> {}",
                c.name,
                c.display_value(from.get(k)),
                c.display_value(to.get(k))
            )
        })
        .collect();
    if changed.is_empty() {
        String::new()
    } else {
        format!(" ({})", changed.join(", "))
    }
}

/// The reasoning about why the behavior in use is untrustworthy: what this behavior's
/// untrustworthy commands carried, and what stated reasons taught across episodes (see
/// the module documentation).
#[derive(Clone, Debug)]
pub struct Attribution {
    vocabulary: Vocabulary,
    /// Per observation, the declared cause it is named after, if any.
    attests: Vec<Option<usize>>,
    /// Per cause, whether some observation is named after it.
    perceivable: Vec<bool>,
    /// `learned[o][c]`: stated reasons `c` on commands where observation `o` was perceived;
    /// the last row is for commands where nothing was perceived.
    learned: Vec<Vec<f64>>,
    /// The behavior in use: per cause, attributed weight from statements and perceptions.
    direct: Vec<f64>,
    stated: Vec<u32>,
    perceived: Vec<u32>,
    /// What was perceived on each of its untrustworthy commands whose reason is inferred.
    unexplained: Vec<Observations>,
}

impl Default for Attribution {
    /// An attribution with no vocabulary: it names only stated reasons.
    fn default() -> Self {
        Self::new(Vocabulary::default())
    }
}

impl Attribution {
    /// An attribution over `vocabulary` that has learned nothing yet.
    pub fn new(vocabulary: Vocabulary) -> Self {
        let mut attribution = Self {
            vocabulary: Vocabulary {
                causes: Vec::new(),
                ..vocabulary.clone()
            },
            attests: vec![None; vocabulary.observations.len()],
            perceivable: Vec::new(),
            learned: vec![Vec::new(); vocabulary.observations.len() + 1],
            direct: Vec::new(),
            stated: Vec::new(),
            perceived: Vec::new(),
            unexplained: Vec::new(),
        };
        for cause in vocabulary.causes {
            attribution.cause_index(cause);
        }
        attribution
    }

    /// The vocabulary.
    pub fn vocabulary(&self) -> &Vocabulary {
        &self.vocabulary
    }

    /// The index of `cause`, added when it was not declared (an operator may state a
    /// reason a library user did not declare).
    fn cause_index(&mut self, cause: Cause) -> usize {
        if let Some(i) = self.vocabulary.causes.iter().position(|&c| c == cause) {
            return i;
        }
        let i = self.vocabulary.causes.len();
        self.vocabulary.causes.push(cause);
        let perceivable = self
            .vocabulary
            .observations
            .iter()
            .position(|&o| o == cause);
        if let Some(o) = perceivable {
            self.attests[o] = Some(i);
        }
        self.perceivable.push(perceivable.is_some());
        self.direct.push(0.0);
        self.stated.push(0);
        self.perceived.push(0);
        for row in &mut self.learned {
            row.push(0.0);
        }
        i
    }

    /// Records one command's outcome for the behavior in use.
    pub fn record(&mut self, outcome: &Outcome) {
        if !outcome.is_untrustworthy() {
            return;
        }
        // The causes perceived on this command (every untrustworthy command passes here:
        // no allocation).
        let attests = &self.attests;
        let attested = || {
            outcome
                .observed
                .indices()
                .filter_map(|o| attests.get(o).copied().flatten())
        };
        for c in attested() {
            self.perceived[c] += 1;
        }
        let perceived = attested().count();
        if let Some(reason) = outcome.stated {
            let c = self.cause_index(reason);
            self.stated[c] += 1;
            self.direct[c] += 1.0;
            self.learn(outcome.observed, c);
        } else if perceived > 0 {
            let share = 1.0 / perceived as f64;
            for c in attested() {
                self.direct[c] += share;
            }
        } else {
            self.unexplained.push(outcome.observed);
        }
    }

    /// A stated reason `c` teaches what operators mean when the robot perceives `observed`.
    fn learn(&mut self, observed: Observations, c: usize) {
        let rows = self.learned.len() - 1;
        let mut any = false;
        for o in observed.indices().filter(|&o| o < rows) {
            self.learned[o][c] += 1.0;
            any = true;
        }
        if !any {
            self.learned[rows][c] += 1.0;
        }
    }

    /// The probability of each cause for an unexplained command on which the robot
    /// perceived `observed` (all zero when no cause can be inferred).
    fn infer(&self, observed: Observations) -> Vec<f64> {
        let rows = self.learned.len() - 1;
        let perceived: Vec<usize> = observed.indices().filter(|&o| o < rows).collect();
        let mut scores: Vec<f64> = (0..self.vocabulary.causes.len())
            .map(|c| {
                if self.perceivable[c] {
                    return 0.0;
                }
                let cause = self.vocabulary.causes[c];
                let mut score = INFERENCE_PRIOR;
                for &o in &perceived {
                    let name = self.vocabulary.observations[o];
                    let hinted = self
                        .vocabulary
                        .hints
                        .iter()
                        .any(|h| h.observation == name && h.suggests == cause);
                    if hinted {
                        score += HINT_WEIGHT;
                    }
                    score += self.learned[o][c];
                }
                if perceived.is_empty() {
                    score += self.learned[rows][c];
                }
                score
            })
            .collect();
        let total: f64 = scores.iter().sum();
        if total > 0.0 {
            for s in &mut scores {
                *s /= total;
            }
        }
        scores
    }

    /// The reasons for the behavior in use so far, the most likely first.
    pub fn reasons(&self) -> Vec<AttributedReason> {
        let n = self.vocabulary.causes.len();
        let mut inferred = vec![0.0; n];
        for &observed in &self.unexplained {
            for (sum, p) in inferred.iter_mut().zip(self.infer(observed)) {
                *sum += p;
            }
        }
        let unexplained = self.unexplained.len().max(1) as f64;
        let mut reasons: Vec<AttributedReason> = (0..n)
            .map(|c| AttributedReason {
                cause: self.vocabulary.causes[c],
                weight: self.direct[c] + inferred[c],
                stated: self.stated[c],
                perceived: self.perceived[c],
                inferred: inferred[c] / unexplained,
            })
            .filter(|r| r.weight > 0.0)
            .collect();
        reasons.sort_by(|a, b| {
            b.weight
                .total_cmp(&a.weight)
                .then(b.stated.cmp(&a.stated))
                .then(b.perceived.cmp(&a.perceived))
                .then(a.cause.cmp(&b.cause))
        });
        reasons.truncate(MAX_REASONS);
        reasons.shrink_to_fit();
        reasons
    }

    /// Forgets the behavior in use (a new one is adopted); what was learned stays.
    pub fn next_behavior(&mut self) {
        self.direct.iter_mut().for_each(|w| *w = 0.0);
        self.stated.iter_mut().for_each(|k| *k = 0);
        self.perceived.iter_mut().for_each(|k| *k = 0);
        self.unexplained.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::NamedComponent;

    const COLLISION: Cause = Cause::from_static("collision");
    const DEADLINE: Cause = Cause::from_static("deadline");
    const TOO_CLOSE: Cause = Cause::from_static("too-close");
    const BEHIND: Cause = Cause::from_static("behind-plan");

    /// Causes collision, deadline and too-close; observations collision (bit 0) and
    /// behind-plan (bit 1), which hints at deadline.
    fn vocabulary() -> Vocabulary {
        Vocabulary {
            causes: vec![COLLISION, DEADLINE, TOO_CLOSE],
            observations: vec![COLLISION, BEHIND],
            hints: vec![Hint {
                observation: BEHIND,
                suggests: DEADLINE,
            }],
        }
    }

    fn interrupted() -> Outcome {
        Outcome::interrupted(1.0, 1.0)
    }

    #[test]
    fn a_perceived_cause_is_attributed_directly() {
        let mut a = Attribution::new(vocabulary());
        a.record(&Outcome::completed(1.0, 1.0).observing(Observations::NONE.with(0)));
        a.record(&interrupted().observing(Observations::NONE.with(0)));
        a.record(&interrupted().observing(Observations::NONE.with(0)));
        let reasons = a.reasons();
        assert_eq!(
            reasons,
            vec![AttributedReason {
                cause: COLLISION,
                weight: 2.0,
                stated: 0,
                perceived: 2,
                inferred: 0.0
            }]
        );
        assert_eq!(reasons[0].phrase(), "collision (perceived twice)");
    }

    #[test]
    fn inference_by_hand() {
        // Nothing stated, behind-plan perceived: collision is ruled out (it would have
        // been perceived); deadline scores 0.5 + 2 (the hint), too-close 0.5:
        // p(deadline) = 2.5 / 3, p(too-close) = 0.5 / 3.
        let mut a = Attribution::new(vocabulary());
        a.record(&interrupted().observing(Observations::NONE.with(1)));
        let reasons = a.reasons();
        assert_eq!(reasons[0].cause, DEADLINE);
        assert!((reasons[0].inferred - 2.5 / 3.0).abs() < 1e-12);
        assert!((reasons[1].weight - 0.5 / 3.0).abs() < 1e-12);
        assert_eq!(reasons[0].phrase(), "deadline (inferred, p = 0.83)");
        // Nothing perceived at all: deadline and too-close tie at 1/2, named in order.
        let mut b = Attribution::new(vocabulary());
        b.record(&interrupted());
        let reasons = b.reasons();
        assert_eq!((reasons[0].cause, reasons[0].inferred), (DEADLINE, 0.5));
        assert_eq!((reasons[1].cause, reasons[1].inferred), (TOO_CLOSE, 0.5));
        // Even odds: the robot settles on no reason, and says so.
        let given_up = Account {
            behavior: Behavior::new(&[0]),
            commands: 1,
            untrustworthy: 1,
            estimate: -1.0,
            reasons,
        };
        assert_eq!(given_up.decided_reason(), None);
        let space =
            BehaviorSpace::new(vec![NamedComponent::numeric("x", "", 0.0, 1.0, 2).unwrap()])
                .unwrap();
        let explanation = Explanation {
            given_up: Some(given_up),
            next: Next::Kept {
                behavior: Behavior::new(&[0]),
                trustworthy: false,
                commands: 1,
                estimate: -1.0,
            },
        };
        assert_eq!(
            explanation.sentence(&space),
            "Gave up x=0 after 1 command (1 untrustworthy): no reason stands out: deadline \
             (inferred, p = 0.50), too-close (inferred, p = 0.50). Keeping x=0: every behavior \
             has been tried and it resisted longest."
        );
        assert_eq!(
            Account {
                reasons: a.reasons(),
                ..explanation.given_up.unwrap()
            }
            .decided_reason(),
            Some(DEADLINE)
        );
    }

    #[test]
    fn stated_reasons_rank_first_and_teach_later_inferences() {
        let mut a = Attribution::new(vocabulary());
        // Stated twice with nothing perceived: too-close, weight 2.
        a.record(&interrupted().stating(Some(TOO_CLOSE)));
        a.record(&interrupted().stating(Some(TOO_CLOSE)));
        // One unexplained command with nothing perceived: learned too-close 2 + 0.5,
        // deadline 0.5: p(too-close) = 2.5 / 3.
        a.record(&interrupted());
        let reasons = a.reasons();
        assert_eq!(reasons[0].cause, TOO_CLOSE);
        assert_eq!(reasons[0].stated, 2);
        assert!((reasons[0].weight - (2.0 + 2.5 / 3.0)).abs() < 1e-12);
        assert!(
            reasons[0]
                .phrase()
                .starts_with("too-close (stated twice; inferred, p = 0.83")
        );
        // A new behavior forgets the counts, not what was learned.
        a.next_behavior();
        assert!(a.reasons().is_empty());
        a.record(&interrupted());
        assert_eq!(a.reasons()[0].cause, TOO_CLOSE);
    }

    #[test]
    fn an_undeclared_stated_reason_is_named() {
        let mut a = Attribution::new(Vocabulary::default());
        let overheated = Cause::from_static("overheated");
        a.record(&Outcome::failed(1.0, 1.0).stating(Some(overheated)));
        assert_eq!(a.reasons()[0].cause, overheated);
        // No declared cause: an unexplained command gives no reason.
        let mut b = Attribution::new(Vocabulary::default());
        b.record(&interrupted());
        assert!(b.reasons().is_empty());
    }

    #[test]
    fn sentences_by_hand() {
        let space = BehaviorSpace::new(vec![
            NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 4).unwrap(),
            NamedComponent::numeric("padding", "m", 0.1, 0.1, 4).unwrap(),
        ])
        .unwrap();
        let given_up = Account {
            behavior: Behavior::new(&[3, 0]),
            commands: 4,
            untrustworthy: 3,
            estimate: -5.0,
            reasons: vec![
                AttributedReason {
                    cause: COLLISION,
                    weight: 2.0,
                    stated: 0,
                    perceived: 2,
                    inferred: 0.0,
                },
                AttributedReason {
                    cause: DEADLINE,
                    weight: 1.0,
                    stated: 1,
                    perceived: 0,
                    inferred: 0.0,
                },
            ],
        };
        let reused = Explanation {
            given_up: Some(given_up.clone()),
            next: Next::Switch {
                behavior: Behavior::new(&[1, 0]),
                source: Source::Case {
                    case: CaseId(12),
                    similarity: 0.97,
                },
                grounds: Grounds::Matches {
                    matched: 1,
                    given_up: 1,
                },
            },
        };
        assert_eq!(
            reused.sentence(&space),
            "Gave up speed=2 m/s, padding=0.1 m after 4 commands (3 untrustworthy): most likely \
             collision (perceived twice), then deadline (stated once). Now speed=1 m/s, \
             padding=0.1 m (speed 2 -> 1): reused case 12 (similarity 0.97, it matches 1 of \
             the 1 behavior given up)."
        );
        let searched = Explanation {
            given_up: Some(given_up),
            next: Next::Switch {
                behavior: Behavior::new(&[3, 2]),
                source: Source::Search,
                grounds: Grounds::Rationale {
                    strategy: "random-walk".into(),
                    rationale: Rationale::Explores {
                        how: "one random step".into(),
                    },
                },
            },
        };
        assert!(searched.sentence(&space).ends_with(
            "Now speed=2 m/s, padding=0.3 m (padding 0.1 -> 0.3): random-walk search, exploring: one random step."
        ));
        // A switch names its source; grounds of the other source (only a hand-made
        // explanation has them) leave the source alone in the sentence.
        let swap = |x: &Explanation, source: Source| {
            let Next::Switch {
                behavior, grounds, ..
            } = &x.next
            else {
                panic!("a switch");
            };
            Explanation {
                given_up: None,
                next: Next::Switch {
                    behavior: *behavior,
                    source,
                    grounds: grounds.clone(),
                },
            }
        };
        assert_eq!(
            swap(
                &searched,
                Source::Case {
                    case: CaseId(3),
                    similarity: 0.5
                }
            )
            .sentence(&space),
            "Now speed=2 m/s, padding=0.3 m: reused case 3 (similarity 0.50)."
        );
        assert_eq!(
            swap(&reused, Source::Search).sentence(&space),
            "Now speed=1 m/s, padding=0.1 m: search."
        );
        let json = serde_json::to_string(&reused.next).unwrap();
        assert_eq!(
            json,
            r#"{"kind":"switch","behavior":[1,0],"source":{"source":"case","case":12,"similarity":0.97},"grounds":{"matches":{"matched":1,"given_up":1}}}"#
        );
        assert_eq!(
            serde_json::from_str::<Explanation>(&serde_json::to_string(&searched).unwrap())
                .unwrap(),
            searched
        );
        let kept = Explanation {
            given_up: None,
            next: Next::Kept {
                behavior: Behavior::new(&[0, 0]),
                trustworthy: true,
                commands: 5,
                estimate: 5.0,
            },
        };
        assert_eq!(
            kept.sentence(&space),
            "Keeping speed=0.5 m/s, padding=0.1 m: trusted after 5 commands (estimate +5.00)."
        );
        let json = serde_json::to_string(&kept).unwrap();
        assert_eq!(
            json,
            r#"{"next":{"kind":"kept","behavior":[0,0],"trustworthy":true,"commands":5,"estimate":5.0}}"#
        );
        assert_eq!(serde_json::from_str::<Explanation>(&json).unwrap(), kept);
    }
}

//! Arms: the strategies an experiment compares, as data.
//!
//! An [`Arm`] is a named way of adapting: a search strategy, whether cases are reused
//! (Algorithm 1) and with which retriever, how each episode starts ([`Initial`]), and
//! optionally a case base to start from. The runner builds every arm's parts through
//! factories, so a user's own searcher or retriever enters an experiment exactly as the
//! built-in ones do ([`Arm::search_only`], [`Arm::case_based`]). [`Arm::builtin`] names
//! the built-in arms; any arm's name followed by [`CONTEXT_BLIND`] is that arm not told
//! the robot's context ([`Arm::blind_to_context`]), followed by [`IGNORES_STATEMENTS`] that
//! arm not hearing what operators state up front ([`Arm::ignoring_statements`]), followed by
//! [`LEARNED_START`] that arm
//! starting each episode from the memory's guess ([`Arm::learned_start`]), and followed by
//! [`PREFERS_COMPETENT`] (last) that arm passing over a trusted behavior the robot is sure
//! is not competent, on missions that judge it ([`Arm::preferring_competent`]); the
//! suffixes are written in that order ([`NameOptions`]).

pub use super::arm_name::{
    ArmName, ArmNameError, CONTEXT_BLIND, IGNORES_STATEMENTS, Initial, LEARNED_START, NameOptions,
    PREFERS_COMPETENT,
};
use cbr_core::BehaviorSpace;
use std::fmt;
use std::sync::Arc;
use std::sync::LazyLock;
use trust::retrieval::RetrieverKind;
use trust::search::{Look, Strategy, TrustSearcher, strategies};
use trust::{RetrieverFactory, SearcherFactory, SetSimilarity};
use trust::{TrustCaseBase, TrustRetriever};

/// A built-in arm: a registered search strategy ([`trust::search::strategies`]) alone, or
/// after case reuse (Algorithm 1 first, the strategy when no case fits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuiltinArm {
    /// Its name (`cause-aware`, `case-based+cause-aware`; the paper's two are
    /// `random-walk` and `case-based`).
    pub name: &'static str,
    /// What it does, in one line.
    pub description: &'static str,
    /// How it looks in figures.
    pub look: Look,
    /// The strategy it searches with.
    pub strategy: &'static Strategy,
    /// Whether it reuses cases.
    pub reuses_cases: bool,
}

/// The built-in arms, read from the strategies' registry: each strategy alone, then after
/// case reuse where it is offered so; the paper's two first.
pub fn builtin_arms() -> &'static [BuiltinArm] {
    static ARMS: LazyLock<Vec<BuiltinArm>> = LazyLock::new(|| {
        strategies()
            .iter()
            .flat_map(|strategy| {
                let alone = BuiltinArm {
                    name: strategy.name,
                    description: strategy.description,
                    look: strategy.look,
                    strategy,
                    reuses_cases: false,
                };
                let reusing = strategy.with_cases.map(|with| BuiltinArm {
                    name: with.name,
                    description: with.description,
                    look: with.look,
                    strategy,
                    reuses_cases: true,
                });
                std::iter::once(alone).chain(reusing)
            })
            .collect()
    });
    &ARMS
}

/// The arm the tool recommends: the default of `serve --arm`, of Python's `Adapter` and of
/// a mission suite that lists no arms, and `"recommended"` in every report's
/// `summary.json`. Chosen on the benchmark's development instances only (the fewest
/// untrustworthy commands over the known-operator limit, geometric mean over patrol's and
/// movement's populations); its figures on the evaluation instances are in
/// docs/search-strategies.md, "The recommended arm".
pub const RECOMMENDED_ARM: &str = "case-based+nested";

/// The built-in arm named `name` (without suffixes).
pub fn builtin_arm(name: &str) -> Option<&'static BuiltinArm> {
    builtin_arms().iter().find(|a| a.name == name)
}

/// The built-in arms' names, in [`builtin_arms`]' order.
pub fn builtin_arm_names() -> Vec<&'static str> {
    builtin_arms().iter().map(|a| a.name).collect()
}

/// How many trusted behaviors an episode of an arm preferring competent ones passes over
/// before it settles on the next whatever its competence: one more look. Each pass costs
/// another search for a trusted behavior, so more would multiply what the operator
/// endures for a preference the operator did not state.
pub const COMPETENT_PASSES: u32 = 1;

/// What each built-in arm does, in one line (docs/search-strategies.md tells more),
/// followed for a [`LEARNED_START`] arm by how it starts; `None` for an arm that is not
/// built in.
pub fn describe(name: &ArmName) -> Option<String> {
    let options = name.options();
    let what = builtin_arm(name.base())?.description;
    let what = if options.context_blind {
        format!(
            "{what}; blind to the robot's context, as the paper's robot: every episode and case in the default context"
        )
    } else {
        what.to_owned()
    };
    let what = if options.ignores_statements {
        format!("{what}; deaf to what operators state up front, as the paper's robot")
    } else {
        what
    };
    let what = match options.initial {
        Initial::Random => what,
        Initial::Learned => format!(
            "{what}; each episode starts from the behavior earlier operators accepted most often (the case memory's guess), not at random"
        ),
    };
    Some(if options.prefers_competent {
        format!(
            "{what}; on missions that judge the robot's competence, an episode passes over a trusted behavior the robot is sure falls short, once, and searches on"
        )
    } else {
        what
    })
}

/// One strategy of an experiment.
#[derive(Clone)]
pub struct Arm {
    /// Its name, which also carries its options (blind, deaf, learned start, competent).
    name: ArmName,
    searcher: SearcherFactory,
    retriever: Option<RetrieverFactory>,
    starting_cases: Option<Arc<TrustCaseBase>>,
}

impl fmt::Debug for Arm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Arm")
            .field("name", &self.name)
            .field("reuses_cases", &self.reuses_cases())
            .field(
                "starting_cases",
                &self.starting_cases.as_ref().map(|c| c.len()),
            )
            .finish()
    }
}

/// An arm name that is not a built-in one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown arm `{name}` (known: {}; each also as NAME{CONTEXT_BLIND}, NAME{IGNORES_STATEMENTS}, NAME{LEARNED_START} and NAME{PREFERS_COMPETENT})", builtin_arm_names().join(", "))]
pub struct UnknownArm {
    /// The name asked for.
    pub name: String,
}

impl Arm {
    /// The search strategy alone: every adaptation comes from `searcher` (cases are still
    /// retained as docs/model.md#cases-and-retention says, and counted, but never read).
    /// `name` is the arm's own, taken as it is: the options its suffixes would name are
    /// added by the methods below ([`Arm::with_name_options`]).
    pub fn search_only(
        name: impl Into<String>,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: ArmName::new(&name.into(), NameOptions::default()),
            searcher: Arc::new(searcher),
            retriever: None,
            starting_cases: None,
        }
    }

    /// Algorithm 1 over the cases `retriever` indexes, with `searcher` as its fallback;
    /// `retriever` ranks cases by the measure it is given (Algorithm 2 at the suite's
    /// `lambda`, weighing contexts as the domain declares: [`trust::SetSimilarity::of_domain`]).
    pub fn case_based(
        name: impl Into<String>,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
        retriever: impl Fn(SetSimilarity) -> Box<TrustRetriever> + Send + Sync + 'static,
    ) -> Self {
        Self {
            retriever: Some(Arc::new(retriever)),
            ..Self::search_only(name, searcher)
        }
    }

    /// Algorithm 1 over the cases a built-in retriever of `retriever`'s kind indexes (the
    /// suite's `adapter.retriever`, which `Catalog::arms` is handed), with `searcher` as
    /// its fallback.
    pub fn case_based_over(
        name: impl Into<String>,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
        retriever: RetrieverKind,
    ) -> Self {
        Self::case_based(name, searcher, move |measure| {
            retriever.build_measure(measure)
        })
    }

    /// A searcher offered as the built-in ones are: the arm `name` (the search alone) and
    /// `case-based+name` (Algorithm 1 over `retriever`'s kind, with it as fallback).
    ///
    /// ```
    /// use lab::Arm;
    /// use trust::RetrieverKind;
    /// use trust::search::Uniform;
    ///
    /// let [alone, reusing] =
    ///     Arm::search_and_case_based("uniform", |_| Box::new(Uniform::new()), RetrieverKind::Linear);
    /// assert_eq!((alone.name(), alone.reuses_cases()), ("uniform", false));
    /// assert_eq!((reusing.name(), reusing.reuses_cases()), ("case-based+uniform", true));
    /// ```
    pub fn search_and_case_based(
        name: &str,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Clone + Send + Sync + 'static,
        retriever: RetrieverKind,
    ) -> [Self; 2] {
        [
            Self::search_only(name, searcher.clone()),
            Self::case_based_over(format!("case-based+{name}"), searcher, retriever),
        ]
    }

    /// The same arm starting every experiment from `cases` instead of an empty case base.
    pub fn with_starting_cases(mut self, cases: TrustCaseBase) -> Self {
        self.starting_cases = Some(Arc::new(cases));
        self
    }

    /// The same arm not told the robot's context, as the paper's robot is not: its
    /// episodes, and the cases they retain, are all in the default context whatever the
    /// trial's context is. Named with [`CONTEXT_BLIND`] after its name.
    pub fn blind_to_context(self) -> Self {
        self.with_name_options(NameOptions {
            context_blind: true,
            ..NameOptions::default()
        })
    }

    /// Whether the arm is not told the robot's context ([`Arm::blind_to_context`]).
    pub fn is_context_blind(&self) -> bool {
        self.name.options().context_blind
    }

    /// The same arm not hearing what operators state up front, as the paper's robot: its
    /// episodes begin as if nothing were stated, on the same trials as the arm that hears
    /// (so the two pair trial by trial). Named with [`IGNORES_STATEMENTS`] after its name.
    pub fn ignoring_statements(self) -> Self {
        self.with_name_options(NameOptions {
            ignores_statements: true,
            ..NameOptions::default()
        })
    }

    /// Whether the arm does not hear what operators state ([`Arm::ignoring_statements`]).
    pub fn ignores_statements(&self) -> bool {
        self.name.options().ignores_statements
    }

    /// The same arm starting each episode from the case memory's guess
    /// ([`Initial::Learned`]), named with [`LEARNED_START`] after its name. Its trials read
    /// the cases earlier ones retained, so they run in order even where the arm reuses no
    /// case.
    pub fn learned_start(self) -> Self {
        self.with_name_options(NameOptions {
            initial: Initial::Learned,
            ..NameOptions::default()
        })
    }

    /// The same arm preferring behaviors the robot judges competent, named with
    /// [`PREFERS_COMPETENT`] after its name: on a mission that judges the robot's
    /// competence, each episode passes over up to [`COMPETENT_PASSES`] behaviors its
    /// operator trusts while the robot is sure they fall short of the standard, searching
    /// on past each ([`trust::MissionAdapter::preferring_competent`]). Elsewhere it is
    /// refused (an experiment, or a mission plan without a standard, judges nothing).
    pub fn preferring_competent(self) -> Self {
        self.with_name_options(NameOptions {
            prefers_competent: true,
            ..NameOptions::default()
        })
    }

    /// Trusted behaviors an episode of the arm passes over for being surely not
    /// competent (0 unless [`Arm::preferring_competent`]).
    pub fn competent_passes(&self) -> u32 {
        if self.name.options().prefers_competent {
            COMPETENT_PASSES
        } else {
            0
        }
    }

    /// A built-in arm by name ([`builtin_arms`]): `NAME` is a search strategy alone and
    /// `case-based+NAME` is Algorithm 1 with it as fallback (`case-based` falls back to
    /// the random walk, as in the paper); case-based arms use `retriever`. Each name
    /// followed by the suffixes of [`NameOptions`] is the same arm with what they add
    /// ([`Arm::with_name_options`]).
    pub fn builtin(name: &str, retriever: RetrieverKind) -> Result<Self, UnknownArm> {
        let name = ArmName::parse(name).map_err(|_| UnknownArm {
            name: name.to_owned(),
        })?;
        Self::builtin_named(&name, retriever)
    }

    /// The built-in arm `name` names ([`Arm::builtin`], for a name already read).
    pub fn builtin_named(name: &ArmName, retriever: RetrieverKind) -> Result<Self, UnknownArm> {
        let builtin = builtin_arm(name.base()).ok_or_else(|| UnknownArm {
            name: name.to_string(),
        })?;
        Ok(Self::of_builtin(builtin, retriever).with_name_options(name.options()))
    }

    /// The same arm with the options `options` turns on added to its own (an option it
    /// has stays): blind to the robot's context ([`Arm::blind_to_context`]), deaf to
    /// statements ([`Arm::ignoring_statements`]), starting from the memory's guess
    /// ([`Arm::learned_start`]), and preferring competent behaviors
    /// ([`Arm::preferring_competent`]), its name's suffixes written in that order.
    pub fn with_name_options(mut self, options: NameOptions) -> Self {
        let own = self.name.options();
        let learned = own.initial == Initial::Learned || options.initial == Initial::Learned;
        self.name = self.name.with_options(NameOptions {
            context_blind: own.context_blind || options.context_blind,
            ignores_statements: own.ignores_statements || options.ignores_statements,
            initial: if learned {
                Initial::Learned
            } else {
                Initial::Random
            },
            prefers_competent: own.prefers_competent || options.prefers_competent,
        });
        self
    }

    /// The built-in arm `builtin`, starting at random.
    fn of_builtin(builtin: &BuiltinArm, retriever: RetrieverKind) -> Self {
        let build = builtin.strategy.build;
        let searcher = move |_: &Arc<BehaviorSpace>| build();
        if builtin.reuses_cases {
            Self::case_based_over(builtin.name, searcher, retriever)
        } else {
            Self::search_only(builtin.name, searcher)
        }
    }

    /// The arm's name in reports.
    pub fn name(&self) -> &str {
        self.name.as_str()
    }

    /// The arm's name, read: its base and its options.
    pub fn arm_name(&self) -> &ArmName {
        &self.name
    }

    /// Whether the arm reuses cases (Algorithm 1).
    pub fn reuses_cases(&self) -> bool {
        self.retriever.is_some()
    }

    /// How the arm's episodes start.
    pub fn initial(&self) -> Initial {
        self.name.options().initial
    }

    /// Whether the arm reads the cases earlier episodes retained: it reuses them, or it
    /// starts each episode from their guess.
    pub fn reads_cases(&self) -> bool {
        self.reuses_cases() || self.initial() == Initial::Learned
    }

    /// The case base the arm starts from, if any.
    pub fn starting_cases(&self) -> Option<&TrustCaseBase> {
        self.starting_cases.as_deref()
    }

    /// A fresh searcher for `space`.
    pub fn build_searcher(&self, space: &Arc<BehaviorSpace>) -> Box<TrustSearcher> {
        (self.searcher)(space)
    }

    /// The retriever ranking cases by `measure`: the arm's own when it reuses cases, the
    /// linear scan otherwise (it only receives the retained cases, which are never read).
    pub fn build_retriever(&self, measure: SetSimilarity) -> Box<TrustRetriever> {
        match &self.retriever {
            Some(build) => build(measure),
            None => RetrieverKind::Linear.build_measure(measure),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_name_builds_and_others_are_refused_with_the_list() {
        let space = Arc::new(
            BehaviorSpace::new(vec![
                cbr_core::NamedComponent::numeric("x", "", 0.0, 1.0, 3).unwrap(),
            ])
            .unwrap(),
        );
        let names = builtin_arm_names();
        assert_eq!(
            names,
            [
                "random-walk",
                "case-based",
                "uniform",
                "cause-aware",
                "case-based+cause-aware",
                "model-based",
                "case-based+model-based",
                "conditioned",
                "case-based+conditioned",
                "hedged",
                "case-based+hedged",
                "bandit",
                "case-based+bandit",
                "reliable",
                "case-based+reliable",
                "nested",
                "case-based+nested",
            ],
            "each strategy alone, then after case reuse where it is offered so"
        );
        let recommended = builtin_arm(RECOMMENDED_ARM).expect("the recommended arm is built in");
        assert!(recommended.reuses_cases && recommended.strategy.learns_across_episodes());
        for name in names {
            let arm = Arm::builtin(name, RetrieverKind::Linear).unwrap();
            assert_eq!(arm.name(), name);
            assert_eq!(arm.reuses_cases(), name.starts_with("case-based"));
            let searcher = arm.build_searcher(&space);
            let expected = name.strip_prefix("case-based+").unwrap_or(match name {
                "case-based" => "random-walk",
                other => other,
            });
            assert_eq!(searcher.name(), expected);
        }
        let err = Arm::builtin("case-based+random-walk", RetrieverKind::Linear).unwrap_err();
        assert!(
            err.to_string()
                .contains("known: random-walk, case-based, uniform")
        );
        assert!(Arm::builtin("annealing", RetrieverKind::Linear).is_err());
    }

    #[test]
    fn preferring_competent_behaviors_is_the_last_suffix_of_any_arm_name() {
        let arm = Arm::builtin(
            "case-based+conditioned+learned-start+competent",
            RetrieverKind::Linear,
        )
        .unwrap();
        assert_eq!(arm.name(), "case-based+conditioned+learned-start+competent");
        assert_eq!(
            (arm.initial(), arm.competent_passes()),
            (Initial::Learned, COMPETENT_PASSES)
        );
        let plain = Arm::builtin("uniform", RetrieverKind::Linear).unwrap();
        assert_eq!(plain.competent_passes(), 0);
        // Once only.
        let preferring = plain.preferring_competent().preferring_competent();
        assert_eq!(preferring.name(), "uniform+competent");
        // Last: before the learned start it is no arm's name.
        for bad in ["competent", "uniform+competent+learned-start"] {
            let err = Arm::builtin(bad, RetrieverKind::Linear).unwrap_err();
            assert!(err.to_string().contains("NAME+competent"), "{err}");
        }
        assert!(describe(&ArmName::parse("uniform+competent").unwrap()).unwrap().ends_with(
            "passes over a trusted behavior the robot is sure falls short, once, and searches on"
        ));
    }

    #[test]
    fn context_blindness_is_the_first_suffix_of_any_arm_name() {
        let arm = Arm::builtin(
            "case-based+context-blind+learned-start+competent",
            RetrieverKind::Linear,
        )
        .unwrap();
        assert!(arm.is_context_blind());
        assert_eq!(
            (arm.initial(), arm.competent_passes()),
            (Initial::Learned, COMPETENT_PASSES)
        );
        let plain = Arm::builtin("case-based", RetrieverKind::Linear).unwrap();
        assert!(!plain.is_context_blind());
        // Once only.
        let blind = plain.blind_to_context().blind_to_context();
        assert_eq!(blind.name(), "case-based+context-blind");
        assert!(
            describe(&ArmName::parse("case-based+context-blind").unwrap())
                .unwrap()
                .ends_with("every episode and case in the default context")
        );
    }

    #[test]
    fn a_learned_start_is_a_suffix_of_any_arm_name() {
        let arm = Arm::builtin(
            "case-based+conditioned+learned-start",
            RetrieverKind::Linear,
        )
        .unwrap();
        assert_eq!(arm.name(), "case-based+conditioned+learned-start");
        assert_eq!(arm.initial(), Initial::Learned);
        assert!(arm.reuses_cases() && arm.reads_cases());
        // A search-only arm that starts from the guess reads cases, without reusing them.
        let arm = Arm::builtin("uniform+learned-start", RetrieverKind::Linear).unwrap();
        assert!(!arm.reuses_cases() && arm.reads_cases());
        let plain = Arm::builtin("uniform", RetrieverKind::Linear).unwrap();
        assert_eq!(plain.initial(), Initial::Random);
        assert!(!plain.reads_cases());
        // Once only.
        assert_eq!(arm.learned_start().name(), "uniform+learned-start");
        for bad in [
            "learned-start",
            "+learned-start",
            "uniform+learned-start+learned-start",
        ] {
            let err = Arm::builtin(bad, RetrieverKind::Linear).unwrap_err();
            assert!(err.to_string().contains("NAME+learned-start"), "{err}");
        }
        assert!(
            describe(&ArmName::parse("case-based+learned-start").unwrap())
                .unwrap()
                .contains("not at random")
        );
        assert_eq!(
            describe(&ArmName::parse("uniform").unwrap()).unwrap(),
            "an untried behavior uniformly at random: the baseline a learning strategy must beat"
        );
        assert_eq!(
            describe(&ArmName::parse("mine+learned-start").unwrap()),
            None
        );
    }
}

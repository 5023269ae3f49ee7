//! End-to-end through the library the command line and the Python package share
//! (`trustcbr::run::run_with_report`): arms a plug-in or a Python caller adds, with names
//! that would leave their folder, searchers that break their contract, and rationales
//! that hold control characters.

use std::path::Path;
use std::sync::Arc;
use trustcbr::cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use trustcbr::lab::Arm;
use trustcbr::run::{RunSettings, run_with_report};
use trustcbr::suite::{StartingCases, SuiteConfig};
use trustcbr::trust::search::Uniform;
use trustcbr::trust::{Evaluated, Outcome, TrustSearcher};
use trustcbr::{AddedArm, UgvCatalog, WithArms};

/// The UGV catalog with `arm` added, as the Python package adds a Python arm.
fn with_arm(
    arm: impl Fn(trustcbr::trust::RetrieverKind) -> Arm + Send + Sync + 'static,
) -> WithArms<UgvCatalog> {
    let added: AddedArm = Arc::new(arm);
    WithArms {
        inner: UgvCatalog,
        arms: vec![added],
    }
}

/// A one-experiment suite of `trials` trials of the arm `arm`.
fn suite(catalog: &WithArms<UgvCatalog>, arm: &str, trials: u32) -> Result<SuiteConfig, String> {
    SuiteConfig::from_ron(
        catalog,
        &format!(
            "(seed: 1, trials: {trials}, landscape_runs: 0, limit: (runs: 0), arms: [{arm:?}], experiments: [(scenario: \"movement\", operator: \"balanced\")])"
        ),
        Path::new("suite.ron"),
    )
    .map_err(|e| format!("{e:#}"))
}

#[test]
fn an_arm_named_to_leave_its_folder_is_refused_and_nothing_outside_is_written() {
    let catalog = with_arm(|retriever| {
        Arm::case_based(
            "../../victim",
            |_| Box::new(Uniform::new()),
            move |measure| retriever.build_measure(measure),
        )
    });
    let dir = tempfile::tempdir().unwrap();
    let victim = dir.path().join("victim.ron");
    std::fs::write(&victim, "precious").unwrap();
    let saves = dir.path().join("saves");
    // The config is refused where it names the arm...
    let err = suite(&catalog, "../../victim", 2).unwrap_err();
    assert!(
        err.contains("arms[0]: arm name `../../victim` holds `/`, which a file name may not"),
        "{err}"
    );
    // ... and a config that skipped the check (built by hand) is refused by the run, for
    // the writer (`--save-cases`) and the reader (`--cases`) alike.
    let mut config = SuiteConfig::from_ron(
        &catalog,
        "(seed: 1, trials: 2, landscape_runs: 0, limit: (runs: 0), arms: [\"uniform\"], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
        Path::new("suite.ron"),
    )
    .unwrap();
    config.arms = vec!["../../victim".parse().unwrap()];
    for settings in [
        RunSettings {
            save_cases: Some(saves.clone()),
            ..RunSettings::default()
        },
        RunSettings {
            starting: Some(StartingCases { dir: saves.clone() }),
            ..RunSettings::default()
        },
    ] {
        std::fs::create_dir_all(&saves).unwrap();
        let err = run_with_report(
            &catalog,
            config.clone(),
            Path::new("suite.ron"),
            &settings,
            &|_| (),
        )
        .err()
        .map(|e| format!("{e:#}"))
        .expect("refused");
        assert!(err.contains("arm name `../../victim` holds `/`"), "{err}");
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert!(!saves.join("movement-balanced").exists());
}

/// A searcher that breaks its contract: it proposes the behavior just given up, or one
/// outside the space.
struct Rogue {
    outside: bool,
}

impl Searcher for Rogue {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "rogue"
    }

    fn propose(
        &mut self,
        _space: &BehaviorSpace,
        evaluated: &[Evaluated],
        _rng: &mut dyn trustcbr::rand::RngCore,
    ) -> Proposal {
        if self.outside {
            Proposal::Next(Behavior::new(&[999, 999]))
        } else {
            Proposal::Next(evaluated.last().expect("a behavior was given up").behavior)
        }
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        Rationale::Explores {
            how: "\u{1b}[31mred\u{1b}[0m\nand\u{7}a bell".into(),
        }
    }
}

fn rogue(outside: bool) -> WithArms<UgvCatalog> {
    with_arm(move |_| {
        Arm::search_only("rogue", move |_| -> Box<TrustSearcher> {
            Box::new(Rogue { outside })
        })
    })
}

#[test]
fn the_runner_refuses_a_search_that_repeats_a_behavior_or_leaves_the_space() {
    for (outside, expected) in [
        (false, "the search of arm `rogue` proposed speed="),
        (
            true,
            "the search of arm `rogue` proposed the value indices [999, 999], which is outside the behavior space",
        ),
    ] {
        let catalog = rogue(outside);
        let config = suite(&catalog, "rogue", 20).unwrap();
        let err = run_with_report(
            &catalog,
            config,
            Path::new("suite.ron"),
            &RunSettings::default(),
            &|_| (),
        )
        .err()
        .map(|e| format!("{e:#}"))
        .expect("refused");
        assert!(
            err.contains("movement/balanced: ") && err.contains(expected),
            "{err}"
        );
        if !outside {
            assert!(
                err.contains("which the episode has already evaluated"),
                "{err}"
            );
        }
    }
}

/// A searcher that proposes untried behaviors (the uniform search) with a rationale full
/// of control characters.
struct Loud(Box<TrustSearcher>);

impl Searcher for Loud {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "loud"
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn trustcbr::rand::RngCore,
    ) -> Proposal {
        self.0.propose(space, evaluated, rng)
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        Rogue { outside: false }.rationale(proposed)
    }
}

#[test]
fn a_rationale_s_control_characters_never_reach_the_report_raw() {
    let catalog = with_arm(|_| {
        Arm::search_only("loud", |_| -> Box<TrustSearcher> {
            Box::new(Loud(Box::new(Uniform::new())))
        })
    });
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let config = suite(&catalog, "loud", 3).unwrap();
    let settings = RunSettings {
        out: Some(out.clone()),
        ..RunSettings::default()
    };
    run_with_report(&catalog, config, Path::new("suite.ron"), &settings, &|_| ()).unwrap();
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("red\u{FFFD}"), "the rationale is shown");
    for file in ["report.html", "table.md", "timeline-movement-balanced.svg"] {
        let text = std::fs::read_to_string(out.join(file)).unwrap();
        assert!(
            !text.contains(['\u{1b}', '\u{7}']),
            "{file} holds a control character"
        );
    }
}

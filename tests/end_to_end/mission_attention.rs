//! Mission suites whose operators grow complacent need a domain that models attention
//! (`lab::Attentive`): over a catalog whose domain does not implement it,
//! such a suite is refused before anything runs, naming the plan's field and the trait,
//! while its attentive plans run; the UGV domain models attention and runs both.

use rand::{Rng, RngCore};
use std::path::Path;
use std::sync::Arc;
use trustcbr::cbr_core::{Behavior, BehaviorSpace, NamedComponent};
use trustcbr::lab::{Domain, Judgement};
use trustcbr::mission_suite::{MissionSuiteConfig, run_mission_suite};
use trustcbr::trust::{Cause, DeclaredCause};
use trustcbr::{Catalog, CatalogError, Readings, ToolInfo, UgvCatalog};

const GLARE: Cause = Cause::from_static("glare");

/// A lamp of 11 brightness levels; an operator interrupts it for glare the further it is
/// from the level it wants. Its operators' attention is not modelled: it does not implement `Attentive`.
struct Lamp(Arc<BehaviorSpace>);

impl Domain for Lamp {
    type Operator = u16;

    fn name(&self) -> &str {
        "lamp"
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        &self.0
    }

    fn causes(&self) -> &[DeclaredCause] {
        const DECLARED: [DeclaredCause; 1] = [DeclaredCause {
            name: GLARE,
            default_weight: None,
        }];
        &DECLARED
    }

    fn run(&self, behavior: &Behavior, wanted: &u16, rng: &mut dyn RngCore) -> Judgement {
        let off = f64::from(behavior.get(0).abs_diff(*wanted));
        if rng.random::<f64>() < 1.0 - off / 10.0 {
            Judgement::completed(1.0, 1.0)
        } else {
            Judgement::interrupted(1.0, GLARE, 1.0)
        }
    }
}

struct LampCatalog;

impl Catalog for LampCatalog {
    type Domain = Lamp;

    fn tool(&self) -> ToolInfo {
        trustcbr::tool_info!()
    }

    fn scenarios(&self) -> Vec<String> {
        vec!["lamp".into()]
    }

    fn domain(&self, scenario: &str) -> Option<Lamp> {
        let level = NamedComponent::numeric("brightness", "", 0.0, 1.0, 11).ok()?;
        (scenario == "lamp").then(|| Lamp(Arc::new(BehaviorSpace::new(vec![level]).unwrap())))
    }

    fn operators(&self, _: &str, _: &Readings) -> Vec<(String, u16)> {
        vec![("dim".into(), 2), ("bright".into(), 9)]
    }

    fn load_operator(
        &self,
        _: &str,
        path: &Path,
        _: &Readings,
    ) -> Result<(String, u16), CatalogError> {
        Err(CatalogError {
            path: Some(path.into()),
            reason: "lamps have no operator files".into(),
        })
    }

    fn default_suite(&self) -> &str {
        "(seed: 1, trials: 10, experiments: [(scenario: \"lamp\", operator: \"random\")])"
    }
}

/// A mission suite of one attentive plan and, when `complacent`, one whose operators grow
/// complacent, over `scenario`.
fn suite(scenario: &str, complacent: bool) -> String {
    let plan = |name: &str, complacency: &str| {
        format!(
            "(name: \"{name}\", operators: (scenario: \"{scenario}\", operator: \"random\"), count: 2, commands: 60, changes: (every: 30.0, takeover: 0.5){complacency})"
        )
    };
    let mut plans = vec![plan("attentive", "")];
    if complacent {
        plans.push(plan(
            "complacent",
            ", complacency: Some((memory: 20.0, floor: 0.3))",
        ));
    }
    format!(
        "(seed: 3, arms: [\"case-based\", \"uniform\"], missions: [{}])",
        plans.join(", ")
    )
}

fn parse(text: &str) -> MissionSuiteConfig {
    trustcbr::files::parse_ron(text, Path::new("lamp.ron")).unwrap()
}

#[test]
fn a_complacency_plan_is_refused_on_a_domain_that_does_not_model_attention() {
    let origin = Path::new("lamp.ron");
    let err = parse(&suite("lamp", true))
        .validate(&LampCatalog, origin)
        .unwrap_err()
        .to_string();
    let expected = "lamp.ron: missions[1].complacency: domain `lamp` does not model its operators' attention: it does not implement `Attentive` (its `Domain::attentive` answers None), so operators who grow complacent would still notice everything and alerts could change nothing; a plan with `complacency` needs a domain that models attention (docs/plugin-guide.md)";
    assert_eq!(err, expected);
    // Running it unchecked is refused too, before any mission, where its plan is built.
    let err = run_mission_suite(&LampCatalog, &parse(&suite("lamp", true)), origin, &|_| {})
        .unwrap_err()
        .to_string();
    assert_eq!(err, expected);
    // Attentive operators need no model of attention.
    let attentive = parse(&suite("lamp", false));
    attentive.validate(&LampCatalog, origin).unwrap();
    let results = run_mission_suite(&LampCatalog, &attentive, origin, &|_| {}).unwrap();
    assert_eq!(results[0].arms.len(), 2);
}

#[test]
fn the_ugv_domain_models_attention_and_runs_complacency_plans() {
    let origin = Path::new("ugv.ron");
    let config = parse(&suite("movement", true));
    config.validate(&UgvCatalog, origin).unwrap();
    let results = run_mission_suite(&UgvCatalog, &config, origin, &|_| {}).unwrap();
    let complacent = &results[1];
    assert!(complacent.complacency);
    // Each arm twice (alerts ignored, answered), every mission run.
    assert_eq!(complacent.arms.len(), 4);
    assert!(complacent.arms.iter().all(|arm| arm.missions.len() == 2));
}

//! Missions on a toy domain whose operators may overlook what they mind: pairing across
//! arms, determinism across thread counts, what the records count, arms that start from
//! the case memory's guess, and complacency refused on a domain that does not model
//! attention.

use cbr_core::{Behavior, Case};
use lab::Arm;
use lab::mission::noticing::Noticing;
use lab::mission::report::{missions_json, missions_markdown};
use lab::mission::summary::{
    MissionSummary, OracleFigure, OracleSummary, harm_comparisons, oracle_multiple,
};
use lab::mission::{
    ChangeKind, Changes, Complacency, ComplacencyOn, MissionPlan, MissionRecord, MissionResult,
    run_missions,
};
use lab::reference::known_operator::LimitSettings;
use lab::testing::{Bare, ToyDomain};
use lab::{Domain, Judgement, PlanError, check_attention};
use rand::Rng;
use trust::AdapterConfig;
use trust::{Cause, Evaluated, Observations, RetrieverKind, TrustCaseBase, first_guess};

const BUMPED: Cause = Cause::from_static("bumped");

/// A 6 x 6 grid; an operator minds every behavior but its favourite, where the robot
/// bumps into things (and feels it) four times in five; it stops the robot for a bump it
/// notices.
type Toy = ToyDomain<Favourite>;

struct Favourite(Behavior);

impl lab::SimulatedOperator for Favourite {}

fn toy() -> Toy {
    ToyDomain::grid(
        "toy",
        &[6, 6],
        &[BUMPED],
        |behavior, operator: &Favourite, attention, rng| {
            let bumps = if *behavior == operator.0 { 0.05 } else { 0.8 };
            if !rng.random_bool(bumps) {
                return Judgement::completed(1.0, 1.0);
            }
            let felt = Observations::NONE.with(0);
            if rng.random::<f64>() < attention {
                Judgement::interrupted(1.0, BUMPED, 1.0).observing(felt)
            } else {
                Judgement::completed(1.0, 1.0)
                    .observing(felt)
                    .overlooking(Some(BUMPED))
            }
        },
    )
    .perceiving(&[BUMPED], &[])
}

fn operators() -> Vec<(String, Favourite)> {
    vec![
        ("low".to_owned(), Favourite(Behavior::new(&[1, 1]))),
        ("high".to_owned(), Favourite(Behavior::new(&[4, 5]))),
    ]
}

fn arms() -> Vec<Arm> {
    ["case-based", "uniform"]
        .into_iter()
        .map(|name| Arm::builtin(name, RetrieverKind::Linear).unwrap())
        .collect()
}

fn run<'a, D: Domain<Operator = Favourite>>(
    domain: &'a D,
    operators: &'a [(String, Favourite)],
    complacency: Option<ComplacencyOn<'a, Favourite>>,
    threads: usize,
) -> Vec<MissionResult> {
    run_arms(domain, operators, complacency, threads, arms())
}

fn run_arms<'a, D: Domain<Operator = Favourite>>(
    domain: &'a D,
    operators: &'a [(String, Favourite)],
    complacency: Option<ComplacencyOn<'a, Favourite>>,
    threads: usize,
    arms: Vec<Arm>,
) -> Vec<MissionResult> {
    try_run_arms(domain, operators, complacency, threads, arms).unwrap()
}

fn try_run_arms<'a, D: Domain<Operator = Favourite>>(
    domain: &'a D,
    operators: &'a [(String, Favourite)],
    complacency: Option<ComplacencyOn<'a, Favourite>>,
    threads: usize,
    arms: Vec<Arm>,
) -> Result<Vec<MissionResult>, PlanError> {
    let plan = MissionPlan {
        name: "toy".into(),
        domain,
        operators,
        missions: 12,
        commands: 300,
        changes: Changes {
            every: 80.0,
            takeover: 0.5,
        },
        contexts: None,
        complacency,
        adapter: AdapterConfig::default(),
        arms,
        feedback: None,
        truth_runs: 50,
        limit: LimitSettings::default(),
        competence: None,
        offer_safer: false,
        change_detector: None,
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run_missions(&[plan], 7, &|_| {}))
}

#[test]
fn missions_are_paired_across_arms_and_independent_of_the_thread_count() {
    let (domain, operators) = (toy(), operators());
    let one = run(&domain, &operators, None, 1);
    assert_eq!(one, run(&domain, &operators, None, 2));
    let [result] = one.as_slice() else {
        panic!("one plan")
    };
    assert!(!result.complacency);
    assert_eq!(result.arms.len(), 2);
    // Every arm meets the same changes at the same commands.
    let schedule = |a: usize| -> Vec<Vec<(u32, ChangeKind)>> {
        result.arms[a]
            .missions
            .iter()
            .map(|m| m.changes.iter().map(|c| (c.at, c.kind)).collect())
            .collect()
    };
    assert_eq!(schedule(0), schedule(1));
    assert!(schedule(0).iter().map(Vec::len).sum::<usize>() > 12);
    // The oracle meets the same missions and adapts to every change that needs it.
    let oracle: Vec<Vec<(u32, ChangeKind)>> = result
        .oracle
        .iter()
        .map(|m| m.changes.iter().map(|c| (c.at, c.kind)).collect())
        .collect();
    assert_eq!(oracle, schedule(0));
    for arm in &result.arms {
        assert_eq!(arm.missions.len(), 12);
        assert_eq!((arm.traced.every, arm.traced.steps.len()), (1, 300));
        for m in &arm.missions {
            // Attentive operators overlook nothing and never become complacent.
            assert_eq!((m.overlooked, m.onsets.len()), (0, 0));
            assert!(m.false_alarms <= m.readaptations);
            for (k, c) in m.changes.iter().enumerate() {
                assert!(c.trusted_again.is_none_or(|t| t >= 1));
                // A behavior given up before the next change, with no more untrustworthy
                // commands than the change had.
                let next = m.changes.get(k + 1).map_or(300, |n| n.at);
                if let Some(n) = c.noticed {
                    assert!(c.at + n.after <= next && n.untrustworthy <= c.untrustworthy);
                }
            }
        }
        // The two favourites differ: most changes need an adaptation, and the robot
        // adapts to some of them before the next change.
        let s = MissionSummary::of(arm);
        assert!(s.needed * 2 > s.changes && s.adapted > 0, "{s:?}");
    }
    // The oracle knows each favourite: it tries it first, so it needs fewer untrustworthy
    // commands per change than any arm, and the report gives each arm's multiple of it.
    let oracle = OracleSummary::of(&result.oracle);
    let o = oracle.figures.untrustworthy_per_change.unwrap().mean;
    // Told of every change, it gives up a behavior the new operator does not trust at
    // once (here keeping one never pays: it fails four times in five, and the oracle knows
    // the favourite); an arm notices only through its estimate, after untrustworthy
    // commands.
    for c in result.oracle.iter().flat_map(|m| &m.changes) {
        if c.needed {
            assert_eq!(c.noticed.map(|n| (n.after, n.untrustworthy)), Some((0, 0)));
        }
    }
    for arm in &result.arms {
        let n = Noticing::of(arm.missions.iter().flat_map(|m| &m.changes));
        assert!(n.noticed > 0 && n.before.mean > 0.0, "{n:?}");
    }
    for (a, arm) in result.arms.iter().enumerate() {
        let s = MissionSummary::of(arm);
        assert!(
            s.untrustworthy_per_change.unwrap().mean > o,
            "{s:?} {oracle:?}"
        );
        // Its multiple is the ratio of the means, inside its bootstrap interval.
        let m = oracle_multiple(result, 0, a, OracleFigure::UntrustworthyPerChange).unwrap();
        let ratio = s.untrustworthy_per_change.unwrap().mean / o;
        assert!((m.ratio - ratio).abs() < 1e-9 && m.low <= m.ratio && m.ratio <= m.high);
        assert!(m.ratio > 1.0, "{m:?}");
    }
    let md = missions_markdown(&one);
    assert!(
        md.contains("| oracle | ") && md.contains("× oracle"),
        "{md}"
    );
    assert!(md.contains("noticing then searching"), "{md}");
    let json = missions_json(&one);
    assert_eq!(json[0]["oracle"]["missions"], 12);
    assert_eq!(json[0]["noticing"][2]["agent"], "oracle");
    assert!(
        json[0]["arms"][0]["untrustworthy_per_change_x_oracle"]
            .as_f64()
            .unwrap()
            > 1.0
    );
    assert!(json[0]["arms"][0]["untrustworthy_per_change_x_oracle_ci95"].is_array());
}

#[test]
fn complacent_operators_overlook_bumps_and_answered_alerts_are_paired() {
    let (domain, operators) = (toy(), operators());
    let complacency = ComplacencyOn::attentive(
        Complacency {
            memory: 20.0,
            floor: 0.3,
        },
        &domain,
    );
    let results = run(&domain, &operators, Some(complacency), 2);
    let result = &results[0];
    assert!(result.complacency);
    // Each arm twice: alerts ignored, then answered, on the same missions.
    let names: Vec<(&str, bool)> = result
        .arms
        .iter()
        .map(|a| (a.arm.as_str(), a.answers_alerts))
        .collect();
    assert_eq!(
        names,
        [
            ("case-based", false),
            ("case-based", true),
            ("uniform", false),
            ("uniform", true)
        ]
    );
    let ignored = &result.arms[0];
    let onsets: usize = ignored.missions.iter().map(|m| m.onsets.len()).sum();
    let overlooked: u32 = ignored.missions.iter().map(|m| m.overlooked).sum();
    assert!(onsets > 0 && overlooked > 0);
    // Until the first alert the two runs of an arm are the same mission command for
    // command: the first mission's changes match.
    assert_eq!(
        ignored.missions[0].changes.first().map(|c| c.at),
        result.arms[1].missions[0].changes.first().map(|c| c.at)
    );
    assert_eq!(harm_comparisons(result).len(), 2);
}

/// A mission's record without saying how it started: what the robot went through.
fn course(m: &MissionRecord) -> MissionRecord {
    MissionRecord {
        learned_start: None,
        ..m.clone()
    }
}

#[test]
fn a_learned_start_arm_starts_its_missions_from_the_memory_s_guess() {
    let (domain, operators) = (toy(), operators());
    let arm = |name: &str| Arm::builtin(name, RetrieverKind::Linear).unwrap();
    // From an empty memory: the first mission starts from its random behavior, and once
    // the memory holds a case every mission starts from its guess.
    let results = run_arms(
        &domain,
        &operators,
        None,
        2,
        vec![arm("case-based"), arm("case-based+learned-start")],
    );
    let [random, learned] = results[0].arms.as_slice() else {
        panic!("two arms")
    };
    assert!(random.missions.iter().all(|m| m.learned_start.is_none()));
    assert_eq!(learned.missions[0].learned_start, None);
    let first_guessed = learned
        .missions
        .iter()
        .position(|m| m.learned_start.is_some())
        .expect("the memory retains a case during the missions");
    assert!(
        learned.missions[first_guessed..]
            .iter()
            .all(|m| m.learned_start.is_some()),
        "a memory never forgets its cases"
    );
    // The first mission is the same (the same random behavior, the same streams); the
    // later ones, started elsewhere, are not.
    assert_eq!(course(&random.missions[0]), course(&learned.missions[0]));
    let courses = |missions: &[MissionRecord]| missions.iter().map(course).collect::<Vec<_>>();
    assert_ne!(courses(&random.missions), courses(&learned.missions));

    // From a memory of one case, trusting the low operator's favourite after rejecting
    // (3, 3): every mission of the learned arm starts from the memory's guess, the first
    // from that case's behavior.
    let mut cases = TrustCaseBase::new();
    cases.push(Case {
        problem: vec![Evaluated {
            behavior: Behavior::new(&[3, 3]),
            time: 5.0,
        }]
        .into(),
        solution: Behavior::new(&[1, 1]),
    });
    let guess = first_guess(&cases, domain.space(), 0.95, &Default::default())
        .unwrap()
        .behavior;
    assert_eq!(guess, Behavior::new(&[1, 1]));
    let from = |name: &str| arm(name).with_starting_cases(cases.clone());
    let results = run_arms(
        &domain,
        &operators,
        None,
        2,
        vec![from("case-based"), from("case-based+learned-start")],
    );
    let [random, learned] = results[0].arms.as_slice() else {
        panic!("two arms")
    };
    assert!(random.missions.iter().all(|m| m.learned_start.is_none()));
    assert_eq!(learned.missions[0].learned_start, Some(guess));
    assert!(learned.missions.iter().all(|m| m.learned_start.is_some()));
    assert_ne!(courses(&random.missions), courses(&learned.missions));
}

#[test]
fn complacency_is_refused_on_a_domain_that_does_not_model_attention() {
    // The toy domain without its capabilities: a plan written in Rust could not hold it
    // as `Attentive` (the compiler refuses), and a plan read from a file asks it.
    let (domain, operators) = (Bare(toy()), operators());
    let err = check_attention(&domain).err().unwrap().to_string();
    assert!(
        err.starts_with("domain `toy` does not model its operators' attention")
            && err.contains("does not implement `Attentive`"),
        "{err}"
    );
    // Attentive operators need no attention model: the same missions as the toy's.
    let attentive = run(&domain, &operators, None, 1);
    assert_eq!(attentive, run(&toy(), &operators, None, 1));
}

//! What `serve` serves: a catalog's scenario or a RON domain file, and optionally an arm's
//! strategy; shared by the command line (`serve`, `cases import`) and the Python package's
//! ask/tell adapter (`python/`), so both accept the same names and give the same errors.

use crate::catalog::Catalog;
use crate::suite::arm_named;
use cbr_core::Behavior;
use lab::Domain;
use lab::{ArmName, Initial, NameOptions, PREFERS_COMPETENT, check_self_judging};
use service::DomainDefinition;
use std::sync::Arc;
use trust::{AdapterConfig, CompetenceStandard, Predictor};

/// Who named the options an error speaks of: the command line (`--arm`, `--competence`)
/// or the Python `Adapter` (`arm=`, `competence=`), so each reads its own words.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Spelling {
    /// `serve`'s flags.
    #[default]
    CommandLine,
    /// The Python `Adapter`'s keyword arguments.
    Python,
}

impl Spelling {
    /// The command line's `flag` or Python's `argument`, as this spelling writes it.
    pub fn of(self, flag: &'static str, argument: &'static str) -> &'static str {
        match self {
            Self::CommandLine => flag,
            Self::Python => argument,
        }
    }
}

/// The domain `name` names: a scenario of the catalog (its space, causes, observations
/// and hints, with the paper's adapter defaults) or a RON domain file.
pub fn served_domain<C: Catalog>(
    catalog: &C,
    name: &str,
) -> Result<DomainDefinition, service::DomainError> {
    DomainDefinition::resolve(name, &catalog.scenarios(), |scenario| {
        catalog.domain(scenario).map(|d| {
            DomainDefinition::new(
                scenario,
                d.space().clone(),
                d.causes().to_vec(),
                AdapterConfig::default(),
            )
            .with_observations(d.observations().to_vec())
            .with_contexts(d.contexts().clone())
            .with_statements(d.statements().to_vec())
            .with_hints(d.hints().to_vec())
            .expect("a built-in domain's hints name its own observations and causes")
        })
    })
}

/// The name `--arm` (Python's `arm=`) takes for the domain's own adapter config (its
/// `search`, `reuse_cases` and retriever) instead of an arm's.
pub const DOMAIN_CONFIG: &str = "domain";

/// `domain` served with the strategy of the arm `name` (the catalog's own arms, then the
/// built-in ones): its searcher, its retriever and whether it reuses cases; served as its
/// adapter config says when `name` is [`DOMAIN_CONFIG`]. An arm that starts from the case
/// memory's guess is refused: the controller's `begin` chooses. Errors name the option as
/// `spelling` writes it.
pub fn serving_arm<C: Catalog>(
    catalog: &C,
    mut domain: DomainDefinition,
    name: &str,
    spelling: Spelling,
) -> anyhow::Result<DomainDefinition> {
    if name == DOMAIN_CONFIG {
        return Ok(domain);
    }
    let option = spelling.of("--arm", "arm");
    // The options `serve` refuses are looked for first, in the name as it was evidently
    // meant (however it orders or repeats its suffixes), so that the name it suggests is
    // one it serves.
    let (read, misread) = match ArmName::parse(name) {
        Ok(read) => (read, None),
        Err(error) => (error.meant.clone(), Some(error)),
    };
    let options = read.options();
    let refused = [
        (
            options.context_blind,
            "is blind to the robot's context, which a controller tells `serve` (`begin` with a context, a `context` request): to serve a robot blind to it, send none",
        ),
        (
            options.ignores_statements,
            "ignores what operators state up front, which a controller tells `serve` (`begin`'s `preferences`): to serve a robot that hears none, send none",
        ),
        (
            options.initial == Initial::Learned,
            "starts each episode from the case memory's guess, which `serve` does not choose: a controller's `begin` names the first behavior (or the server draws one)",
        ),
    ];
    if let Some((_, why)) = refused.iter().find(|(on, _)| *on) {
        let served = read.with_options(NameOptions {
            prefers_competent: options.prefers_competent,
            ..NameOptions::default()
        });
        anyhow::bail!("{option}: `{name}` {why}; serve `{served}`");
    }
    if let Some(error) = misread {
        anyhow::bail!("{option}: {error}");
    }
    let arm = arm_named(catalog, &read, domain.adapter.retriever)
        .map_err(|reason| anyhow::anyhow!("{option}: {reason}"))?;
    debug_assert!(
        !arm.is_context_blind() && !arm.ignores_statements() && arm.initial() == Initial::Random
    );
    domain.adapter.reuse_cases = arm.reuses_cases();
    let passes = arm.competent_passes();
    let (searcher, retriever) = (arm.clone(), arm);
    Ok(domain
        .preferring_competent(passes)
        .with_searcher(move |space| searcher.build_searcher(space))
        .with_retriever(move |measure| retriever.build_retriever(measure)))
}

/// Refuses a served `domain` that prefers competent behaviors (`--arm NAME+competent`)
/// while its robot judges nothing: a mission session with a competence standard is where
/// the preference acts, so anywhere else it would be accepted and do nothing.
pub fn check_preference(domain: &DomainDefinition, spelling: Spelling) -> anyhow::Result<()> {
    if domain.competent_passes() > 0 && !(domain.mission() && domain.judges_competence()) {
        anyhow::bail!(
            "{}: an arm NAME{PREFERS_COMPETENT} prefers behaviors the robot judges competent, which it judges only in mission mode with a standard: {}",
            spelling.of("--arm", "arm"),
            spelling.of(
                "add --mission --competence AT_MOST",
                "pass mission=True, competence=AT_MOST"
            )
        );
    }
    Ok(())
}

/// `domain` whose robot judges its own competence in mission mode, held to at most
/// `at_most` per command in every part (`serve --competence`, the Python `Adapter`'s
/// `competence`): the parts and models of the catalog's scenario of the same name. A
/// domain file declares neither, and is refused, as is a scenario that declares no part.
/// Errors name the option as `spelling` writes it.
pub fn judging_competence<C: Catalog>(
    catalog: &C,
    domain: DomainDefinition,
    at_most: f64,
    spelling: Spelling,
) -> anyhow::Result<DomainDefinition> {
    let option = spelling.of("--competence", "competence");
    let Some(robot) = catalog.domain(&domain.name) else {
        anyhow::bail!(
            "{option}: `{}` is not a scenario of {}; only a scenario's robot has competence parts and models to judge itself by",
            domain.name,
            catalog.tool().name
        );
    };
    let standard =
        CompetenceStandard::uniform(at_most).map_err(|e| anyhow::anyhow!("{option}: {e}"))?;
    let parts = check_self_judging(&robot)
        .map_err(|e| anyhow::anyhow!("{option}: {e}"))?
        .competence_parts()
        .to_vec();
    let predict: Predictor<'static> = Arc::new(move |behavior: &Behavior| {
        let judging = robot.self_judging().expect("asked above");
        judging.predict_competence(behavior)
    });
    domain
        .judging_competence(parts, predict, standard)
        .map_err(|e| anyhow::anyhow!("{option}: {e}"))
}

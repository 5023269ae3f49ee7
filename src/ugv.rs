//! The built-in catalog: the paper's movement and patrol scenarios over the UGV world
//! (`domains`), with the paper's operators, the operator family and prior, the patrol
//! weight reading and the paper's seven
//! experiments as the embedded suite. The shipped `trustcbr` binary is
//! [`crate::cli::main`] over this catalog.

use crate::catalog::{Catalog, CatalogError, Family, OperatorFile, Reading, Readings, ToolInfo};
use cbr_core::Behavior;
use domains::{OperatorModel, Scenario, UgvDomain, builtin_operators, prior};
use lab::Instance;
use std::path::Path;

/// The name of the reading of the patrol operators' weights (docs/model.md#open-readings).
pub const PATROL_WEIGHTS: &str = "patrol_weights";

/// The patrol weights as the operator files write them: 1/3 for every outcome, 1 for a
/// detonation (weights stay in `[0, 1]`).
pub const AS_WRITTEN: &str = "as_written";

/// Every patrol weight times 3: 1 for every outcome, 3 for a detonation, with the same
/// thresholds (each command moves the estimate three times as far).
pub const THREE_AND_ONE: &str = "three_and_one";

/// The UGV scenarios (`movement`, `patrol`).
#[derive(Clone, Copy, Debug, Default)]
pub struct UgvCatalog;

impl UgvCatalog {
    /// `operator` as `readings` read it: patrol weights tripled under `three_and_one`.
    fn read(scenario: Scenario, mut operator: OperatorModel, readings: &Readings) -> OperatorModel {
        let tripled = readings.get(PATROL_WEIGHTS).map(String::as_str) == Some(THREE_AND_ONE);
        if scenario == Scenario::Patrol && tripled {
            operator.weights = operator.weights.scaled(3.0);
        }
        operator
    }
}

impl Catalog for UgvCatalog {
    type Domain = UgvDomain;

    fn tool(&self) -> ToolInfo {
        crate::tool_info!()
    }

    fn scenarios(&self) -> Vec<String> {
        Scenario::ALL
            .iter()
            .map(|s| s.as_str().to_owned())
            .collect()
    }

    fn domain(&self, scenario: &str) -> Option<UgvDomain> {
        scenario.parse().ok().map(UgvDomain::new)
    }

    fn operators(&self, scenario: &str, readings: &Readings) -> Vec<(String, OperatorModel)> {
        let Ok(scenario) = scenario.parse::<Scenario>() else {
            return Vec::new();
        };
        builtin_operators(scenario)
            .into_iter()
            .map(|o| (o.name.clone(), Self::read(scenario, o, readings)))
            .collect()
    }

    fn load_operator(
        &self,
        scenario: &str,
        path: &Path,
        readings: &Readings,
    ) -> Result<(String, OperatorModel), CatalogError> {
        let scenario: Scenario = scenario.parse().map_err(|e| CatalogError {
            path: Some(path.to_owned()),
            reason: Box::new(e),
        })?;
        // The operator's own errors name the file already.
        let operator = OperatorModel::load(path, scenario.causes()).map_err(|e| CatalogError {
            path: None,
            reason: Box::new(e),
        })?;
        Ok((
            operator.name.clone(),
            Self::read(scenario, operator, readings),
        ))
    }

    fn family(
        &self,
        scenario: &str,
        family: &Family,
        readings: &Readings,
    ) -> Result<Vec<(String, OperatorModel)>, CatalogError> {
        let scenario: Scenario = scenario.parse().map_err(|e| CatalogError {
            path: None,
            reason: Box::new(e),
        })?;
        Ok(
            domains::population::family(scenario, family.conflict, family.size, family.seed)
                .into_iter()
                .map(|o| (o.name.clone(), Self::read(scenario, o, readings)))
                .collect(),
        )
    }

    fn prior(
        &self,
        scenario: &str,
        instance: &Instance,
        screened: bool,
    ) -> Result<Vec<OperatorFile>, CatalogError> {
        let failed = |e: Box<dyn std::error::Error + Send + Sync>| CatalogError {
            path: None,
            reason: e,
        };
        let scenario: Scenario = scenario.parse().map_err(|e| failed(Box::new(e)))?;
        let members = prior::population(&UgvDomain::new(scenario), instance, screened)
            .map_err(|e| failed(Box::new(e)))?;
        Ok(members
            .iter()
            .map(|member| OperatorFile {
                name: member.operator.name.clone(),
                text: prior::operator_file(scenario, instance, members.len(), member, screened),
            })
            .collect())
    }

    fn readings(&self) -> Vec<Reading> {
        vec![Reading {
            name: PATROL_WEIGHTS.to_owned(),
            values: vec![AS_WRITTEN.to_owned(), THREE_AND_ONE.to_owned()],
            about: "how the patrol weights are scaled (docs/model.md#open-readings)".to_owned(),
        }]
    }

    fn default_suite(&self) -> &str {
        domains::PAPER_CONFIG
    }

    #[cfg(feature = "console")]
    fn stage(&self, scenario: &str) -> Option<std::sync::Arc<dyn console::Stage>> {
        let scenario = scenario.parse::<Scenario>().ok()?;
        Some(std::sync::Arc::new(crate::console_stage::UgvStage::new(
            scenario,
        )))
    }

    fn render(
        &self,
        domain: &UgvDomain,
        behavior: &Behavior,
        operator: &OperatorModel,
        seed: u64,
    ) -> Option<String> {
        Some(domains::render_run(domain, behavior, operator, seed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalog::find_operator;

    #[test]
    fn operators_are_found_by_name_or_file_and_unknown_names_list_the_scenario_s() {
        let readings = Readings::new();
        let (name, op) =
            find_operator(&UgvCatalog, "patrol", "detection-focused", &readings).unwrap();
        assert_eq!((name.as_str(), op.p_deadline), ("detection-focused", 0.05));
        let err = find_operator(&UgvCatalog, "movement", "detection-focused", &readings)
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "`detection-focused` is neither an operator of movement (speed-focused, safety-focused, balanced) nor an operator file"
        );
    }
}

//! `WarehouseCatalog`: the picking scenario offered to the command-line tool
//! (`trustcbr::cli::main`), with its operators and the suite `reproduce` runs.

use crate::domain::{PICKING, WarehouseDomain};
use crate::operator::{WarehouseOperator, builtin_operators};
use std::path::Path;
use trustcbr::catalog::UnknownScenario;
use trustcbr::{Catalog, CatalogError, Readings, ToolInfo};

/// The suite `reproduce` runs and `config` prints (`experiments/suite.ron`).
pub const SUITE: &str = include_str!("../experiments/suite.ron");

/// The warehouse's one scenario, `picking`.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarehouseCatalog;

impl Catalog for WarehouseCatalog {
    type Domain = WarehouseDomain;

    fn tool(&self) -> ToolInfo {
        ToolInfo {
            name: env!("CARGO_PKG_NAME").to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: None,
            about: env!("CARGO_PKG_DESCRIPTION").to_owned(),
        }
    }

    fn scenarios(&self) -> Vec<String> {
        vec![PICKING.to_owned()]
    }

    fn domain(&self, scenario: &str) -> Option<WarehouseDomain> {
        (scenario == PICKING).then(WarehouseDomain::new)
    }

    fn operators(&self, scenario: &str, _: &Readings) -> Vec<(String, WarehouseOperator)> {
        if scenario != PICKING {
            return Vec::new();
        }
        builtin_operators()
            .into_iter()
            .map(|o| (o.name.clone(), o))
            .collect()
    }

    fn load_operator(
        &self,
        scenario: &str,
        path: &Path,
        _: &Readings,
    ) -> Result<(String, WarehouseOperator), CatalogError> {
        if scenario != PICKING {
            return Err(CatalogError {
                path: Some(path.to_owned()),
                reason: Box::new(UnknownScenario {
                    name: scenario.to_owned(),
                    known: PICKING.to_owned(),
                }),
            });
        }
        // The operator's errors name the file already.
        let operator = WarehouseOperator::load(path).map_err(|e| CatalogError {
            path: None,
            reason: Box::new(e),
        })?;
        Ok((operator.name.clone(), operator))
    }

    fn completion_weight(&self, operator: &WarehouseOperator) -> Option<f64> {
        Some(operator.weights.completed)
    }

    fn default_suite(&self) -> &str {
        SUITE
    }
}

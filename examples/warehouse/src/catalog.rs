//! `WarehouseCatalog`: the picking scenario offered to the command-line tool
//! (`trustcbr::cli::main`), with its operators and the suite `reproduce` runs.

use crate::domain::{PICKING, WarehouseDomain};
use crate::operator::{WarehouseOperator, builtin_operators};
use std::path::Path;
use trustcbr::{Catalog, CatalogError, Readings, ToolInfo};

/// The suite `reproduce` runs and `config` prints (`experiments/suite.ron`).
pub const SUITE: &str = include_str!("../experiments/suite.ron");

/// The warehouse's one scenario, `picking`.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarehouseCatalog;

impl Catalog for WarehouseCatalog {
    type Domain = WarehouseDomain;

    fn tool(&self) -> ToolInfo {
        trustcbr::tool_info!()
    }

    fn scenarios(&self) -> Vec<String> {
        vec![PICKING.to_owned()]
    }

    fn domain(&self, scenario: &str) -> Option<WarehouseDomain> {
        (scenario == PICKING).then(WarehouseDomain::new)
    }

    // The tool asks for operators only of a scenario `domain` knows: `picking`.
    fn operators(&self, _: &str, _: &Readings) -> Vec<(String, WarehouseOperator)> {
        builtin_operators()
            .into_iter()
            .map(|o| (o.name.clone(), o))
            .collect()
    }

    fn load_operator(
        &self,
        _: &str,
        path: &Path,
        _: &Readings,
    ) -> Result<(String, WarehouseOperator), CatalogError> {
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

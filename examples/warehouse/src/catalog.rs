//! `WarehouseCatalog`: the picking scenario offered to the command-line tool
//! (`trustcbr::cli::main`), with its operators, its family of operators, its own arms and
//! the suite `reproduce` runs.

use crate::domain::{PICKING, WarehouseDomain};
use crate::operator::{WarehouseOperator, builtin_operators};
use crate::population;
use crate::searcher::{TROUBLESHOOTER, Troubleshooter};
use std::path::Path;
use std::sync::Arc;
use trustcbr::cbr_core::BehaviorSpace;
use trustcbr::lab::Arm;
use trustcbr::lab::contract::operator_file::{named, with_name};
use trustcbr::trust::RetrieverKind;
use trustcbr::{Catalog, CatalogError, Family, Readings, ToolInfo};

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
        named(builtin_operators())
    }

    fn load_operator(
        &self,
        _: &str,
        path: &Path,
        _: &Readings,
    ) -> Result<(String, WarehouseOperator), CatalogError> {
        // The operator's errors name the file already.
        Ok(with_name(WarehouseOperator::load(path)?))
    }

    // Members of the throughput-against-care family (`population`).
    fn family(
        &self,
        _: &str,
        family: &Family,
        _: &Readings,
    ) -> Result<Vec<(String, WarehouseOperator)>, CatalogError> {
        Ok(named(population::family(
            family.conflict,
            family.size,
            family.seed,
        )))
    }

    // The troubleshooter alone, and as the fallback of case reuse.
    fn arms(&self, retriever: RetrieverKind) -> Vec<Arm> {
        let troubleshooter = |_: &Arc<BehaviorSpace>| Box::new(Troubleshooter::new()) as _;
        Arm::search_and_case_based(TROUBLESHOOTER, troubleshooter, retriever).into()
    }

    fn default_suite(&self) -> &str {
        SUITE
    }
}

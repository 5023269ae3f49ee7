//! Case bases saved at the end of a run (`--save-cases`) and read back as an arm's
//! starting cases (`--cases`), one RON file per experiment and arm.

use super::{SuiteConfig, SuiteError, SuiteResults};
use cbr_core::BehaviorSpace;
use files::FileError;
use lab::report::file_stems;
use service::store::{self, Identity, Location, ron_file};
use std::path::{Path, PathBuf};
use trust::TrustCaseBase;

/// Case bases saved by an earlier run ([`save_case_bases`]): `DIR/EXPERIMENT/ARM.ron`, the
/// experiment's name made a file name ([`file_stems`]). An arm that reads cases (it reuses
/// them, or starts from their guess: [`lab::Arm::reads_cases`]) starts from its file when there
/// is one, and from an empty case base otherwise.
#[derive(Clone, Debug)]
pub struct StartingCases {
    /// The folder.
    pub dir: PathBuf,
}

impl StartingCases {
    /// The saved case base of `arm` in the experiment `stem` of `scenario`, if there is
    /// one: refused when it records another behavior space or a case does not fit `space`.
    /// A file that records no space (saved by an earlier version) is read as `space`'s.
    pub(super) fn load(
        &self,
        stem: &str,
        arm: &str,
        scenario: &str,
        space: &BehaviorSpace,
    ) -> Result<Option<TrustCaseBase>, SuiteError> {
        let path = self.dir.join(stem).join(format!("{arm}.ron"));
        if !path.exists() {
            return Ok(None);
        }
        let identity = Identity {
            domain: scenario.to_owned(),
            space: space.clone(),
        };
        let mut store = store::open(&Location::Ron(path), &identity)?;
        let location = store.location();
        let mut cases = TrustCaseBase::new();
        store.read_after(None, &mut |stored| {
            store::check_case(&location, &stored, space)?;
            cases.push(stored.case);
            Ok(())
        })?;
        Ok(Some(cases))
    }
}

/// Saves the case base each case-reading arm ([`lab::Arm::reads_cases`]) ended every
/// experiment with, as
/// `DIR/EXPERIMENT/ARM.ron` (what [`StartingCases`] reads), each file naming its scenario
/// and behavior space as `trustcbr cases export` writes them, so that `cases info`,
/// `cases import` and `serve` read it as it is. Returns the files written.
pub fn save_case_bases(
    dir: &Path,
    config: &SuiteConfig,
    results: &SuiteResults,
) -> Result<Vec<PathBuf>, SuiteError> {
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let mut written = Vec::new();
    let experiments = results.results.iter().zip(&results.spaces);
    for (((result, space), stem), spec) in experiments.zip(&stems).zip(&config.experiments) {
        let folder = dir.join(stem);
        let identity = Identity {
            domain: spec.scenario.clone(),
            space: (**space).clone(),
        };
        for arm in &result.arms {
            let Some(cases) = &arm.final_cases else {
                continue;
            };
            std::fs::create_dir_all(&folder).map_err(|reason| FileError {
                path: folder.clone(),
                reason,
            })?;
            let path = folder.join(format!("{}.ron", arm.name));
            ron_file::save(&path, &identity, cases.cases())?;
            written.push(path);
        }
    }
    Ok(written)
}

//! Case bases saved at the end of a run (`--save-cases`) and read back as an arm's
//! starting cases (`--cases`), one RON file per experiment and arm, `DIR/EXPERIMENT/ARM.ron`:
//! the experiment's name made a file name ([`file_stems`]) and the arm's name checked as
//! one ([`file_in`]), by the writer and the reader alike, so no name leads outside `DIR`.

use super::{SuiteConfig, SuiteError, SuiteResults, arm_named};
use crate::catalog::Catalog;
use cbr_core::{BehaviorSpace, ContextSpace};
use files::FileError;
use files::name::file_in;
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

/// The file of `arm`'s case base in the experiment `stem` under `dir`.
pub(crate) fn saved_file(dir: &Path, stem: &str, arm: &str) -> Result<PathBuf, SuiteError> {
    Ok(file_in(&dir.join(stem), "arm", arm, "ron")?)
}

impl StartingCases {
    /// The saved case base of `arm` in the experiment `stem` of `scenario`, if there is
    /// one: refused when its path is there but is no regular file (a folder, a FIFO, a
    /// symlink to nothing or a loop of them), when it records another behavior space, or
    /// a case does not fit `space`. A file that records no space (saved by an earlier
    /// version) is read as `space`'s.
    pub(super) fn load(
        &self,
        stem: &str,
        arm: &str,
        scenario: &str,
        space: &BehaviorSpace,
        contexts: &ContextSpace,
    ) -> Result<Option<TrustCaseBase>, SuiteError> {
        let path = saved_file(&self.dir, stem, arm)?;
        if !store::check_file(&path)? {
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
            store::check_case(&location, &stored, space, contexts)?;
            cases.push(stored.case);
            Ok(())
        })?;
        Ok(Some(cases))
    }
}

/// The files [`save_case_bases`] will write for `config` in `dir`: one per experiment and
/// arm that reads cases.
fn save_targets<C: Catalog>(
    catalog: &C,
    dir: &Path,
    config: &SuiteConfig,
) -> Result<Vec<PathBuf>, SuiteError> {
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let mut targets = Vec::new();
    for name in &config.arms {
        let arm = arm_named(catalog, name, config.adapter.retriever)
            .map_err(|e| super::invalid(dir, "arms".into(), e))?;
        if arm.reads_cases() {
            for stem in &stems {
                targets.push(saved_file(dir, stem, name.as_str())?);
            }
        }
    }
    Ok(targets)
}

/// Checks, before a run, that [`save_case_bases`] may write every file it will in `dir`:
/// each is absent, or a case base saved earlier (a RON case file recording its behavior
/// space, as `--save-cases` and `trustcbr cases export` write them), never any other file
/// (a text, an SQLite case base), which is left as it is.
pub fn check_save_targets<C: Catalog>(
    catalog: &C,
    dir: &Path,
    config: &SuiteConfig,
) -> Result<(), SuiteError> {
    for path in save_targets(catalog, dir, config)? {
        check_save_target(&path)?;
    }
    Ok(())
}

/// Refuses `path` as a place to save a case base unless it is absent (its folder may be
/// missing too) or an earlier one.
fn check_save_target(path: &Path) -> Result<(), SuiteError> {
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(());
    }
    if store::check_file(path)? {
        ron_file::check_earlier_export(path).map_err(|reason| SuiteError::SaveOver {
            path: path.to_owned(),
            reason,
        })?;
    }
    Ok(())
}

/// Saves the case base each case-reading arm ([`lab::Arm::reads_cases`]) ended every
/// experiment with, as
/// `DIR/EXPERIMENT/ARM.ron` (what [`StartingCases`] reads), each file naming its scenario
/// and behavior space as `trustcbr cases export` writes them, so that `cases info`,
/// `cases import` and `serve` read it as it is. A file there already is replaced only if
/// it is a case base saved earlier ([`check_save_targets`], checked again as it is
/// written). Returns the files written.
pub fn save_case_bases(
    dir: &Path,
    config: &SuiteConfig,
    results: &SuiteResults,
) -> Result<Vec<PathBuf>, SuiteError> {
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let mut written = Vec::new();
    let experiments = results.results.iter().zip(&results.spaces);
    for (((result, space), stem), spec) in experiments.zip(&stems).zip(&config.experiments) {
        let identity = Identity {
            domain: spec.scenario.clone(),
            space: (**space).clone(),
        };
        for arm in &result.arms {
            let Some(cases) = &arm.final_cases else {
                continue;
            };
            let path = saved_file(dir, stem, arm.name.as_str())?;
            let folder = path.parent().expect("a saved case base is in a folder");
            std::fs::create_dir_all(folder).map_err(|reason| FileError {
                path: folder.to_owned(),
                reason,
            })?;
            check_save_target(&path)?;
            ron_file::save(&path, &identity, cases.cases())?;
            written.push(path);
        }
    }
    Ok(written)
}

//! `trustcbr cases export | import | info`: moving case bases between stores and looking
//! at one.
//!
//! RON is the human-readable exchange format: `export` writes a case base (with its domain
//! and behavior space) to a RON file, `import` appends the cases of a RON file to a
//! database (created when absent) after checking every case against the domain's space,
//! and `info` describes a case base. None of them modifies its source.

use crate::domain::DomainDefinition;
use crate::store::{self, Identity, Location, StoreError, StoreId, ron_file, row};
use cbr_core::BehaviorSpace;
use std::collections::HashSet;
use std::fmt;
use std::path::Path;
use trust::TrustCase;

/// What `cases info` shows.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseBaseInfo {
    /// The store.
    pub location: String,
    /// The domain and space recorded.
    pub identity: Identity,
    /// How many cases it holds.
    pub cases: usize,
    /// The smallest and largest case ids, if it holds any.
    pub ids: Option<(StoreId, StoreId)>,
}

impl fmt::Display for CaseBaseInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let space = &self.identity.space;
        writeln!(f, "case base: {}", self.location)?;
        writeln!(f, "domain:    {}", self.identity.domain)?;
        writeln!(f, "space:     {}", describe(space))?;
        write!(f, "cases:     {}", self.cases)?;
        if let Some((first, last)) = self.ids {
            write!(f, " (ids {first} to {last})")?;
        }
        Ok(())
    }
}

fn describe(space: &BehaviorSpace) -> String {
    let components: Vec<String> = space
        .components()
        .iter()
        .zip(space.weights())
        .map(|(c, w)| format!("{} ({} values, weight {w})", c.name, c.len()))
        .collect();
    format!("{} behaviors: {}", space.size(), components.join(", "))
}

/// Describes the case base at `location`.
pub fn info(location: &Location) -> Result<CaseBaseInfo, StoreError> {
    let mut store = store::open_existing(location)?;
    let mut cases = 0;
    let mut ids = None;
    store.read_after(None, &mut |stored| {
        cases += 1;
        let (first, _) = ids.unwrap_or((stored.id, stored.id));
        ids = Some((first, stored.id));
        Ok(())
    })?;
    Ok(CaseBaseInfo {
        location: store.location(),
        identity: store.identity().clone(),
        cases,
        ids,
    })
}

/// Writes the case base at `from` to the RON file `to`; returns how many cases.
///
/// `to` must end in `.ron` and be absent or an earlier export (a RON case file recording
/// its behavior space); it is never the case base itself, however spelled (another path,
/// a symlink or a hard link to the same file). A refused `to` is left as it is, and so is
/// the case base, which is only read.
pub fn export(from: &Location, to: &Path) -> Result<usize, StoreError> {
    check_export_target(from, to)?;
    let mut store = store::open_existing(from)?;
    ron_file::export(store.as_mut(), to)
}

/// Refuses an export path that names the case base being exported or any file but an
/// earlier export.
fn check_export_target(from: &Location, to: &Path) -> Result<(), StoreError> {
    if to.extension().is_none_or(|e| e != "ron") {
        return Err(StoreError::ExportName(to.to_owned()));
    }
    if !store::check_file(to)? {
        return Ok(());
    }
    if let Location::Sqlite(source) | Location::Ron(source) = from
        && same_file(source, to)
    {
        return Err(StoreError::ExportOverSource {
            out: to.to_owned(),
            source_base: from.shown(),
        });
    }
    ron_file::check_earlier_export(to).map_err(|reason| StoreError::ExportOverOther {
        out: to.to_owned(),
        reason,
    })
}

/// Whether `a` and `b` are one file (the same device and inode, after symlinks).
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
        _ => false,
    }
}

/// What an import did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Imported {
    /// How many cases were appended.
    pub cases: usize,
    /// How many of them the case base already held (the same evaluated pairs and
    /// solution): a file imported twice holds its cases twice.
    pub already_held: usize,
}

/// Appends every case of the RON file `from` to the case base at `to` (created when
/// absent), learned in `domain`'s space. A file recording another space, or a case that
/// does not fit the space, is refused and nothing is appended; so are a RON file as the
/// target (RON case files are read-only) and a target holding a case that `serve` would
/// refuse.
pub fn import(
    from: &Path,
    to: &Location,
    domain: &DomainDefinition,
) -> Result<Imported, StoreError> {
    if let Location::Ron(path) = to {
        return Err(StoreError::ImportIntoRon {
            target: path.clone(),
            instead: path.with_extension("db"),
        });
    }
    let identity = Identity {
        domain: domain.name.clone(),
        space: (*domain.space).clone(),
    };
    let source = Location::Ron(from.to_owned());
    let mut reader = store::open(&source, &identity)?;
    let location = reader.location();
    let mut cases: Vec<TrustCase> = Vec::new();
    reader.read_after(None, &mut |stored| {
        store::check_case(&location, &stored, &identity.space, &domain.contexts)?;
        cases.push(stored.case);
        Ok(())
    })?;
    let mut target = store::open(to, &identity)?;
    // The cases already there are read as `serve` and `info` read them: a target they
    // would refuse is refused before anything is appended.
    let location = target.location();
    let mut held = HashSet::new();
    target.read_after(None, &mut |stored| {
        store::check_case(&location, &stored, &identity.space, &domain.contexts)?;
        held.insert(row::encode(&stored.case));
        Ok(())
    })?;
    let already_held = cases
        .iter()
        .filter(|c| held.contains(&row::encode(c)))
        .count();
    Ok(Imported {
        cases: target.append_all(&cases)?,
        already_held,
    })
}

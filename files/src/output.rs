//! Writing output files safely.
//!
//! [`write_no_follow`] replaces a file so that readers see either the old content or all
//! of the new, never through a symbolic link (a target that is one is refused, as is a link
//! planted beside it), keeping the file's mode and owner. [`create_whole`] makes a new
//! file complete or not at all. [`write_file_in`] writes a file in a folder, creating the folder first, and
//! [`ensure_writable_dir`] checks before any work starts that a folder can take files.
//! What makes a folder a *report* folder is not this crate's business (the lab's
//! `folder` module).

use crate::input::{FileError, special_file_kind};
use std::ffi::{OsStr, OsString};
use std::fs::{self, Permissions};
use std::io::{self, Write};
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Why a folder cannot take the files to be written in it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FolderError {
    /// The path exists and is not a folder.
    #[error("{}: exists and is {kind}, not a folder for the report", path.display())]
    NotAFolder {
        /// The path given.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
    },
    /// The path is a symbolic link: nothing is written through one.
    #[error(
        "{}: is a symbolic link; nothing is written through one: give the folder itself, or another",
        path.display()
    )]
    Symlink {
        /// The path given.
        path: PathBuf,
    },
    /// The folder could not be created, listed or written in.
    #[error("{}: cannot {action}: {reason}", path.display())]
    Unwritable {
        /// The folder.
        path: PathBuf,
        /// What could not be done: `create this folder`, `create a file in this folder`,
        /// `list this folder`.
        action: &'static str,
        /// Why (shown in the message, so not chained as a source).
        reason: io::Error,
    },
}

/// Checks, before any work starts, that files can be written in the folder `dir`:
/// creates it if missing, and refuses a symbolic link (what it points to is not the folder
/// named), a path that is not a folder or a folder that cannot be written in (a temporary
/// file is created and removed to find out: permissions, read-only file systems).
pub fn ensure_writable_dir(dir: &Path) -> Result<(), FolderError> {
    if fs::symlink_metadata(dir).is_ok_and(|meta| meta.file_type().is_symlink()) {
        return Err(FolderError::Symlink {
            path: dir.to_owned(),
        });
    }
    let unwritable = |action| {
        move |reason| FolderError::Unwritable {
            path: dir.to_owned(),
            action,
            reason,
        }
    };
    match fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => {
            return Err(FolderError::NotAFolder {
                path: dir.to_owned(),
                kind: special_file_kind(&meta.file_type()).unwrap_or("a regular file"),
            });
        }
        Ok(_) => {}
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            fs::create_dir_all(dir).map_err(unwritable("create this folder"))?;
        }
        Err(e) => return Err(unwritable("create this folder")(e)),
    }
    tempfile::Builder::new()
        .prefix(".trustcbr-probe-")
        .tempfile_in(dir)
        .map_err(|e| unwritable("create a file in this folder")(without_temporary_path(e)))?;
    Ok(())
}

/// Whether `name` is a temporary file of [`write_no_follow`] (`.NAME.tmp-...`), which
/// an interrupted write may leave.
pub fn is_temporary_name(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp-")
}

/// Random characters in a temporary file's name.
const RANDOM_CHARS: usize = 10;

/// Writes `text` atomically as the file `name` in `dir`, creating `dir` and any folder
/// `name` names first, never through a symbolic link ([`write_no_follow`]): neither the
/// file nor a folder `name` names below `dir` may be one. Returns the file's path; an
/// error names the file or folder.
pub fn write_file_in(dir: &Path, name: impl AsRef<Path>, text: &str) -> Result<PathBuf, FileError> {
    let path = dir.join(name);
    let folder = path.parent().unwrap_or(dir);
    fs::create_dir_all(folder).map_err(|reason| FileError {
        path: folder.to_owned(),
        reason,
    })?;
    // Each folder between `dir` and the file: a link there would lead the file elsewhere.
    for between in folder
        .ancestors()
        .take_while(|a| *a != dir && a.starts_with(dir))
    {
        if fs::symlink_metadata(between).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(FileError {
                path: between.to_owned(),
                reason: symlink_refused(),
            });
        }
    }
    write_no_follow(&path, text.as_bytes()).map_err(|reason| FileError {
        path: path.clone(),
        reason,
    })?;
    Ok(path)
}

/// Writes `bytes` to `path` so that readers see either the old content or all of the new,
/// never through a symbolic link.
///
/// The bytes go to a new temporary file beside the target, named `.NAME.tmp-PID-RANDOM`
/// and created exclusively (an existing file or link of that name is never opened), with
/// mode 0600; it is synced, given the target's mode and owner (where permitted), renamed
/// over the target, and the directory is synced so the rename survives a power cut.
///
/// A `path` that is a symbolic link is refused (the link and what it points to stay as
/// they were); the rename that puts the file in place replaces a directory entry and
/// never opens what is there, so even a link planted after the check is replaced, not
/// followed. A target that is a directory, FIFO, socket or device is refused. Temporary
/// files of the same target left by writers that no longer run are removed first.
pub fn write_no_follow(path: &Path, bytes: &[u8]) -> io::Result<()> {
    if fs::symlink_metadata(path).is_ok_and(|meta| meta.file_type().is_symlink()) {
        return Err(symlink_refused());
    }
    replace_entry(path, bytes)
}

/// The error of a write refused because its target is a symbolic link.
fn symlink_refused() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "is a symbolic link; nothing is written through one: remove the link, or write elsewhere",
    )
}

/// Replaces the directory entry `target` (no symbolic link, or one to replace itself)
/// with a file holding `bytes`: the body of [`write_no_follow`].
fn replace_entry(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let target = target.to_owned();
    let existing = match fs::symlink_metadata(&target) {
        // A link planted since the caller looked is replaced, so nothing of it is kept.
        Ok(meta) if meta.file_type().is_symlink() => None,
        Ok(meta) => Some(meta),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
    };
    if let Some(kind) = existing
        .as_ref()
        .and_then(|meta| special_file_kind(&meta.file_type()))
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is {kind}, not a regular file; refusing to write over it"),
        ));
    }
    // A new target gets the usual mode of new files (0666 less the umask).
    let create_mode = if existing.is_some() { 0o600 } else { 0o666 };
    let (dir, mut temp) = temporary_beside(&target, create_mode)?;
    temp.write_all(bytes).map_err(without_temporary_path)?;
    if let Some(meta) = &existing {
        let file = temp.as_file();
        let created = file.metadata()?;
        if (created.uid(), created.gid()) != (meta.uid(), meta.gid()) {
            // Only a privileged writer may give a file away; others keep their own.
            std::os::unix::fs::fchown(file, Some(meta.uid()), Some(meta.gid())).ok();
        }
        file.set_permissions(Permissions::from_mode(meta.mode() & 0o7777))?;
    }
    temp.as_file().sync_all()?;
    temp.persist(&target).map_err(|e| e.error)?;
    // Persist the directory entry; not every platform lets a directory be opened.
    if let Ok(d) = fs::File::open(&dir) {
        d.sync_all().ok();
    }
    Ok(())
}

/// The folder `path` is in: its parent, or `.` for a bare file name.
pub fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A fresh temporary file beside `target` (in its folder, `.NAME.tmp-PID-RANDOM`, created
/// with `mode` less the umask), with that folder, after removing the temporaries that
/// writers of the same name left and no longer run to remove.
fn temporary_beside(target: &Path, mode: u32) -> io::Result<(PathBuf, NamedTempFile)> {
    let name = target
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file path"))?;
    let dir = folder_of(target).to_owned();
    let prefix = temporary_prefix(name);
    remove_stale_temporaries(&dir, &prefix);
    let mut own_prefix = prefix;
    own_prefix.push(format!("{}-", std::process::id()));
    let temp = tempfile::Builder::new()
        .prefix(&own_prefix)
        .rand_bytes(RANDOM_CHARS)
        .permissions(Permissions::from_mode(mode))
        .tempfile_in(&dir)
        .map_err(without_temporary_path)?;
    Ok((dir, temp))
}

/// Creates the file `path` complete or not at all: `fill` makes it at a fresh temporary
/// path beside `path` (an empty file to start from, in the same folder, so the move is
/// atomic), and it is moved into place only if nothing is at `path` yet, never over
/// anything. Returns `true` when this call created it, `false` when another writer did
/// first (its file is kept; this one is dropped). A writer killed meanwhile leaves only a
/// temporary file, which the next writer for the same name removes; a reader never sees a
/// half-made file.
///
/// ```
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("base.txt");
/// let fill = |temp: &std::path::Path| std::fs::write(temp, "complete");
/// assert!(files::output::create_whole(&path, fill)?);
/// // Something is there now: it is kept.
/// assert!(!files::output::create_whole(&path, |temp| std::fs::write(temp, "other"))?);
/// assert_eq!(std::fs::read_to_string(&path)?, "complete");
/// assert_eq!(std::fs::read_dir(dir.path())?.count(), 1);
/// # Ok::<(), std::io::Error>(())
/// ```
pub fn create_whole<E: From<io::Error>>(
    path: &Path,
    fill: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<bool, E> {
    let (dir, temp) = temporary_beside(path, 0o666)?;
    fill(temp.path())?;
    temp.as_file().sync_all()?;
    match temp.persist_noclobber(path) {
        Ok(_) => {
            // Persist the directory entry; not every platform lets a directory be opened.
            if let Ok(d) = fs::File::open(&dir) {
                d.sync_all().ok();
            }
            Ok(true)
        }
        // The temporary file is removed as the error drops it.
        Err(e) if e.error.kind() == io::ErrorKind::AlreadyExists => Ok(false),
        Err(e) => Err(e.error.into()),
    }
}

/// `.NAME.tmp-`: what every temporary file of the target `NAME` starts with.
pub(crate) fn temporary_prefix(name: &OsStr) -> OsString {
    let mut prefix = OsString::from(".");
    prefix.push(name);
    prefix.push(".tmp-");
    prefix
}

/// Removes the temporary files `PREFIX PID[-RANDOM]` in `dir` whose writer `PID` no longer
/// runs (where `/proc` tells), and the temporary folders of that name
/// ([`crate::staged`]). Best effort: a file that cannot be removed stays.
pub(crate) fn remove_stale_temporaries(dir: &Path, prefix: &OsStr) {
    let processes = Path::new("/proc");
    if !processes.join("self").exists() {
        return;
    }
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name
            .as_encoded_bytes()
            .strip_prefix(prefix.as_encoded_bytes())
        else {
            continue;
        };
        let pid = rest.split(|&b| b == b'-').next().unwrap_or_default();
        let is_pid = !pid.is_empty() && pid.iter().all(u8::is_ascii_digit);
        let Ok(file_type) = entry.file_type() else {
            continue;
        };
        let pid = String::from_utf8_lossy(pid);
        if !is_pid || processes.join(pid.as_ref()).exists() {
            continue;
        }
        if file_type.is_dir() {
            // Removes the folder's entries, never what a link in it points to.
            fs::remove_dir_all(entry.path()).ok();
        } else if file_type.is_file() || file_type.is_symlink() {
            fs::remove_file(entry.path()).ok();
        }
    }
}

/// A failed temporary-file creation without the random name the `tempfile` crate appends
/// to its message (`... at path "..."`): the caller names the target instead.
fn without_temporary_path(error: io::Error) -> io::Error {
    let message = error.to_string();
    match message.rfind(" at path ") {
        Some(end) => io::Error::new(error.kind(), &message[..end]),
        None => error,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::os::unix::fs::{FileTypeExt, symlink};

    /// The names in `dir`, sorted (for this crate's tests).
    pub(crate) fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_and_replaces_leaving_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        write_no_follow(&path, b"one").unwrap();
        write_no_follow(&path, b"two").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two");
        assert_eq!(names_in(dir.path()), ["out.txt"]);
    }

    #[test]
    fn a_missing_folder_is_reported_without_the_temporary_name() {
        let err = write_no_follow(Path::new("/nonexistent/dir/out.txt"), b"x").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::NotFound);
        assert_eq!(err.to_string(), "No such file or directory (os error 2)");
    }

    #[test]
    fn a_link_planted_at_a_predictable_temporary_name_is_not_followed() {
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim");
        fs::write(&victim, b"precious").unwrap();
        let path = dir.path().join("cases.ron");
        // The name the writer once used: `.NAME.tmp-PID`.
        let planted = dir
            .path()
            .join(format!(".cases.ron.tmp-{}", std::process::id()));
        symlink(&victim, &planted).unwrap();
        write_no_follow(&path, b"cases").unwrap();
        assert_eq!(fs::read(&victim).unwrap(), b"precious");
        assert_eq!(fs::read(&path).unwrap(), b"cases");
        assert!(fs::symlink_metadata(&path).unwrap().file_type().is_file());
        assert!(fs::symlink_metadata(&planted).unwrap().is_symlink());
    }

    #[test]
    fn a_symlinked_target_is_refused_and_it_and_its_file_stay() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ron");
        fs::write(&real, b"old").unwrap();
        let link = dir.path().join("cases.ron");
        symlink("real.ron", &link).unwrap();
        let err = write_no_follow(&link, b"new").unwrap_err();
        assert!(err.to_string().starts_with("is a symbolic link"), "{err}");
        assert!(fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(fs::read(&real).unwrap(), b"old");
    }

    #[test]
    fn the_mode_of_the_target_is_kept() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        fs::write(&path, b"old").unwrap();
        fs::set_permissions(&path, Permissions::from_mode(0o640)).unwrap();
        write_no_follow(&path, b"new").unwrap();
        assert_eq!(fs::metadata(&path).unwrap().mode() & 0o7777, 0o640);
        fs::set_permissions(&path, Permissions::from_mode(0o604)).unwrap();
        write_no_follow(&path, b"newer").unwrap();
        assert_eq!(fs::metadata(&path).unwrap().mode() & 0o7777, 0o604);
    }

    #[test]
    fn the_owner_of_the_target_is_kept_where_permitted() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        fs::write(&path, b"old").unwrap();
        // Only a privileged process can give the file to someone else; otherwise there is
        // no other owner to keep.
        if std::os::unix::fs::chown(&path, Some(4321), Some(4321)).is_err() {
            return;
        }
        write_no_follow(&path, b"new").unwrap();
        let meta = fs::metadata(&path).unwrap();
        assert_eq!((meta.uid(), meta.gid()), (4321, 4321));
    }

    #[test]
    fn devices_fifos_and_directories_are_refused_as_output() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        crate::input::tests::make_fifo(&fifo);
        let err = write_no_follow(&fifo, b"x").unwrap_err();
        assert_eq!(
            err.to_string(),
            "is a FIFO (named pipe), not a regular file; refusing to write over it"
        );
        assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
        let err = write_no_follow(Path::new("/dev/null"), b"x").unwrap_err();
        assert!(
            err.to_string().starts_with("is a character device"),
            "{err}"
        );
        // A link to a device is refused too, as a link, and stays.
        let link = dir.path().join("null");
        symlink("/dev/null", &link).unwrap();
        let err = write_no_follow(&link, b"x").unwrap_err();
        assert!(err.to_string().starts_with("is a symbolic link"), "{err}");
        let err = write_no_follow(dir.path(), b"x").unwrap_err();
        assert!(err.to_string().starts_with("is a directory"), "{err}");
        assert_eq!(names_in(dir.path()), ["null", "pipe"]);
    }

    #[test]
    fn stale_temporary_files_of_dead_writers_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let own = std::process::id();
        // No process has an id above the kernel's largest (2^22).
        let dead = 99_999_999;
        for name in [
            format!(".cases.ron.tmp-{dead}-a1b2c3"),
            format!(".cases.ron.tmp-{dead}"),
            format!(".cases.ron.tmp-{own}-d4e5f6"),
            format!(".other.ron.tmp-{dead}-a1b2c3"),
        ] {
            fs::write(dir.path().join(name), b"partial").unwrap();
        }
        write_no_follow(&path, b"cases").unwrap();
        assert_eq!(
            names_in(dir.path()),
            [
                format!(".cases.ron.tmp-{own}-d4e5f6"),
                format!(".other.ron.tmp-{dead}-a1b2c3"),
                "cases.ron".to_owned(),
            ]
        );
    }
}

//! An SQLite database file known by its first bytes: the SQLite store looks at a file
//! before SQLite opens it, and an export at the file it would write over. Every build has
//! this, with or without the SQLite store (the `sqlite` feature): an export never writes
//! over a database, whether or not this build could open it.

use std::path::Path;

/// Whether the file begins with SQLite's header.
pub(crate) fn is_database(path: &Path) -> bool {
    header(path).is_some_and(|start| start == HEADER)
}

/// The first bytes of every SQLite database file.
pub(crate) const HEADER: &[u8; 16] = b"SQLite format 3\0";

/// The file's first bytes, as many as SQLite's header has.
pub(crate) fn header(path: &Path) -> Option<Vec<u8>> {
    use std::io::Read;
    let mut start = Vec::with_capacity(HEADER.len());
    std::fs::File::open(path)
        .and_then(|f| f.take(HEADER.len() as u64).read_to_end(&mut start))
        .ok()?;
    Some(start)
}

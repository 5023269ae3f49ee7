//! Reading and writing the workspace's files safely.
//!
//! - [`input`]: bounded reads of regular files only ([`read_text`]), and [`FileError`].
//! - [`name`]: names a user gives that end up in file names, checked
//!   ([`name::check_file_name`], [`name::file_in`]) or made into file names
//!   ([`name::file_stems`]), so none escapes its folder.
//! - [`ron_text`]: RON text parsed with errors that point at file, line:column and the
//!   offending line ([`parse_ron`]).
//! - [`output`]: atomic writes ([`write_atomically`], [`write_file_in`]) and a check that a
//!   folder can take files ([`output::ensure_writable_dir`]).
//!
//! The libraries a robot embeds (`cbr-core`, `trust`) read and write no file; every crate
//! that does (the lab, the domains, the service, the tool) goes through this one.

#![deny(missing_docs)]

pub mod input;
pub mod name;
pub mod output;
pub mod ron_text;

pub use input::{FileError, MAX_CASE_BASE_BYTES, MAX_CONFIG_BYTES, read_text, read_text_at_most};
pub use output::{FolderError, write_atomically, write_file_in};
pub use ron_text::{RonError, parse_ron};

#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod input;
pub mod name;
pub mod output;
pub mod own;
pub mod ron_text;
pub mod staged;

pub use input::{FileError, MAX_CASE_BASE_BYTES, MAX_CONFIG_BYTES, read_text, read_text_at_most};
pub use output::{FolderError, write_file_in, write_no_follow};
pub use own::{OwnFile, ReplaceError};
pub use ron_text::{RonError, parse_ron};
pub use staged::{StagedFolder, StagingError};

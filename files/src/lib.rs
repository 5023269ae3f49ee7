#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod input;
pub mod name;
pub mod output;
pub mod ron_text;

pub use input::{FileError, MAX_CASE_BASE_BYTES, MAX_CONFIG_BYTES, read_text, read_text_at_most};
pub use output::{FolderError, write_atomically, write_file_in};
pub use ron_text::{RonError, parse_ron};

#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod domain;
pub mod exchange;
pub mod lines;
pub mod reply;
pub mod request;
pub mod session;
pub mod shared;
pub mod store;
pub mod transport;

/// The JSON-lines protocol of `serve`, as trustcbr's `docs/protocol.md` tells it (the page
/// itself, so a plug-in's developer finds it in the rustdoc of this crate, with
/// `cargo doc -p service --open`): framing, requests and replies, mission mode, errors,
/// case bases and domain files. The commands it shows are the shipped `trustcbr` tool's; a
/// plug-in's tool takes the same options under its own name.
#[doc = include_str!("../../docs/protocol.md")]
pub mod protocol {}

pub use domain::{DomainDefinition, DomainError};
pub use reply::Reply;
pub use request::{Request, RequestError};
pub use session::{Session, SessionError};
pub use shared::{OpenError, SharedCases};
pub use store::{CaseStore, Location, StoreError};
pub use transport::{Limits, MAX_LINE_BYTES, ServeError};

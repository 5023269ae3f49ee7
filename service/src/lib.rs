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

pub use domain::{DomainDefinition, DomainError};
pub use reply::Reply;
pub use request::{Request, RequestError};
pub use session::{Session, SessionError};
pub use shared::{OpenError, SharedCases};
pub use store::{CaseStore, Location, StoreError};
pub use transport::{Limits, MAX_LINE_BYTES, ServeError};

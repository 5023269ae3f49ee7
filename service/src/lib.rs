//! The trust adapter as a service a robot controller drives.
//!
//! A controller (often Python or C++ in a ROS node) reports every command's outcome as one
//! JSON object per line and reads back, one JSON object per line, whether to keep the
//! behavior or switch to another, in real units. The protocol is documented in
//! `docs/protocol.md`.
//!
//! - [`lines`]: reading lines with a length limit, so no input can claim unbounded memory.
//! - [`request`]: parsing one request line into a typed [`Request`].
//! - [`reply`]: writing answers, with behaviors in real units.
//! - [`domain`]: the behavior space (and adapter config) to serve: built-in or a RON file.
//! - [`store`]: case stores (SQLite, PostgreSQL, RON) behind the [`CaseStore`] trait, each
//!   recording the behavior space its cases were learned in.
//! - [`shared`]: [`SharedCases`], the case memory a server's sessions share, kept in step
//!   with the store.
//! - [`exchange`]: `trustcbr cases export | import | info`.
//! - [`session`]: [`Session`], one controller's request handler over a
//!   [`trust::Adaptation`] and the shared memory; no I/O but the store's.
//! - [`transport`]: sessions over any reader and writer: stdin/stdout, or one thread per
//!   loopback TCP connection.
//!
//! This crate holds no adaptation logic: that is `trust`'s.

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

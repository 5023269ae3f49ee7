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
//! - [`store`]: the case base on disk, loaded once and saved atomically after each retention.
//! - [`session`]: [`Session`], the request handler over a [`trust::TrustAdapter`]; no I/O.
//! - [`transport`]: the session over any reader and writer, stdin/stdout or loopback TCP.
//!
//! This crate holds no adaptation logic: that is `trust`'s.

pub mod domain;
pub mod lines;
pub mod reply;
pub mod request;
pub mod session;
pub mod store;
pub mod transport;

pub use domain::{DomainDefinition, DomainError};
pub use request::{Request, RequestError};
pub use session::{Session, SessionError};
pub use store::{CaseStore, StoreError};
pub use transport::{MAX_LINE_BYTES, ServeError};

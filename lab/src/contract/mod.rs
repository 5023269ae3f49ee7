//! The contract a domain implements: the [`Domain`](domain::Domain) trait, the
//! capabilities a domain may add ([`capability`]) and what its runs return
//! ([`Judgement`](judgement::Judgement)), and the operator it simulates: the standard
//! fields every operator has ([`operator`]), operator files read and checked
//! ([`operator_file`]), patience and attention ([`patience`], [`attention`]), the reasons an
//! operator states ([`feedback`]) and what it states up front ([`stating`]).
//!
//! Nothing here imports another folder: a domain plug-in needs only this folder and the
//! shared modules at the crate's root.

pub mod attention;
pub mod capability;
pub mod domain;
pub mod feedback;
pub mod judgement;
pub mod operator;
pub mod operator_file;
pub mod patience;
pub mod stating;

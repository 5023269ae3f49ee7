//! Many operators at once: families of operators between two poles ([`family`]), the
//! benchmark's development and evaluation instances ([`instance`]), and the benchmark
//! report of every arm over many populations against each one's limit ([`benchmark`]).
//!
//! Imports the [`contract`](crate::contract), [`reference`](crate::reference) and
//! [`experiment`](crate::experiment) folders.

pub mod benchmark;
pub mod family;
pub mod instance;

//! What an arm is measured against: the known-operator limit ([`limit`], its law
//! [`limit_law`], estimated for a domain's operator by [`known_operator`]), the agent that
//! knows a population's members but not which it faces ([`population_reference`]), the operator's
//! landscape over the behavior space ([`landscape`]), and the robot's true competence
//! ([`competence_truth`]).
//!
//! Imports only the [`contract`](crate::contract) folder and the crate root's shared
//! modules: a reference knows nothing of arms or experiments.

pub mod competence_truth;
pub mod known_operator;
pub mod landscape;
pub mod limit;
pub mod limit_law;
pub mod population_reference;

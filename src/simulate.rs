//! A simulated command as a JSON object: the line `simulate` prints for each command, and
//! the dict Python's `trustcbr.simulate` returns. It is the outcome as the protocol's
//! outcome report spells it (`outcome`, `weight`, `duration_s`, `observed`, `stated`:
//! what a controller would send, so it may be sent back as it is) with the operator's true
//! reason, `truth` (`null` for a completion; evaluation only, a robot is never told it),
//! and `overlooked`, the problem an inattentive operator let pass, when there was one.

use lab::Domain;
use lab::experiment::simulate::SimulatedCommand;
use serde_json::{Value, json};
use service::reply;

/// `command` of `domain` as `simulate` prints it.
pub fn command_json<D: Domain + ?Sized>(domain: &D, command: &SimulatedCommand) -> Value {
    let mut line = reply::outcome(&command.outcome, domain.observations());
    line["truth"] = json!(command.judgement.truth);
    if let Some(overlooked) = command.judgement.overlooked {
        line["overlooked"] = json!(overlooked);
    }
    line
}

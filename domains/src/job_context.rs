//! The UGV's context: what its robot knows of the job it was sent on besides the operator
//! (docs/simulation.md#context).
//!
//! - `cargo`: `normal` (the default) or `hazardous`: whether the robot carries material
//!   that harms people or the site if it is spilt, which its dispatcher loads and so knows.
//! - `situation`: `routine` (the default) or `emergency`: whether it was dispatched into
//!   an emergency, which whoever dispatched it says.
//!
//! Both are matched exactly in retrieval: neither value tells what operators accept in the
//! other (docs/simulation.md argues it).

use cbr_core::{ContextSpace, ContextVariable};
use std::sync::LazyLock;

/// The cargo variable's name.
pub const CARGO: &str = "cargo";
/// The situation variable's name.
pub const SITUATION: &str = "situation";

static CONTEXTS: LazyLock<ContextSpace> = LazyLock::new(|| {
    ContextSpace::new(vec![
        ContextVariable::new(CARGO, &["normal", "hazardous"]),
        ContextVariable::new(SITUATION, &["routine", "emergency"]),
    ])
    .expect("distinct names and values")
});

/// The context variables of both UGV scenarios.
pub fn contexts() -> &'static ContextSpace {
    &CONTEXTS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_normal_cargo_on_a_routine_job() {
        let space = contexts();
        let default = space.context([]).unwrap();
        assert_eq!(space.value(&default, CARGO), Some("normal"));
        assert_eq!(space.value(&default, SITUATION), Some("routine"));
        let hazardous = space.context([(CARGO, "hazardous")]).unwrap();
        assert_eq!(hazardous.to_string(), "cargo=hazardous");
        assert!(space.context([(SITUATION, "drill")]).is_err());
    }
}

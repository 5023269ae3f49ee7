//! The two tasks of the paper, by name.

use cbr_core::BehaviorSpace;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;
use trust::DeclaredCause;

/// A task of the UGV world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scenario {
    /// Drive from one place to another.
    Movement,
    /// Patrol from one place to another, scanning suspicious objects on the way.
    Patrol,
}

impl Scenario {
    /// Both scenarios.
    pub const ALL: [Scenario; 2] = [Scenario::Movement, Scenario::Patrol];

    /// The scenario's name: `movement` or `patrol`.
    pub fn as_str(self) -> &'static str {
        match self {
            Scenario::Movement => "movement",
            Scenario::Patrol => "patrol",
        }
    }

    /// The behaviors the robot can adopt in this scenario.
    pub fn space(self) -> Arc<BehaviorSpace> {
        match self {
            Scenario::Movement => crate::spaces::movement_space(),
            Scenario::Patrol => crate::spaces::patrol_space(),
        }
    }

    /// The causes a run of this scenario can end with ([`crate::causes`]).
    pub fn causes(self) -> &'static [DeclaredCause] {
        match self {
            Scenario::Movement => &crate::causes::MOVEMENT,
            Scenario::Patrol => &crate::causes::PATROL,
        }
    }
}

impl fmt::Display for Scenario {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A scenario name that is neither `movement` nor `patrol`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown scenario `{0}`: expected `movement` or `patrol`")]
pub struct UnknownScenario(pub String);

impl FromStr for Scenario {
    type Err = UnknownScenario;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Scenario::ALL
            .into_iter()
            .find(|sc| sc.as_str() == s.trim())
            .ok_or_else(|| UnknownScenario(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for s in Scenario::ALL {
            assert_eq!(s.to_string().parse::<Scenario>(), Ok(s));
        }
        assert!("drive".parse::<Scenario>().is_err());
        assert_eq!(Scenario::Patrol.space().size(), 16_000);
    }
}

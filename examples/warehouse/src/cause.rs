//! Why a pick fails or is interrupted: the warehouse's own causes.
//!
//! Operator files name them (`"dropped-item"`, ...) and the simulation reports them. The
//! domain declares them to the trust machinery ([`DECLARED`], what `Domain::causes`
//! returns), and [`WarehouseCause::to_trust`] names one as a `trust::Cause`; inside this
//! crate a cause is a [`WarehouseCause`], so a misspelt cause cannot compile.

use std::fmt;
use std::str::FromStr;
use trustcbr::serde::{Deserialize, Serialize};
use trustcbr::trust;

/// Why a pick failed or was interrupted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(crate = "trustcbr::serde", into = "String", try_from = "String")]
pub enum WarehouseCause {
    /// The pick took longer than the operator allows.
    TooSlow,
    /// The robot could not stop for someone crossing its path.
    Collision,
    /// The shelf slot was not where the robot's map put it.
    ItemNotFound,
    /// The item slipped out of the gripper.
    DroppedItem,
    /// The gripper squeezed the item beyond what it stands, and the packer saw it.
    CrushedItem,
}

impl WarehouseCause {
    /// Every cause, in declaration order.
    pub const ALL: [WarehouseCause; 5] = [
        WarehouseCause::TooSlow,
        WarehouseCause::Collision,
        WarehouseCause::ItemNotFound,
        WarehouseCause::DroppedItem,
        WarehouseCause::CrushedItem,
    ];

    /// The name operator files use.
    pub const fn as_str(self) -> &'static str {
        match self {
            WarehouseCause::TooSlow => "too-slow",
            WarehouseCause::Collision => "collision",
            WarehouseCause::ItemNotFound => "item-not-found",
            WarehouseCause::DroppedItem => "dropped-item",
            WarehouseCause::CrushedItem => "crushed-item",
        }
    }

    /// The cause as the trust machinery names it.
    pub const fn to_trust(self) -> trust::Cause {
        trust::Cause::from_static(self.as_str())
    }
}

/// The warehouse's causes as the domain declares them (no default weights: each operator
/// file weighs the causes it cares about).
pub const DECLARED: [trust::DeclaredCause; 5] = {
    let mut declared = [trust::DeclaredCause {
        name: WarehouseCause::TooSlow.to_trust(),
        default_weight: None,
    }; 5];
    let mut k = 0;
    while k < WarehouseCause::ALL.len() {
        declared[k].name = WarehouseCause::ALL[k].to_trust();
        k += 1;
    }
    declared
};

impl fmt::Display for WarehouseCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A cause name that is not one of [`WarehouseCause::ALL`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownCause(pub String);

impl fmt::Display for UnknownCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let known = WarehouseCause::ALL.map(WarehouseCause::as_str).join(", ");
        write!(f, "unknown cause `{}` (known: {known})", self.0)
    }
}

impl std::error::Error for UnknownCause {}

impl FromStr for WarehouseCause {
    type Err = UnknownCause;

    fn from_str(name: &str) -> Result<Self, UnknownCause> {
        Self::ALL
            .into_iter()
            .find(|c| c.as_str() == name)
            .ok_or_else(|| UnknownCause(name.to_owned()))
    }
}

impl TryFrom<String> for WarehouseCause {
    type Error = UnknownCause;

    fn try_from(name: String) -> Result<Self, UnknownCause> {
        name.parse()
    }
}

impl From<WarehouseCause> for String {
    fn from(cause: WarehouseCause) -> String {
        cause.as_str().to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_are_declared_once_each() {
        for (cause, declared) in WarehouseCause::ALL.into_iter().zip(DECLARED) {
            assert_eq!(cause.as_str().parse::<WarehouseCause>(), Ok(cause));
            assert_eq!(declared.name.as_str(), cause.as_str());
        }
        assert!(
            "squashed"
                .parse::<WarehouseCause>()
                .unwrap_err()
                .to_string()
                .contains("known: too-slow")
        );
    }
}

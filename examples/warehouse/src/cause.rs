//! Why a pick fails or is interrupted: the warehouse's own causes.
//!
//! Operator files name them (`"dropped-item"`, ...) and the simulation reports them. The
//! trust machinery today knows only the UGV task's causes (`trust::Cause` is a closed
//! enum), so [`WarehouseCause::to_trust`] is the one place where a warehouse cause becomes
//! a `trust::Cause`; everything else in this crate speaks warehouse.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use trustcbr::trust;

/// Why a pick failed or was interrupted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(into = "String", try_from = "String")]
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
    pub fn as_str(self) -> &'static str {
        match self {
            WarehouseCause::TooSlow => "too-slow",
            WarehouseCause::Collision => "collision",
            WarehouseCause::ItemNotFound => "item-not-found",
            WarehouseCause::DroppedItem => "dropped-item",
            WarehouseCause::CrushedItem => "crushed-item",
        }
    }

    /// MERGE: replace this function when `trust::Cause` becomes a domain-declared name
    /// (`trust::Cause::new(self.as_str())`, with the causes listed by
    /// `Domain::causes`). Until then each warehouse cause maps onto the nearest UGV
    /// cause, one to one, so the cause-aware search still tells them apart: too slow ->
    /// `deadline`, collision -> `collision`, slot not found -> `stuck` (the robot cannot
    /// go on), dropped item -> `missed-object` (an object left unhandled), crushed item
    /// -> `detonation` (damage the robot's own action did).
    pub fn to_trust(self) -> trust::Cause {
        match self {
            WarehouseCause::TooSlow => trust::Cause::Deadline,
            WarehouseCause::Collision => trust::Cause::Collision,
            WarehouseCause::ItemNotFound => trust::Cause::Stuck,
            WarehouseCause::DroppedItem => trust::Cause::MissedObject,
            WarehouseCause::CrushedItem => trust::Cause::Detonation,
        }
    }
}

impl fmt::Display for WarehouseCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A cause name that is not one of [`WarehouseCause::ALL`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown cause `{0}` (known: {known})", known = WarehouseCause::ALL.map(WarehouseCause::as_str).join(", "))]
pub struct UnknownCause(pub String);

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
    fn names_round_trip_and_map_one_to_one() {
        for cause in WarehouseCause::ALL {
            assert_eq!(cause.as_str().parse::<WarehouseCause>(), Ok(cause));
        }
        let mut mapped: Vec<_> = WarehouseCause::ALL.map(WarehouseCause::to_trust).into();
        mapped.sort();
        mapped.dedup();
        assert_eq!(mapped.len(), WarehouseCause::ALL.len());
        assert!(
            "squashed"
                .parse::<WarehouseCause>()
                .unwrap_err()
                .to_string()
                .contains("known: too-slow")
        );
    }
}

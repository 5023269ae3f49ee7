//! The behavior spaces of the paper's two scenarios (docs/model.md#the-two-scenarios).
//!
//! Component names are part of the user interface (`--behavior 'speed=3.5,padding=0.4'`,
//! reports, the service protocol): `speed`, `padding`, `scan_time`, `scan_distance`.

use cbr_core::{BehaviorSpace, NamedComponent};
use std::sync::Arc;

/// Speed `{0.5, 1.0, ..., 10.0}` m/s (20 values).
pub fn speed() -> NamedComponent {
    NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).expect("valid grid")
}

/// Obstacle padding `{0.1, 0.2, ..., 2.0}` m (20 values).
pub fn padding() -> NamedComponent {
    NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).expect("valid grid")
}

/// Scan time `{0.5, 1.0, ..., 5.0}` s (10 values).
pub fn scan_time() -> NamedComponent {
    NamedComponent::numeric("scan_time", "s", 0.5, 0.5, 10).expect("valid grid")
}

/// Scan distance `{0.25, 0.5, 0.75, 1.0}` m (4 values).
pub fn scan_distance() -> NamedComponent {
    NamedComponent::numeric("scan_distance", "m", 0.25, 0.25, 4).expect("valid grid")
}

/// The movement space: speed x padding, 400 behaviors.
pub fn movement_space() -> Arc<BehaviorSpace> {
    Arc::new(BehaviorSpace::new(vec![speed(), padding()]).expect("valid space"))
}

/// The patrol space: speed x padding x scan time x scan distance, 16,000 behaviors.
pub fn patrol_space() -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(vec![speed(), padding(), scan_time(), scan_distance()])
            .expect("valid space"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_follow_the_listed_values() {
        assert_eq!(movement_space().size(), 400);
        // 20 x 20 x 10 x 4 (docs/model.md#patrol).
        assert_eq!(patrol_space().size(), 16_000);
    }
}

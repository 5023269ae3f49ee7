//! The maps the robot can plan on: which data the planner uses to find a shelf slot.
//!
//! A map made before today misplaces the slots of aisles re-racked since it was made: the
//! robot drives to where the map puts the slot, scans the label, and finds another item
//! there. A map built live from the robot's own lidar while it drives knows every slot
//! where it is now, but scan matching needs consecutive scans to overlap, which caps the
//! speed. Reasons for the numbers: the crate's README ("Maps").

/// Where the planner's map comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapSource {
    /// The floor plan drawn when the warehouse was commissioned, three years ago.
    AsBuilt,
    /// The quarterly survey, about six weeks old on average.
    LastSurvey,
    /// Built live from the robot's lidar while it drives.
    Live,
}

impl MapSource {
    /// Every map, in the order of the `map` component's labels.
    pub const ALL: [MapSource; 3] = [MapSource::AsBuilt, MapSource::LastSurvey, MapSource::Live];

    /// The label in behaviors (`map=last-survey`).
    pub fn label(self) -> &'static str {
        match self {
            MapSource::AsBuilt => "as-built",
            MapSource::LastSurvey => "last-survey",
            MapSource::Live => "live",
        }
    }

    /// The share of shelf slots the map puts in the wrong place (re-racked since the map
    /// was made).
    pub fn misplaced_share(self) -> f64 {
        match self {
            MapSource::AsBuilt => 0.20,
            MapSource::LastSurvey => 0.04,
            MapSource::Live => 0.0,
        }
    }

    /// The speed (m/s) the robot drives at when commanded `commanded` m/s: live mapping
    /// caps it at 1 m/s (a 10 Hz lidar whose scan matching tolerates 0.1 m between scans).
    pub fn driving_speed(self, commanded: f64) -> f64 {
        match self {
            MapSource::Live => commanded.min(1.0),
            MapSource::AsBuilt | MapSource::LastSurvey => commanded,
        }
    }
}

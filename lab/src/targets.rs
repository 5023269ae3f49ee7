//! Every pass/fail target a report checks and every significance level its tests use, in
//! one place (docs/missions.md states the mission targets and why).

/// The level under which a paired test says two arms differ: a benchmark's wins and
/// losses, and a mission report's "lower with alerts" and "better than its blind twin".
pub const SIGNIFICANCE: f64 = 0.05;

/// The stricter level a preference for competent behaviors must reach on missions: it
/// trades the operator's commands for harm, so the cut must be sure.
pub const PREFERENCE_SIGNIFICANCE: f64 = 0.01;

/// The share of complacency onsets a mission arm must detect within
/// [`crate::mission::DETECTION_WINDOW`] commands.
pub const ONSETS_DETECTED: f64 = 0.9;

/// The most missions without complacency that may have a false alert, as a share.
pub const FALSE_ALERTS: f64 = 0.05;

/// The most missions, as a share, whose watched behavior was competent and still drew an
/// overtrust alert.
pub const FALSE_OVERTRUST_ALERTS: f64 = 0.05;

/// The most untrustworthy commands per switch back the best arm may need, as a multiple of
/// the oracle's.
pub const SWITCH_BACK_TIMES_ORACLE: f64 = 1.5;

/// The cut in harm a preference for competent behaviors must reach, as a share of its base
/// arm's harm.
pub const PREFERENCE_HARM_CUT: f64 = 0.3;

/// The most untrustworthy commands a preference for competent behaviors may cost, as a
/// multiple of its base arm's.
pub const PREFERENCE_COST: f64 = 1.2;

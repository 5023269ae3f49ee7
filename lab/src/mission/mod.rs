//! Missions: long runs of commands in which the operator changes without the robot being
//! told, and operators may grow complacent (docs/missions.md). A mission suite's plan
//! ([`plan`]), the course every arm and the oracle share (`course`), how missions are run
//! ([`run`]) and what they leave ([`record`]), the oracle they are measured against
//! ([`oracle`]), and what a mission suite reports ([`report`], with [`contexts`],
//! [`noticing`], [`calibration`] and the timeline figure, [`figure`]).
//!
//! The highest folder: imports every other, and none imports it.

pub mod calibration;
pub mod contexts;
pub(crate) mod course;
pub mod figure;
pub mod noticing;
pub mod oracle;
pub mod plan;
pub mod record;
pub mod report;
pub mod run;
pub mod summary;

pub use plan::{
    COMPLACENT_BELOW, Changes, CompetenceOn, Complacency, ComplacencyOn, ContextSwitches,
    DETECTION_WINDOW, MissionPlan, RECOVERED_AT, check_competence,
};
pub use record::{
    CalibrationRecord, ChangeKind, ChangeRecord, MAX_TRACE_STEPS, Mark, MissionArmResult,
    MissionRecord, MissionResult, MissionStep, MissionTrace, Noticed, OnsetRecord, OracleRecord,
};
pub use run::run_missions;

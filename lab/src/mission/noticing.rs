//! What the operator changes that needed adaptation cost before and after the robot gave
//! up the behavior it was using (docs/missions.md#noticing-then-searching): how many it
//! noticed so, how soon, and the untrustworthy commands of each part, for every arm and for
//! the oracle, which is told of every change. An arm that is not told notices a change
//! only through its trust estimate, so this splits its cost per change into the cost of
//! noticing and the cost of the search that follows.

use crate::mission::summary::{arm_label, median};
use crate::mission::{ChangeKind, ChangeRecord, MissionResult};
use crate::stats::{MeanCi, mean_ci95_or_zero};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// How one agent met the operator changes that needed adaptation.
#[derive(Clone, Debug, PartialEq)]
pub struct Noticing {
    /// Operator changes after which the behavior in use was not trustworthy.
    pub needed: usize,
    /// Of those, changes after which the behavior was given up before the next change or
    /// the mission's end.
    pub noticed: usize,
    /// The median commands from the change until it was given up, over those noticed.
    pub median_after: Option<f64>,
    /// Untrustworthy commands per change needing adaptation until the behavior was given
    /// up (all of them, when it never was).
    pub before: MeanCi,
    /// Untrustworthy commands per change needing adaptation after it was given up.
    pub after: MeanCi,
}

impl Noticing {
    /// The figures of the operator changes among `changes` that needed adaptation.
    pub fn of<'a>(changes: impl IntoIterator<Item = &'a ChangeRecord>) -> Self {
        let needed: Vec<&ChangeRecord> = changes
            .into_iter()
            .filter(|c| c.kind != ChangeKind::Context && c.needed)
            .collect();
        let before_of = |c: &ChangeRecord| c.noticed.map_or(c.untrustworthy, |n| n.untrustworthy);
        let delays: Vec<f64> = needed
            .iter()
            .filter_map(|c| c.noticed.map(|n| f64::from(n.after)))
            .collect();
        let before: Vec<f64> = needed.iter().map(|c| f64::from(before_of(c))).collect();
        let after: Vec<f64> = needed
            .iter()
            .map(|c| f64::from(c.untrustworthy - before_of(c)))
            .collect();
        Self {
            needed: needed.len(),
            noticed: delays.len(),
            median_after: median(delays),
            before: mean_ci95_or_zero(&before),
            after: mean_ci95_or_zero(&after),
        }
    }
}

/// Every arm's figures (named as in the report's tables) and the oracle's, last.
fn rows(result: &MissionResult) -> Vec<(String, Noticing)> {
    result
        .arms
        .iter()
        .map(|arm| {
            (
                arm_label(&arm.arm, arm.answers_alerts),
                Noticing::of(arm.missions.iter().flat_map(|m| &m.changes)),
            )
        })
        .chain(std::iter::once((
            "oracle".to_owned(),
            Noticing::of(result.oracle.iter().flat_map(|m| &m.changes)),
        )))
        .collect()
}

/// The section of a plan's `missions.md`; `None` when no operator change needed
/// adaptation for any agent.
pub fn noticing_markdown(result: &MissionResult) -> Option<String> {
    let rows = rows(result);
    if rows.iter().all(|(_, n)| n.needed == 0) {
        return None;
    }
    let mut md = String::from(
        "\nOperator changes needing adaptation, noticing then searching (noticed: the behavior in use at the change given up before the next change; untrustworthy commands per change needing adaptation, until then and after):\n\n| agent | changes needing adaptation | noticed | median commands to notice | untrustworthy until noticed | after |\n|---|---:|---:|---:|---:|---:|\n",
    );
    for (label, n) in &rows {
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {:.2} ± {:.2} | {:.2} ± {:.2} |",
            n.needed,
            n.noticed,
            n.median_after.map_or("-".to_owned(), |d| format!("{d:.0}")),
            n.before.mean,
            n.before.ci95,
            n.after.mean,
            n.after.ci95,
        );
    }
    Some(md)
}

/// The plan's `noticing` in `summary.json`: per agent, as in [`noticing_markdown`].
pub fn noticing_json(result: &MissionResult) -> Value {
    Value::Array(
        rows(result)
            .into_iter()
            .map(|(agent, n)| {
                json!({
                    "agent": agent,
                    "needed": n.needed,
                    "noticed": n.noticed,
                    "median_commands_to_notice": n.median_after,
                    "untrustworthy_until_noticed": n.before,
                    "untrustworthy_after": n.after,
                })
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mission::Noticed;

    fn change(kind: ChangeKind, needed: bool, untrustworthy: u32) -> ChangeRecord {
        ChangeRecord {
            at: 100,
            kind,
            needed,
            trusted_again: None,
            untrustworthy,
            back: false,
            start: None,
            noticed: None,
        }
    }

    #[test]
    fn a_behavior_is_noticed_once_with_the_untrustworthy_commands_so_far() {
        let mut c = change(ChangeKind::Shift, true, 6);
        c.notice(112);
        c.untrustworthy += 3;
        c.notice(130);
        assert_eq!(
            c.noticed,
            Some(Noticed {
                after: 12,
                untrustworthy: 6
            })
        );
    }

    #[test]
    fn noticing_then_searching_by_hand() {
        // Three operator changes needed adaptation: noticed after 4 commands (3 of its 10
        // untrustworthy commands before), after 10 (5 of 5), and never (7, all before).
        // A change that needed none and a context switch are left out.
        let mut first = change(ChangeKind::Shift, true, 10);
        first.noticed = Some(Noticed {
            after: 4,
            untrustworthy: 3,
        });
        let mut second = change(ChangeKind::Takeover, true, 5);
        second.noticed = Some(Noticed {
            after: 10,
            untrustworthy: 5,
        });
        let never = change(ChangeKind::Shift, true, 7);
        let changes = [
            first,
            second,
            never,
            change(ChangeKind::Shift, false, 9),
            change(ChangeKind::Context, true, 9),
        ];
        let n = Noticing::of(&changes);
        assert_eq!((n.needed, n.noticed), (3, 2));
        assert_eq!(n.median_after, Some(7.0));
        // Before: 3, 5, 7; after: 7, 0, 0.
        assert!((n.before.mean - 5.0).abs() < 1e-12);
        assert!((n.after.mean - 7.0 / 3.0).abs() < 1e-12);
    }
}

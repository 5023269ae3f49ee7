//! A participant's session told as text (`trustcbr console explain`): each behavior, its
//! commands (how each ended, when, what the robot perceived, what the participant said,
//! the estimate after it), the adapter's explanation of each change and of the end, and
//! the ratings where they were given. Told from the recorded events, after the caller has
//! replayed them (so the story is what the adapter decides).

use crate::db::{Event, Participant};
use crate::participant::{contribution, outcome_kind};
use crate::study::Study;
use std::fmt::Write;
use trust::OutcomeKind;

const HEADER: [&str; 6] = ["#", "outcome", "at (s)", "perceived", "stated", "estimate"];

fn line(cells: &[String], widths: &[usize]) -> String {
    let padded: Vec<String> = cells
        .iter()
        .zip(widths)
        .map(|(cell, width)| format!("{cell:<width$}"))
        .collect();
    format!("  {}", padded.join("  ").trim_end())
}

/// The story of `participant`'s session from their `events`.
pub fn story(study: &Study, participant: &Participant, events: &[Event]) -> String {
    let condition = &study.conditions[participant.condition];
    // Rows per behavior: the behavior's text, its command rows, then what followed it.
    let mut behaviors: Vec<(String, Vec<[String; 6]>, Vec<String>)> = Vec::new();
    let mut estimate = 0.0;
    let mut commands = 0;
    let mut untrustworthy = 0;
    let mut shown = String::new();
    let mut stated: Option<String> = None;
    let mut ended = String::from("the session is under way");
    // Whether the next decision's command opens a behavior (the first, or after a switch).
    let mut opens = true;
    for event in events {
        let body = &event.body;
        match event.kind.as_str() {
            "shown" => shown = body["behavior"].as_str().unwrap_or_default().to_owned(),
            "statement" => stated = body["cause"].as_str().map(str::to_owned),
            "decision" => {
                if opens {
                    behaviors.push((shown.clone(), Vec::new(), Vec::new()));
                    opens = false;
                }
                let report = &body["report"];
                let outcome = report["outcome"].as_str().unwrap_or_default();
                estimate += contribution(report);
                commands += 1;
                if outcome_kind(report) != Some(OutcomeKind::Completed) {
                    untrustworthy += 1;
                }
                let perceived: Vec<&str> = report["observed"]
                    .as_array()
                    .map(|a| a.iter().filter_map(|o| o.as_str()).collect())
                    .unwrap_or_default();
                let (_, rows, after) = behaviors.last_mut().expect("pushed above");
                rows.push([
                    commands.to_string(),
                    outcome.to_owned(),
                    format!("{:.1}", report["duration_s"].as_f64().unwrap_or(0.0)),
                    if perceived.is_empty() {
                        "-".into()
                    } else {
                        perceived.join(", ")
                    },
                    stated.take().unwrap_or_else(|| "-".into()),
                    format!("{estimate:+}"),
                ]);
                let reply = &body["reply"];
                if let Some(sentence) = reply["explanation"]["sentence"].as_str() {
                    after.push(format!("-> {sentence}"));
                }
                if reply["ok"] == "switch" {
                    estimate = 0.0;
                    opens = true;
                }
                if reply["ok"] == "settled" {
                    ended = if reply["trustworthy"] == true {
                        "settled on a behavior the participant trusts, by the estimate".into()
                    } else {
                        "settled without a trustworthy behavior".into()
                    };
                }
                if body.get("abandon_reply").is_some_and(|r| !r.is_null()) {
                    ended = "ended at the study's limits (abandoned, no case retained)".into();
                    after.push("-> the study's limits ended the episode".into());
                }
            }
            "rating" => {
                if let Some((_, _, after)) = behaviors.last_mut() {
                    after.push(format!(
                        "rated {} (the estimate was {:+})",
                        body["value"],
                        body["estimate"].as_f64().unwrap_or(0.0)
                    ));
                }
            }
            _ => {}
        }
    }
    let mut widths = HEADER.map(str::len);
    for (_, rows, _) in &behaviors {
        for row in rows {
            for (width, cell) in widths.iter_mut().zip(row) {
                *width = (*width).max(cell.chars().count());
            }
        }
    }
    let mut text = format!(
        "study/{}, arm {}, participant {}: {commands} commands, {untrustworthy} untrustworthy, {} behaviors; {ended}\n",
        condition.name,
        condition.arm,
        participant.pseudonym(),
        behaviors.len(),
    );
    for (k, (behavior, rows, after)) in behaviors.iter().enumerate() {
        let _ = writeln!(text, "\nbehavior {}: {behavior}", k + 1);
        let _ = writeln!(text, "{}", line(&HEADER.map(str::to_owned), &widths));
        for row in rows {
            let _ = writeln!(text, "{}", line(row, &widths));
        }
        for note in after {
            let _ = writeln!(text, "  {note}");
        }
    }
    text
}

//! `report.html`: one self-contained page (inline SVG and CSS, nothing fetched) holding
//! a contents list, the glossary of arms and metrics, every table (a benchmark suite's
//! benchmark among them), every figure with its caption, the config and the provenance.

use super::benchmark_tables::{
    BENCHMARK_NOTE, BENCHMARK_TITLE, NO_BENCHMARK, SPLIT_NOTE, benchmark_split_table,
    benchmark_table, benchmark_title,
};
use super::entry::{Provenance, ReportEntry};
use super::tables::{
    CONTEXTS_TITLE, FREE_FIRST_TITLE, GOAL_CHANGES_TITLE, POPULATION_TITLE, arms_table,
    contexts_table, effects_table, explanations_table, found_note, free_first_table,
    goal_changes_table, limit_table, population_table, sample_explanations, table,
};
use crate::experiment::arm::Initial;
use crate::population::benchmark::ScenarioBenchmark;
use crate::stats::RatioCi;
use files::name::file_stems;
use std::fmt::Write as _;

/// A figure of the page: its section, its SVG text and its caption (HTML).
pub(super) struct Figure {
    section: String,
    svg: String,
    caption: String,
}

impl Figure {
    pub(super) fn new(section: &str, svg: String, caption: String) -> Self {
        Self {
            section: section.to_owned(),
            svg,
            caption,
        }
    }
}

/// Escapes text for HTML; a control character but a line break or a tab (an escape
/// sequence a user's text may hold) is shown as U+FFFD, never written raw.
pub(super) fn escape(text: &str) -> String {
    let text: String = text
        .chars()
        .map(|c| {
            if c.is_control() && !matches!(c, '\n' | '\t') {
                '\u{FFFD}'
            } else {
                c
            }
        })
        .collect();
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A Markdown table as made by [`table`] and [`arms_table`], as an HTML table in a
/// container that scrolls sideways when the table is wider than the screen.
fn html_table(markdown: &str) -> String {
    let cells = |line: &str| -> Vec<String> {
        line.trim()
            .trim_matches('|')
            .split('|')
            .map(|c| escape(c.trim()))
            .collect()
    };
    let mut lines = markdown.lines().filter(|l| l.starts_with('|'));
    let mut html = String::from("<div class=\"scroll\">\n<table>\n<thead><tr>");
    if let Some(header) = lines.next() {
        for c in cells(header) {
            let _ = write!(html, "<th>{c}</th>");
        }
    }
    html.push_str("</tr></thead>\n<tbody>\n");
    for line in lines.skip(1) {
        html.push_str("<tr>");
        for c in cells(line) {
            let _ = write!(html, "<td>{c}</td>");
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody>\n</table>\n</div>\n");
    html
}

/// What the tables' columns mean, one line each.
const METRICS: [(&str, &str); 9] = [
    (
        "Behaviors evaluated",
        "behaviors the robot tried in a trial before settling on one the operator trusts (the paper's metric; lower is better)",
    ),
    (
        "Commands",
        "commands the operator gave in a trial until it ended",
    ),
    (
        "Untrustworthy commands",
        "commands that failed or that the operator interrupted: what the operator endured",
    ),
    (
        "Found trustworthy",
        "share of trials that ended on a behavior whose trust estimate reached the trustworthy threshold",
    ),
    (
        "Cases acquired",
        "cases retained over the experiment (an arm that reuses cases reads them in later trials)",
    ),
    (
        "Cut off",
        "trials stopped by the suite's <code>max_commands</code> before they ended",
    ),
    (
        "Mean ± CI",
        "the mean over trials and the half-width of its 95% confidence interval",
    ),
    (
        "t-test p, Wilcoxon p",
        "two-sided p-values of the paired t-test and the Wilcoxon signed-rank test of behaviors evaluated, trial by trial, against the reference arm",
    ),
    (
        "Known-operator limit",
        "the cost of an agent that knows every behavior's outcome distribution under the operator and tries them in the best order: no arm can do better on average",
    ),
];

/// The glossary: each arm of the report in one line, then the metrics.
fn glossary(entries: &[ReportEntry<'_>]) -> String {
    let mut html = String::from("<h3>Arms</h3>\n<dl>\n");
    let mut seen: Vec<&str> = Vec::new();
    for arm in entries.iter().flat_map(|e| &e.result.arms) {
        if seen.contains(&arm.name.as_str()) {
            continue;
        }
        seen.push(arm.name.as_str());
        let what = crate::experiment::arm::describe(&arm.name).unwrap_or_else(|| {
            let what = if arm.reuses_cases {
                "an arm of the catalog's own that reuses cases"
            } else {
                "an arm of the catalog's own"
            };
            match arm.initial {
                Initial::Random => what.to_owned(),
                Initial::Learned => {
                    format!("{what}, starting each episode from the case memory's guess")
                }
            }
        });
        let _ = writeln!(
            html,
            "<dt><code>{}</code></dt><dd>{}</dd>",
            escape(arm.name.as_str()),
            escape(&what)
        );
    }
    html.push_str("</dl>\n<h3>Metrics</h3>\n<dl>\n");
    for (name, what) in METRICS {
        let _ = writeln!(html, "<dt>{name}</dt><dd>{what}</dd>");
    }
    html.push_str("</dl>\n");
    html
}

/// The page's style: readable at 800 px, tables scroll sideways in their container,
/// numbers never wrap.
const STYLE: &str = "body { font-family: sans-serif; margin: 2em auto; padding: 0 1em; max-width: 1300px; color: #222; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
.scroll { overflow-x: auto; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; }
th { background: #eee; }
td { text-align: right; white-space: nowrap; }
td:first-child, td:nth-child(2) { text-align: left; white-space: normal; }
figure { margin: 1em 0 2em; }
figure svg { max-width: 100%; height: auto; }
figcaption { max-width: 60em; color: #333; }
dt { font-weight: bold; margin-top: 0.4em; }
code { overflow-wrap: anywhere; }
pre { background: #f6f6f6; padding: 1em; overflow-x: auto; }
";

/// `report.html`: one self-contained page (inline SVG and CSS, nothing fetched): a
/// contents list, the glossary, the tables, the figures (the same SVG text as the files,
/// but the learning curves without their per-trial dots) each with a caption, the config
/// and the provenance; the benchmark's tables after the explanations, for a benchmark suite.
pub(super) fn html_page(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    benchmark: Option<&[ScenarioBenchmark]>,
    config_ron: &str,
    provenance: &Provenance,
    figures: &[Figure],
) -> String {
    // The sections, in order: (id, title, HTML).
    let mut sections: Vec<(String, String, String)> = Vec::new();
    let mut section = |id: &str, title: &str, html: String| {
        sections.push((id.to_owned(), title.to_owned(), html));
    };
    section("glossary", "Arms and metrics", glossary(entries));
    section(
        "paper",
        "Behaviors evaluated per trial (mean ± 95% CI): the paper's two arms",
        html_table(&table(entries)),
    );
    let reference = entries.first().map_or("", |e| e.reference);
    section(
        "arms",
        "Every arm: what it costs the operator",
        format!(
            "<p>p-values test each arm's behaviors evaluated against the reference arm, \
             <code>{}</code> (the suite's <code>reference</code>), trial by trial.</p>\n{}{}",
            escape(reference),
            html_table(&arms_table(entries)),
            match found_note(entries) {
                "" => String::new(),
                note => format!("<p>{}</p>\n", note.trim_end()),
            }
        ),
    );
    section(
        "effects",
        "Effect sizes against the reference arm",
        html_table(&effects_table(entries, effects)),
    );
    let limits = limit_table(entries);
    if !limits.is_empty() {
        section(
            "limit",
            "Against the known-operator limit (the paper's protocol: a random first behavior)",
            html_table(&limits),
        );
        let free_first = free_first_table(entries);
        if !free_first.is_empty() {
            section("free-first", FREE_FIRST_TITLE, html_table(&free_first));
        }
        section(
            "population",
            POPULATION_TITLE,
            html_table(&population_table(entries)),
        );
    }
    let explanations = explanations_html(entries);
    section(
        "explanations",
        "Explanations against the truth",
        explanations,
    );
    let goal_changes = goal_changes_table(entries);
    if !goal_changes.is_empty() {
        section(
            "goal-changes",
            GOAL_CHANGES_TITLE,
            format!(
                "<p>A goal change interrupts a command for a reason that is not the behavior's. Given up though trusted: behaviors the trial's operator trusts (its trustworthy region, learned without goal changes) that the arm gave up. The guess takes an interruption with no stated reason and nothing perceived for an unsaid goal change.</p>\n{}",
                html_table(&goal_changes)
            ),
        );
    }
    let contexts = contexts_table(entries);
    if !contexts.is_empty() {
        section(
            "contexts",
            CONTEXTS_TITLE,
            format!(
                "<p>An arm told its context learns and retrieves its cases in it; its twin <code>NAME+context-blind</code>, as the paper's robot, keeps every case in the default context. Told − blind: the mean paired difference on the same trials, with its Wilcoxon signed-rank p.</p>\n{}",
                html_table(&contexts)
            ),
        );
    }
    if let Some(benchmarks) = benchmark {
        section("benchmark", BENCHMARK_TITLE, benchmark_html(benchmarks));
    }
    let mut titles: Vec<&str> = Vec::new();
    for figure in figures {
        if !titles.contains(&figure.section.as_str()) {
            titles.push(&figure.section);
        }
    }
    for (title, stem) in titles.iter().zip(file_stems(&titles)) {
        let mut html = String::new();
        for figure in figures.iter().filter(|f| f.section == *title) {
            let _ = write!(
                html,
                "<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>\n",
                figure.svg, figure.caption
            );
        }
        section(&format!("figures-{stem}"), title, html);
    }
    section(
        "config",
        "Config",
        format!("<pre>{}</pre>\n", escape(config_ron)),
    );

    page_of(&sections, provenance)
}

/// The explanations section: how often an arm's explanations were right, then a sample of
/// them per experiment.
fn explanations_html(entries: &[ReportEntry<'_>]) -> String {
    let mut explanations = format!(
        "<p>Every behavior an arm gave up was explained from what the robot was told and perceived; the share whose first reason is the operator's most frequent true reason on that behavior (the simulator knows it; the robot does not). Perceivable reasons are those the robot perceives itself (a collision, being stuck, a detonation).</p>\n{}",
        html_table(&explanations_table(entries))
    );
    for e in entries {
        let _ = writeln!(
            explanations,
            "<details><summary>Sample explanations: {}</summary><ul>",
            escape(&e.result.name)
        );
        for (arm, samples) in sample_explanations(e) {
            for sample in samples {
                let _ = writeln!(
                    explanations,
                    "<li><b>{}</b>, {}</li>",
                    escape(&arm),
                    escape(&sample)
                );
            }
        }
        explanations.push_str("</ul></details>\n");
    }
    explanations
}

/// The benchmark section of a benchmark suite: its note, then each scenario's table.
fn benchmark_html(benchmarks: &[ScenarioBenchmark]) -> String {
    let mut html = format!("<p>{}</p>\n", escape(BENCHMARK_NOTE));
    if benchmarks.is_empty() {
        let _ = writeln!(html, "<p>{}</p>", escape(NO_BENCHMARK));
    }
    for benchmark in benchmarks {
        let _ = write!(
            html,
            "<h3>{}</h3>\n{}",
            escape(&benchmark_title(benchmark)),
            html_table(&benchmark_table(benchmark))
        );
        let split = benchmark_split_table(benchmark);
        if !split.is_empty() {
            let _ = write!(
                html,
                "<p>{}</p>\n{}",
                escape(SPLIT_NOTE),
                html_table(&split)
            );
        }
    }
    html
}

/// The page around its `sections` (id, title, HTML): the provenance, the contents, then
/// each section.
fn page_of(sections: &[(String, String, String)], provenance: &Provenance) -> String {
    let mut page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>trustcbr report</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n<h1>Trust-guided behavior adaptation: experiment report</h1>\n"
    );
    let _ = writeln!(
        page,
        "<p>{} {}{}. Command line: <code>{}</code>.</p>",
        escape(&provenance.tool),
        escape(&provenance.version),
        provenance
            .git_commit
            .as_ref()
            .map_or(String::new(), |c| format!(
                ", commit <code>{}</code>",
                escape(c)
            )),
        escape(&provenance.command_line.join(" "))
    );
    page.push_str("<nav>\n<h2>Contents</h2>\n<ul>\n");
    for (id, title, _) in sections {
        let _ = writeln!(page, "<li><a href=\"#{id}\">{}</a></li>", escape(title));
    }
    page.push_str("</ul>\n</nav>\n");
    for (id, title, html) in sections {
        let _ = write!(page, "<h2 id=\"{id}\">{}</h2>\n{html}", escape(title));
    }
    page.push_str("</body>\n</html>\n");
    page
}

//! Progress that tells the truth, on a terminal or in a log.
//!
//! On a terminal: one bar per part of the work (each experiment), which ends when that
//! part ends, and one overall bar whose time left comes from the measured throughput of
//! the whole run (work done per second so far), every line within 100 columns. When
//! stderr is not a terminal (a log, CI, a batch job): a plain line every few seconds and
//! one at the end, so a long run is never silent.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How often a plain line is written when stderr is not a terminal.
pub const PLAIN_EVERY: Duration = Duration::from_secs(5);

/// The widest a part's name is shown, in characters (longer names are cut with `...`).
const NAME_WIDTH: usize = 30;

/// A bar's width, in characters.
const BAR_WIDTH: usize = 16;

/// The width of a count (up to 999,999).
const COUNT_WIDTH: usize = 6;

/// The template of a bar line, with `tail` after the counts.
fn template(tail: &str) -> String {
    format!(
        "{{prefix:<{NAME_WIDTH}}} [{{bar:{BAR_WIDTH}}}] {{pos:>{COUNT_WIDTH}}}/{{len:<{COUNT_WIDTH}}} {tail}"
    )
}

/// How often the overall bar's time left is recomputed.
const ETA_EVERY: Duration = Duration::from_millis(250);

/// Progress over several parts of counted work (e.g. trials per experiment).
pub struct Progress {
    unit: &'static str,
    /// What follows the counted work, shown once it is all done.
    afterwards: Option<&'static str>,
    totals: Vec<u64>,
    done: Vec<AtomicU64>,
    started: Instant,
    display: Display,
    finished: std::sync::atomic::AtomicBool,
}

enum Display {
    Bars {
        parts: Vec<ProgressBar>,
        overall: ProgressBar,
        _group: MultiProgress,
        eta_updated: Mutex<Instant>,
    },
    Plain {
        last: Mutex<Instant>,
    },
}

/// `name` cut to [`NAME_WIDTH`] characters.
fn shown(name: &str) -> String {
    if name.chars().count() <= NAME_WIDTH {
        name.to_owned()
    } else {
        let cut: String = name.chars().take(NAME_WIDTH - 3).collect();
        format!("{cut}...")
    }
}

/// `42 s`, `3 min 05 s`.
fn duration(seconds: f64) -> String {
    let s = seconds.round().max(0.0) as u64;
    if s < 60 {
        format!("{s} s")
    } else {
        format!("{} min {:02} s", s / 60, s % 60)
    }
}

/// The time left at the measured throughput: `done` of `total` in `elapsed` seconds.
pub fn time_left(done: u64, total: u64, elapsed: f64) -> Option<f64> {
    (done > 0 && elapsed > 0.0).then(|| (total.saturating_sub(done)) as f64 * elapsed / done as f64)
}

impl Progress {
    /// Progress over `parts` (a name and how many `unit`s each), drawn on stderr: bars on
    /// a terminal, plain lines otherwise.
    pub fn new(unit: &'static str, parts: &[(String, u64)]) -> Self {
        Self::with_terminal(unit, parts, std::io::stderr().is_terminal())
    }

    fn with_terminal(unit: &'static str, parts: &[(String, u64)], terminal: bool) -> Self {
        let totals: Vec<u64> = parts.iter().map(|(_, n)| *n).collect();
        let all: u64 = totals.iter().sum();
        let display = if terminal {
            let group = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template(&template("{elapsed:>4}"))
                .expect("a valid template")
                .progress_chars("=> ");
            let parts = if parts.len() > 1 {
                parts
                    .iter()
                    .map(|(name, n)| {
                        group.add(
                            ProgressBar::new(*n)
                                .with_style(style.clone())
                                .with_prefix(shown(name)),
                        )
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let overall = group.add(
                ProgressBar::new(all)
                    .with_style(
                        ProgressStyle::with_template(&template("{msg}"))
                            .expect("a valid template")
                            .progress_chars("=> "),
                    )
                    .with_prefix(format!("all ({unit}s)")),
            );
            Display::Bars {
                parts,
                overall,
                _group: group,
                eta_updated: Mutex::new(Instant::now()),
            }
        } else {
            Display::Plain {
                last: Mutex::new(Instant::now()),
            }
        };
        Self {
            unit,
            afterwards: None,
            done: totals.iter().map(|_| AtomicU64::new(0)).collect(),
            totals,
            started: Instant::now(),
            display,
            finished: std::sync::atomic::AtomicBool::new(false),
        }
    }

    /// The same progress saying `text` (e.g. "writing the report") once every unit is
    /// done and the work goes on.
    #[must_use]
    pub fn with_afterwards(self, text: &'static str) -> Self {
        Self {
            afterwards: Some(text),
            ..self
        }
    }

    /// One more unit of part `part` is done.
    pub fn tick(&self, part: usize) {
        let done = self.done[part].fetch_add(1, Ordering::Relaxed) + 1;
        let elapsed = self.started.elapsed();
        let (all_done, total) = self.counts();
        if all_done == total {
            self.finish(self.afterwards);
            return;
        }
        match &self.display {
            Display::Bars {
                parts,
                overall,
                eta_updated,
                ..
            } => {
                if let Some(bar) = parts.get(part) {
                    bar.inc(1);
                    if done >= self.totals[part] {
                        bar.finish();
                    }
                }
                overall.inc(1);
                let mut updated = eta_updated.lock().expect("never poisoned");
                if updated.elapsed() >= ETA_EVERY {
                    *updated = Instant::now();
                    overall.set_message(self.status(elapsed.as_secs_f64()));
                }
            }
            Display::Plain { last } => {
                let mut last = last.lock().expect("never poisoned");
                if last.elapsed() >= PLAIN_EVERY {
                    *last = Instant::now();
                    eprintln!("{}", self.line(elapsed.as_secs_f64()));
                }
            }
        }
    }

    /// Units done and in all.
    fn counts(&self) -> (u64, u64) {
        (
            self.done.iter().map(|d| d.load(Ordering::Relaxed)).sum(),
            self.totals.iter().sum(),
        )
    }

    /// `12 s elapsed, about 30 s left`.
    fn status(&self, elapsed: f64) -> String {
        let (done, total) = self.counts();
        match time_left(done, total, elapsed) {
            Some(left) => format!("{}, about {} left", duration(elapsed), duration(left)),
            None => duration(elapsed),
        }
    }

    /// `progress: 12345/31500 trials (39%), 12 s elapsed, about 30 s left`.
    fn line(&self, elapsed: f64) -> String {
        let (done, total) = self.counts();
        let left = time_left(done, total, elapsed).map_or(String::new(), |left| {
            format!(", about {} left", duration(left))
        });
        format!(
            "progress: {done}/{total} {}s ({}%), {} elapsed{left}",
            self.unit,
            (100 * done).checked_div(total).unwrap_or(100),
            duration(elapsed),
        )
    }

    /// The counted work is done (the last [`Progress::tick`]); `then` says what still
    /// follows, if anything. Once only.
    fn finish(&self, then: Option<&str>) {
        if self.finished.swap(true, Ordering::Relaxed) {
            return;
        }
        let elapsed = self.started.elapsed().as_secs_f64();
        match &self.display {
            Display::Bars { parts, overall, .. } => {
                for bar in parts.iter().filter(|bar| !bar.is_finished()) {
                    bar.finish();
                }
                overall.finish_with_message(match then {
                    Some(next) => format!("{}; {next}", duration(elapsed)),
                    None => duration(elapsed),
                });
            }
            Display::Plain { .. } => {
                let (_, total) = self.counts();
                eprintln!(
                    "progress: {total}/{total} {}s done in {}{}",
                    self.unit,
                    duration(elapsed),
                    then.map_or(String::new(), |next| format!("; {next}"))
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_left_is_the_measured_throughput() {
        // 100 of 400 in 10 s: 10 per second, 300 left: 30 s.
        assert_eq!(time_left(100, 400, 10.0), Some(30.0));
        assert_eq!(time_left(0, 400, 10.0), None);
        assert_eq!(time_left(400, 400, 10.0), Some(0.0));
        assert_eq!(duration(42.4), "42 s");
        assert_eq!(duration(185.0), "3 min 05 s");
        assert_eq!(shown("movement/speed-focused"), "movement/speed-focused");
        assert_eq!(
            shown("patrol/a-very-long-population-name-indeed"),
            "patrol/a-very-long-populati..."
        );
    }

    #[test]
    fn plain_lines_fit_a_terminal_and_count_every_part() {
        let p = Progress::with_terminal("trial", &[("a".into(), 3), ("b".into(), 1)], false);
        p.tick(0);
        p.tick(1);
        let line = p.line(10.0);
        assert!(
            line.starts_with("progress: 2/4 trials (50%), 10 s elapsed, about 10 s left"),
            "{line}"
        );
        assert!(line.len() <= 100);
    }

    #[test]
    fn bar_lines_fit_100_columns() {
        // The widest line: the overall bar an hour in with an hour left. The template is
        // the name, ` [`, the bar, `] `, the counts with `/` and a space, then the status.
        assert_eq!(template("x"), "{prefix:<30} [{bar:16}] {pos:>6}/{len:<6} x");
        let status = format!("{}, about {} left", duration(3599.0), duration(3599.0));
        let widest = NAME_WIDTH + 2 + BAR_WIDTH + 2 + COUNT_WIDTH + 1 + COUNT_WIDTH + 1;
        assert!(widest + status.len() <= 100, "{}", widest + status.len());
    }
}

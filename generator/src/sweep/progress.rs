//! Progress of a sweep: a bar with rate and ETA (indicatif) on a terminal,
//! plain periodic log lines otherwise (nightly logs), or nothing.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use crate::homogenize::path::LevelReport;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ProgressMode {
    /// A bar if standard error is a terminal, log lines otherwise.
    #[default]
    Auto,
    /// Always a bar.
    Bar,
    /// Always log lines.
    Log,
    /// Nothing.
    Quiet,
}

/// A thread-safe progress counter of micro-solves (one per grid point and sample).
pub struct Progress {
    total: usize,
    done: AtomicUsize,
    failed: AtomicUsize,
    start: Instant,
    bar: Option<ProgressBar>,
    log: Option<(Duration, Mutex<Instant>)>,
}

/// `1h02m03s`-style durations.
pub fn format_duration(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "?".into();
    }
    let s = seconds.round() as u64;
    match (s / 3600, (s / 60) % 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, m, sec) => format!("{m}m{sec:02}s"),
        (h, m, sec) => format!("{h}h{m:02}m{sec:02}s"),
    }
}

impl Progress {
    /// Progress over `total` micro-solves; log lines every `interval`.
    pub fn new(mode: ProgressMode, total: usize, interval: Duration) -> Self {
        let terminal = std::io::stderr().is_terminal();
        let (bar, log) = match (mode, terminal) {
            (ProgressMode::Quiet, _) => (None, None),
            (ProgressMode::Bar, _) | (ProgressMode::Auto, true) => {
                let b = ProgressBar::new(total as u64);
                b.set_style(
                    ProgressStyle::with_template(
                        "{elapsed_precise} [{bar:40}] {pos}/{len} micro-solves, {per_sec}, ETA {eta} {msg}",
                    )
                    .expect("valid template")
                    .progress_chars("=> "),
                );
                b.enable_steady_tick(Duration::from_millis(500));
                (Some(b), None)
            }
            (ProgressMode::Log, _) | (ProgressMode::Auto, false) => {
                (None, Some((interval, Mutex::new(Instant::now()))))
            }
        };
        Progress {
            total,
            done: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            start: Instant::now(),
            bar,
            log,
        }
    }

    /// One more micro-solve finished.
    pub fn point(&self, failed: bool) {
        self.done.fetch_add(1, Ordering::Relaxed);
        if failed {
            let f = self.failed.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(b) = &self.bar {
                b.set_message(format!("({f} failed)"));
            }
        }
        if let Some(b) = &self.bar {
            b.inc(1);
        }
        self.log_line("");
    }

    /// In log mode, the periodic line with `suffix`, at most once per
    /// interval.
    fn log_line(&self, suffix: &str) {
        if let Some((interval, last)) = &self.log {
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if last.elapsed() >= *interval {
                *last = Instant::now();
                eprintln!("{}{suffix}", self.line());
            }
        }
    }

    /// An adaptive level ended ([`LevelReport`]): a 3D point takes minutes per
    /// level. On the bar it is the message; in the log it is added to the
    /// periodic line, which it may also bring (at most one line per
    /// interval, as the points).
    pub fn level(&self, report: &LevelReport) {
        let failed = self.failed.load(Ordering::Relaxed);
        let failed = if failed > 0 {
            format!("({failed} failed) ")
        } else {
            String::new()
        };
        if let Some(b) = &self.bar {
            b.set_message(format!("{failed}last level: {report}"));
        }
        if self.log.is_some() {
            self.log_line(&format!("; last level: {report}"));
        }
    }

    /// Micro-solves done and failed so far.
    pub fn counts(&self) -> (usize, usize) {
        (
            self.done.load(Ordering::Relaxed),
            self.failed.load(Ordering::Relaxed),
        )
    }

    /// A log line: done/total, rate, ETA, failures, elapsed.
    pub fn line(&self) -> String {
        let (done, failed) = self.counts();
        let elapsed = self.start.elapsed().as_secs_f64();
        let rate = done as f64 / elapsed.max(1e-9);
        let eta = (self.total - done.min(self.total)) as f64 / rate;
        format!(
            "[tcgen sweep] {done}/{} micro-solves ({:.1} %), {rate:.3}/s, ETA {}, {failed} failed, elapsed {}",
            self.total,
            100.0 * done as f64 / self.total.max(1) as f64,
            if done == 0 {
                "?".into()
            } else {
                format_duration(eta)
            },
            format_duration(elapsed)
        )
    }

    /// Ends the display (the final log line in log mode).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish();
        }
        if self.log.is_some() {
            eprintln!("{}", self.line());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_formats() {
        let p = Progress::new(ProgressMode::Quiet, 4, Duration::from_secs(1));
        p.point(false);
        p.point(true);
        assert_eq!(p.counts(), (2, 1));
        assert!(
            p.line().contains("2/4 micro-solves (50.0 %)"),
            "{}",
            p.line()
        );
        assert_eq!(format_duration(3723.0), "1h02m03s");
        assert_eq!(format_duration(61.0), "1m01s");
    }
}

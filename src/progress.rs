//! Progress of the long phases (field build, start surface, final fit) for the app's status line:
//! a phase name and the fraction done, handed to a callback the caller supplies. Reports are
//! thinned to one per [`INTERVAL_MS`] (and always the end of a phase), so a loop may report every
//! item at the cost of a clock read.

use crate::clock::now_ms;

/// Shortest time between two reports of the same phase, in milliseconds.
pub const INTERVAL_MS: f64 = 100.0;

/// A callback `(phase, fraction)`.
pub type Sink<'a> = &'a mut dyn FnMut(&str, f64);

/// Where progress goes: nowhere ([`Progress::none`]) or to a [`Sink`].
pub struct Progress<'a> {
    sink: Option<Sink<'a>>,
    last_ms: f64,
    last_phase: &'static str,
}

impl<'a> Progress<'a> {
    /// Reports go nowhere.
    pub fn none() -> Progress<'static> {
        Progress {
            sink: None,
            last_ms: f64::NEG_INFINITY,
            last_phase: "",
        }
    }

    /// Reports go to `sink(phase, fraction)`.
    pub fn to(sink: Sink<'a>) -> Self {
        Progress {
            sink: Some(sink),
            last_ms: f64::NEG_INFINITY,
            last_phase: "",
        }
    }

    /// `phase` is `fraction` (0–1) done: passed on when the phase is new, finished, or the last
    /// report is [`INTERVAL_MS`] old.
    pub fn report(&mut self, phase: &'static str, fraction: f64) {
        let Some(sink) = self.sink.as_mut() else {
            return;
        };
        let now = now_ms();
        if phase != self.last_phase || fraction >= 1.0 || now - self.last_ms >= INTERVAL_MS {
            sink(phase, fraction.clamp(0.0, 1.0));
            self.last_ms = now;
            self.last_phase = phase;
        }
    }

    /// `done` of `total` items of `phase`; cheap enough for every item (reads the clock only
    /// every 1024th).
    pub fn items(&mut self, phase: &'static str, done: usize, total: usize) {
        if self.sink.is_some() && (done % 1024 == 0 || done + 1 == total) {
            self.report(phase, (done + 1) as f64 / total.max(1) as f64);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_are_thinned_but_phase_starts_and_ends_pass() {
        let mut seen = Vec::new();
        let mut sink = |p: &str, f: f64| seen.push((p.to_string(), f));
        {
            let mut pr = Progress::to(&mut sink);
            for i in 0..10_000 {
                pr.items("a", i, 10_000);
            }
            pr.report("b", 0.0);
            pr.report("b", 1.0);
        }
        assert_eq!(seen.first().map(|s| s.0.as_str()), Some("a"));
        assert!(seen.iter().any(|s| s == &("a".to_string(), 1.0)));
        assert_eq!(seen.last(), Some(&("b".to_string(), 1.0)));
        assert!(seen.len() < 20, "{}", seen.len());
        Progress::none().report("c", 0.5);
    }
}

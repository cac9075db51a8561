//! Periodic timing on absolute deadlines, and the loop statistics every periodic
//! thread keeps about itself (wake-up lateness, execution time, overruns).
//!
//! A thread wakes at start + k * period. If a tick runs past the next deadline, the
//! missed periods are counted as overruns and skipped, so that a late loop never
//! bursts to catch up.

use std::time::{Duration, Instant};

use hdrhistogram::Histogram;

/// Percentiles of one measured quantity, in microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Percentiles {
    pub p50: u64,
    pub p99: u64,
    pub max: u64,
}

/// A loop's figures, as the report and the status line show them.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct LoopSummary {
    pub rate_hz: f64,
    pub ticks: u64,
    pub overruns: u64,
    pub late_us: Percentiles,
    pub exec_us: Percentiles,
}

/// Histograms of lateness and execution time; recording never allocates.
pub struct LoopStats {
    rate_hz: f64,
    late_us: Histogram<u64>,
    exec_us: Histogram<u64>,
    pub ticks: u64,
    pub overruns: u64,
}

fn histogram() -> Histogram<u64> {
    // 1 us to 10 s at 3 significant digits; values beyond are clamped into range.
    Histogram::new_with_bounds(1, 10_000_000, 3).expect("constant bounds are valid")
}

fn percentiles(h: &Histogram<u64>) -> Percentiles {
    Percentiles {
        p50: h.value_at_quantile(0.5),
        p99: h.value_at_quantile(0.99),
        max: h.max(),
    }
}

impl LoopStats {
    pub fn new(rate_hz: f64) -> LoopStats {
        LoopStats {
            rate_hz,
            late_us: histogram(),
            exec_us: histogram(),
            ticks: 0,
            overruns: 0,
        }
    }

    pub fn record(&mut self, late: Duration, exec: Duration) {
        self.ticks += 1;
        self.late_us.saturating_record(late.as_micros() as u64);
        self.exec_us.saturating_record(exec.as_micros() as u64);
    }

    pub fn summary(&self) -> LoopSummary {
        LoopSummary {
            rate_hz: self.rate_hz,
            ticks: self.ticks,
            overruns: self.overruns,
            late_us: percentiles(&self.late_us),
            exec_us: percentiles(&self.exec_us),
        }
    }
}

/// Wakes a thread at absolute deadlines.
pub struct Periodic {
    period: Duration,
    next: Instant,
    woke: Instant,
    late: Duration,
    pub stats: LoopStats,
}

impl Periodic {
    pub fn new(rate_hz: f64) -> Periodic {
        let now = Instant::now();
        let period = Duration::from_secs_f64(1.0 / rate_hz);
        Periodic {
            period,
            next: now + period,
            woke: now,
            late: Duration::ZERO,
            stats: LoopStats::new(rate_hz),
        }
    }

    /// Sleep until the next deadline.
    pub fn wait(&mut self) {
        let now = Instant::now();
        if self.next > now {
            std::thread::sleep(self.next - now);
        }
        self.woke = Instant::now();
        self.late = self.woke.saturating_duration_since(self.next);
    }

    /// The time until the next deadline (for threads that also wait on a channel).
    pub fn until_deadline(&self) -> Duration {
        self.next.saturating_duration_since(Instant::now())
    }

    /// Whether the next deadline has passed.
    pub fn due(&self) -> bool {
        Instant::now() >= self.next
    }

    /// Mark the start of an unscheduled tick (woken early by an event).
    pub fn woke_now(&mut self) {
        self.woke = Instant::now();
        self.late = Duration::ZERO;
    }

    /// The tick's work is done: record its figures and set the next deadline,
    /// skipping (and counting) any periods the work ran into.
    pub fn done(&mut self) {
        let now = Instant::now();
        self.stats.record(self.late, now - self.woke);
        self.next += self.period;
        while self.next <= now {
            self.next += self.period;
            self.stats.overruns += 1;
        }
    }

    /// Done with an unscheduled tick: record it but keep the deadline.
    pub fn done_unscheduled(&mut self) {
        let now = Instant::now();
        self.stats.record(Duration::ZERO, now - self.woke);
    }
}

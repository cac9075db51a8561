//! The latency test: the supervisor's loop, empty, at its rate, priority and CPU for a
//! few seconds. A tick woken later than a tenth of its period eats into the time the
//! regulators have; one later than a period is a missed tick, which the supervisor
//! counts and, repeated, faults on.

use super::{Check, Level};
use crate::config::Settings;

pub(super) fn check(s: &Settings, duration_s: f64) -> Check {
    let rate_hz = s.supervisor.rate_hz;
    let (priority, cpu) = (s.rt.supervisor_priority, s.rt.supervisor_cpu);
    let (figures, refused) = crate::rt::latency::empty_loop(rate_hz, priority, cpu, duration_s);
    let period_us = 1e6 / rate_hz;
    let late = figures.late_us;
    let at = match &refused {
        None if priority > 0 => format!("SCHED_FIFO {priority}"),
        _ => "normal priority".to_string(),
    };
    let says = format!(
        "{} ticks at {rate_hz} Hz, {at}: late p50 {} us, p99 {} us, max {} us, {} missed (period {period_us:.0} us)",
        figures.ticks, late.p50, late.p99, late.max, figures.overruns
    );
    judge(says, late.max as f64, figures.overruns, period_us)
}

/// The level of a test whose worst tick was `max_late_us` late.
pub(super) fn judge(says: String, max_late_us: f64, missed: u64, period_us: f64) -> Check {
    let fix = "a PREEMPT_RT kernel, the real-time priority (the service's LimitRTPRIO), [rt] supervisor_cpu on a CPU kept free (isolcpus), and no other heavy program on the robot PC";
    if missed > 0 || max_late_us >= period_us {
        Check::new("latency", Level::Fail, says, fix)
    } else if max_late_us >= period_us / 10.0 {
        Check::new("latency", Level::Warning, says, fix)
    } else {
        Check::ok("latency", says)
    }
}

//! Real-time behaviour of the periodic threads: sleeping to absolute deadlines,
//! scheduling priorities, locked memory, and the figures each loop keeps about itself.
//!
//! A periodic thread wakes at start + k * period on CLOCK_MONOTONIC (clock_nanosleep
//! with TIMER_ABSTIME), so its period does not drift with its own execution time. If a
//! tick runs past the next deadline, the missed periods are counted as overruns and
//! skipped: a late loop never bursts to catch up.

use hdrhistogram::Histogram;
use thread_priority::{
    RealtimeThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue, ThreadSchedulePolicy,
    set_thread_priority_and_policy, thread_native_id,
};

pub mod health;
pub mod inject;
pub mod latency;
pub mod load;

use crate::config::RtSettings;

mod liu_layland;
pub use liu_layland::{LiuLayland, liu_layland};

/// Nanoseconds on `clock`.
fn clock_ns(clock: libc::clockid_t) -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the timespec we own; both clocks used here
    // always exist on Linux.
    unsafe { libc::clock_gettime(clock, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Nanoseconds on CLOCK_MONOTONIC.
pub(crate) fn monotonic_ns() -> u64 {
    clock_ns(libc::CLOCK_MONOTONIC)
}

/// CPU time used by this whole process so far (every thread, also those that have
/// ended), s: what `bench loop` compares between headless and GUI-open runs.
pub fn process_cpu_s() -> f64 {
    clock_ns(libc::CLOCK_PROCESS_CPUTIME_ID) as f64 * 1e-9
}

/// Sleep until `deadline_ns` on CLOCK_MONOTONIC.
fn sleep_until_ns(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    loop {
        // SAFETY: plain system call on a timespec we own; no remaining-time pointer is
        // needed with TIMER_ABSTIME.
        let rc = unsafe {
            libc::clock_nanosleep(
                libc::CLOCK_MONOTONIC,
                libc::TIMER_ABSTIME,
                &ts,
                std::ptr::null_mut(),
            )
        };
        if rc != libc::EINTR {
            return;
        }
    }
}

/// Percentiles of one measured quantity, in microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Percentiles {
    pub p50: u64,
    pub p99: u64,
    pub p999: u64,
    pub max: u64,
}

/// A loop's figures, as the report and the status line show them.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct LoopSummary {
    pub rate_hz: f64,
    pub ticks: u64,
    pub overruns: u64,
    pub late_us: Percentiles,
    pub exec_us: Percentiles,
    /// Longest the loop waited for or held a protected object's lock, us.
    pub worst_lock_us: u64,
    /// Times the loop found a lock busy and went on without waiting.
    pub locks_busy: u64,
}

/// Histograms of lateness and execution time; recording never allocates.
pub(crate) struct LoopStats {
    rate_hz: f64,
    late_us: Histogram<u64>,
    exec_us: Histogram<u64>,
    pub ticks: u64,
    pub overruns: u64,
    pub worst_lock_us: u64,
    pub locks_busy: u64,
}

fn histogram() -> Histogram<u64> {
    // 1 us to 10 s at 3 significant digits; values beyond are clamped into range.
    Histogram::new_with_bounds(1, 10_000_000, 3).expect("constant bounds are valid")
}

fn percentiles(h: &Histogram<u64>) -> Percentiles {
    Percentiles {
        p50: h.value_at_quantile(0.5),
        p99: h.value_at_quantile(0.99),
        p999: h.value_at_quantile(0.999),
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
            worst_lock_us: 0,
            locks_busy: 0,
        }
    }

    pub fn record(&mut self, late_ns: u64, exec_ns: u64) {
        self.ticks += 1;
        self.late_us.saturating_record(late_ns / 1000);
        self.exec_us.saturating_record(exec_ns / 1000);
    }

    pub fn summary(&self) -> LoopSummary {
        LoopSummary {
            rate_hz: self.rate_hz,
            ticks: self.ticks,
            overruns: self.overruns,
            late_us: percentiles(&self.late_us),
            exec_us: percentiles(&self.exec_us),
            worst_lock_us: self.worst_lock_us,
            locks_busy: self.locks_busy,
        }
    }
}

/// Wakes a thread at absolute deadlines and measures each tick.
pub(crate) struct Periodic {
    period_ns: u64,
    next_ns: u64,
    woke_ns: u64,
    late_ns: u64,
    /// When the loop's figures are next due for its readers (`figures_due`).
    figures_due_ns: u64,
    pub stats: LoopStats,
}

/// How often a loop's figures go out to the bus, the GUI and the console, ns: often
/// enough that a rate worked out from two of them is within a few per cent.
const FIGURES_EVERY_NS: u64 = 250_000_000;

impl Periodic {
    pub fn new(rate_hz: f64) -> Periodic {
        let now = monotonic_ns();
        let period_ns = (1e9 / rate_hz).round() as u64;
        Periodic {
            period_ns,
            next_ns: now + period_ns,
            woke_ns: now,
            late_ns: 0,
            figures_due_ns: now,
            stats: LoopStats::new(rate_hz),
        }
    }

    /// Sleep until the next deadline.
    pub fn wait(&mut self) {
        sleep_until_ns(self.next_ns);
        self.woke_ns = monotonic_ns();
        self.late_ns = self.woke_ns.saturating_sub(self.next_ns);
    }

    /// The time until the next deadline (for threads that also wait on a channel).
    pub(crate) fn until_deadline(&self) -> std::time::Duration {
        std::time::Duration::from_nanos(self.next_ns.saturating_sub(monotonic_ns()))
    }

    /// Mark the start of an unscheduled tick (woken early by an event).
    pub(crate) fn woke_now(&mut self) {
        self.woke_ns = monotonic_ns();
        self.late_ns = 0;
    }

    /// The tick's work is done: record its figures and set the next deadline,
    /// skipping (and counting) any periods the work ran into.
    pub fn done(&mut self) {
        let now = monotonic_ns();
        self.stats.record(self.late_ns, now - self.woke_ns);
        self.next_ns += self.period_ns;
        if self.next_ns <= now {
            let missed = (now - self.next_ns) / self.period_ns + 1;
            self.next_ns += missed * self.period_ns;
            self.stats.overruns += missed;
        }
    }

    /// Whether the loop's figures are due for its readers: every FIGURES_EVERY_NS of the
    /// monotonic clock (and at the first tick), whatever woke the loop.
    pub(crate) fn figures_due(&mut self) -> bool {
        let now = monotonic_ns();
        if now < self.figures_due_ns {
            return false;
        }
        self.figures_due_ns = now + FIGURES_EVERY_NS;
        true
    }

    /// Done with an unscheduled tick: record its execution but keep the deadline.
    pub(crate) fn done_unscheduled(&mut self) {
        let now = monotonic_ns();
        self.stats.record(0, now - self.woke_ns);
    }
}

/// Below this memlock limit the program does not lock its memory: with MCL_FUTURE,
/// every later allocation beyond the limit would fail and stop the program.
const MEMLOCK_NEEDED_BYTES: u64 = 1 << 30;

/// Capability bit that lifts the memlock limit (linux/capability.h).
const CAP_IPC_LOCK: u32 = 14;

/// Whether the process holds a capability, from /proc/self/status (root holds all).
fn has_capability(bit: u32) -> bool {
    capability_in(
        &std::fs::read_to_string("/proc/self/status").unwrap_or_default(),
        bit,
    )
}

/// Whether the effective capability set in a /proc/PID/status text has `bit`.
fn capability_in(status: &str, bit: u32) -> bool {
    status
        .lines()
        .find_map(|line| line.strip_prefix("CapEff:"))
        .and_then(|hex| u64::from_str_radix(hex.trim(), 16).ok())
        .is_some_and(|caps| caps & (1 << bit) != 0)
}

/// Lock the process's memory, so that no page fault delays a tick. Returns a warning
/// saying what to change when the system refuses.
pub fn lock_memory() -> Option<String> {
    if let Some(refusal) = memlock_too_small() {
        return Some(refusal);
    }
    // SAFETY: mlockall takes flags only.
    let rc = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) };
    (rc != 0).then(|| {
        format!(
            "memory not locked ({}): allow it with 'ulimit -l unlimited', a memlock line in /etc/security/limits.conf, or LimitMEMLOCK=infinity in the systemd unit",
            std::io::Error::last_os_error()
        )
    })
}

/// Why this process may not lock its memory safely (the memlock limit, without
/// CAP_IPC_LOCK), or None: `mechweed doctor` asks without locking.
pub fn memlock_too_small() -> Option<String> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes into the struct we own.
    let known = unsafe { libc::getrlimit(libc::RLIMIT_MEMLOCK, &mut limit) } == 0;
    if known
        && !has_capability(CAP_IPC_LOCK)
        && limit.rlim_cur != libc::RLIM_INFINITY
        && limit.rlim_cur < MEMLOCK_NEEDED_BYTES
    {
        return Some(format!(
            "memory not locked: the memlock limit is {} MiB, too small to lock safely; raise it with 'ulimit -l unlimited', a memlock line in /etc/security/limits.conf, or LimitMEMLOCK=infinity in the systemd unit",
            limit.rlim_cur >> 20
        ));
    }
    None
}

/// Give the calling thread SCHED_FIFO `priority` (0 = leave it normal) and pin it to
/// `cpu` (-1 = any: every CPU, also when the thread that started it was pinned, as the
/// GUI is by `[rt] gui_cpu`). Returns a warning saying what to change when refused.
pub fn set_this_thread(priority: u8, cpu: i32) -> Option<String> {
    let mut problems = Vec::new();
    if priority > 0 {
        let result = ThreadPriorityValue::try_from(priority)
            .map_err(|e| e.to_string())
            .and_then(|value| {
                set_thread_priority_and_policy(
                    thread_native_id(),
                    ThreadPriority::Crossplatform(value),
                    ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
                )
                .map_err(|e| format!("{e:?}"))
            });
        if let Err(e) = result {
            problems.push(format!(
                "real-time priority {priority} refused ({e}): give the program CAP_SYS_NICE (setcap cap_sys_nice+ep), an rtprio line in /etc/security/limits.conf, or set [rt] priorities to 0"
            ));
        }
    }
    if cpu >= 0 {
        // SAFETY: cpu_set_t is plain data; CPU_SET bounds are checked by the caller's range.
        let rc = unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            libc::CPU_SET(cpu as usize, &mut set);
            libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set)
        };
        if rc != 0 {
            problems.push(format!(
                "cannot pin to CPU {cpu} ({})",
                std::io::Error::last_os_error()
            ));
        }
    } else {
        unpin_this_thread();
    }
    (!problems.is_empty()).then(|| problems.join("; "))
}

/// Let the calling thread run on every CPU: a thread inherits its creator's CPUs.
pub fn unpin_this_thread() {
    // SAFETY: cpu_set_t is plain data; every bit set means every CPU the system has
    // (the kernel ignores CPUs that do not exist).
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for cpu in 0..libc::CPU_SETSIZE as usize {
            libc::CPU_SET(cpu, &mut set);
        }
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

/// Ask once, on a throw-away thread, whether the system grants `priority`.
pub fn priorities_allowed(rt: &RtSettings) -> Option<String> {
    let highest = rt
        .supervisor_priority
        .max(rt.steer_priority)
        .max(rt.camlink_priority);
    if highest == 0 {
        return None;
    }
    std::thread::spawn(move || set_this_thread(highest, -1))
        .join()
        .unwrap_or(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effective_capabilities_are_parsed() {
        let root = "Name:\tmechweed\nCapInh:\t0000000000000000\nCapEff:\t000001ffffffffff\n";
        let user = "Name:\tmechweed\nCapEff:\t0000000000000000\n";
        let ipc_lock_only = "CapEff:\t0000000000004000\n";
        assert!(capability_in(root, CAP_IPC_LOCK));
        assert!(!capability_in(user, CAP_IPC_LOCK));
        assert!(capability_in(ipc_lock_only, CAP_IPC_LOCK));
        assert!(!capability_in(ipc_lock_only, 13));
        assert!(!capability_in("garbage", CAP_IPC_LOCK));
    }

    #[test]
    fn overruns_are_counted_and_skipped_not_burst() {
        let mut p = Periodic::new(1000.0);
        p.wait();
        std::thread::sleep(std::time::Duration::from_millis(5));
        let before_done = monotonic_ns();
        p.done();
        assert!(p.stats.overruns >= 4, "{}", p.stats.overruns);
        // The next deadline lies ahead: no burst of ticks to catch up.
        assert!(p.next_ns > before_done);
    }
}

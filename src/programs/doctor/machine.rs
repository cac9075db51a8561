//! The kernel and the limits it sets the program: real-time priority (tried, not
//! guessed), locked memory, PREEMPT_RT, Secure Boot's lockdown, and the clock.

use std::path::{Path, PathBuf};

use super::{Check, Level};
use crate::config::{Backend, Settings};

/// The PC the doctor looks at: the root its /sys, /proc and /dev are under ("/" but in
/// the tests), and the clock's state (the kernel's, but in the tests).
pub struct Machine {
    pub root: PathBuf,
    /// Whether the system clock is synchronised to a time source (None: unknown).
    pub clock_synchronised: Option<bool>,
}

impl Machine {
    pub fn real() -> Machine {
        Machine {
            root: PathBuf::from("/"),
            clock_synchronised: kernel_clock_synchronised(),
        }
    }

    /// A system path ("/sys/...") under this machine's root.
    pub fn path(&self, system_path: &str) -> PathBuf {
        self.root.join(system_path.trim_start_matches('/'))
    }

    /// Whether this is the PC the program runs on (priorities and ports are tried here).
    pub fn is_this_pc(&self) -> bool {
        self.root == Path::new("/")
    }

    fn read(&self, system_path: &str) -> Option<String> {
        std::fs::read_to_string(self.path(system_path)).ok()
    }
}

pub(super) fn checks(m: &Machine, s: &Settings) -> Vec<Check> {
    let mut checks = Vec::new();
    if m.is_this_pc() {
        checks.push(priority(s));
        checks.push(memlock(s));
    }
    checks.push(kernel(m));
    checks.push(lockdown(m, s.backend));
    checks.push(clock(m.clock_synchronised));
    checks
}

/// SCHED_FIFO at the highest of [rt]'s priorities, tried on a thread of this process.
fn priority(s: &Settings) -> Check {
    let rt = &s.rt;
    let highest = rt
        .supervisor_priority
        .max(rt.steer_priority)
        .max(rt.camlink_priority);
    if highest == 0 {
        return Check::ok("rt_priority", "[rt] asks for no real-time priority");
    }
    match crate::rt::priorities_allowed(rt) {
        None => Check::ok(
            "rt_priority",
            format!("SCHED_FIFO {highest} granted (tried)"),
        ),
        Some(why) => Check::needed_on_cards(
            "rt_priority",
            s.backend,
            format!("SCHED_FIFO {highest} refused: {why}"),
            "run it as the mechweed service (LimitRTPRIO=90), or for a login shell add '@mechweed - rtprio 90' to /etc/security/limits.d/mechweed.conf; for the operator's desktop GUI: sudo /usr/share/mechweed/desktop-limits USER, then log in again",
        ),
    }
}

fn memlock(s: &Settings) -> Check {
    if !s.rt.lock_memory {
        return Check::ok("memlock", "[rt] lock_memory = no: memory is not locked");
    }
    match crate::rt::memlock_too_small() {
        None => Check::ok(
            "memlock",
            "the memory can be locked (memlock limit large enough)",
        ),
        Some(why) => Check::needed_on_cards(
            "memlock",
            s.backend,
            why,
            "the mechweed service has LimitMEMLOCK=infinity; for a login shell add '@mechweed - memlock unlimited' to /etc/security/limits.d/mechweed.conf",
        ),
    }
}

/// PREEMPT_RT gives tens of microseconds of lateness; a generic kernel, milliseconds now
/// and then under load.
fn kernel(m: &Machine) -> Check {
    let release = m.read("/proc/sys/kernel/osrelease").unwrap_or_default();
    let release = release.trim();
    let realtime = m
        .read("/sys/kernel/realtime")
        .is_some_and(|t| t.trim() == "1");
    // The RT throttle: -1 lets a runaway real-time thread freeze the PC; the default
    // (950000) keeps 5 % of each second for everything else.
    let throttle = m
        .read("/proc/sys/kernel/sched_rt_runtime_us")
        .map(|t| t.trim().to_string());
    let throttle_words = match throttle.as_deref() {
        Some("-1") => "; RT throttling off (sched_rt_runtime_us = -1)".to_string(),
        Some(us) => format!("; real-time threads get at most {us} us of each second"),
        None => String::new(),
    };
    if realtime {
        Check::ok("kernel", format!("{release}: PREEMPT_RT{throttle_words}"))
    } else {
        Check::new(
            "kernel",
            Level::Warning,
            format!(
                "{release}: not PREEMPT_RT: a tick can be late by milliseconds under load{throttle_words}"
            ),
            "install the real-time kernel (Debian: linux-image-rt-amd64) and boot it; the latency test below shows the difference",
        )
    }
}

/// Secure Boot's lockdown refuses both ways to the cards' registers.
fn lockdown(m: &Machine, backend: Backend) -> Check {
    match m.read("/sys/kernel/security/lockdown") {
        None => Check::ok("lockdown", "no kernel lockdown"),
        Some(text) if text.contains("[none]") => Check::ok("lockdown", "kernel lockdown: none"),
        Some(text) => Check::needed_on_cards(
            "lockdown",
            backend,
            format!(
                "the kernel is locked down ({}): it refuses the cards' registers",
                text.trim()
            ),
            "switch Secure Boot off in the firmware setup (mokutil --sb-state tells)",
        ),
    }
}

/// Rows, fixes and records are stamped: a clock that jumps later makes them disagree.
fn clock(synchronised: Option<bool>) -> Check {
    match synchronised {
        Some(true) => Check::ok("clock", "the system clock is synchronised"),
        Some(false) => Check::new(
            "clock",
            Level::Warning,
            "the system clock is not synchronised: records and the bus's stamps may be off, and jump when it is",
            "start a time service (systemd-timesyncd or chrony) with a time source the robot reaches; GNSS time where there is no network",
        ),
        None => Check::new(
            "clock",
            Level::Warning,
            "whether the system clock is synchronised could not be read",
            "timedatectl tells",
        ),
    }
}

/// The kernel's own word: adjtimex's STA_UNSYNC is clear while a time service keeps
/// the clock.
fn kernel_clock_synchronised() -> Option<bool> {
    // SAFETY: an all-zero timex with modes = 0 only reads the kernel's clock state.
    let mut timex: libc::timex = unsafe { std::mem::zeroed() };
    // SAFETY: adjtimex writes into the struct we own.
    let state = unsafe { libc::adjtimex(&mut timex) };
    (state >= 0).then_some(state != libc::TIME_ERROR && timex.status & libc::STA_UNSYNC == 0)
}

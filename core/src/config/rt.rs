//! [rt]: the threads' priorities, CPUs and locked memory, and the limits of the loops'
//! timing that the supervisor checks (heartbeats, overruns, a tick started late).

use super::RtSettings;
use super::reader::Reader;

pub(super) fn load(r: &mut Reader) -> RtSettings {
    let s = "rt";
    RtSettings {
        supervisor_priority: r.u64(s, "supervisor_priority", 0, 99) as u8,
        steer_priority: r.u64(s, "steer_priority", 0, 99) as u8,
        camlink_priority: r.u64(s, "camlink_priority", 0, 99) as u8,
        lock_memory: r.choice(s, "lock_memory", &["no", "yes"]) == 1,
        // A CPU number is whole: 1.7 is an error, not CPU 1. The range fits i32.
        supervisor_cpu: r.i64(s, "supervisor_cpu", -1, 1023) as i32,
        gui_cpu: r.i64(s, "gui_cpu", -1, 1023) as i32,
        // A stopped steer or camera-link thread leaves its last command standing: the
        // robot must not drive on it for more than about a second.
        heartbeat_timeout_s: r.f64(s, "heartbeat_timeout_s", 0.05, 1.0),
        // The GUI runs at normal priority and may stall a few frames on a loaded computer
        // (and a frame owed stops its beat until drawn); it holds the HALT button but
        // not the driving (the e-stops are wired), so it may take up to 5 s.
        gui_heartbeat_timeout_s: r.f64(s, "gui_heartbeat_timeout_s", 0.1, 5.0),
        max_overruns: r.u64(s, "max_overruns", 0, 1_000_000) as u32,
        overrun_window_s: r.f64(s, "overrun_window_s", 0.1, 3600.0),
        max_late_periods: r.f64(s, "max_late_periods", 1.0, 100.0),
    }
}

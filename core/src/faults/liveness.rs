//! The controller's own health, checked each tick: its threads alive and beating, and
//! the supervisor's own ticks on time.

use super::{CheckContext, FaultChecks};
use crate::rt::health::ThreadName;
use crate::state::fault_cause::FaultCause;

/// A thread's first beat may come this late after the controller starts, s: on a busy
/// computer a new thread waits to be scheduled, to take its priority and to finish its
/// first tick, longer than a heartbeat. Until it beats nothing it would send is used: the
/// supervisor takes a steer command only in the mode it was made for, rows once they come.
pub(super) const FIRST_BEAT_S: f64 = 3.0;

impl FaultChecks {
    /// The other threads: none panicked, each started and still beating.
    pub(super) fn threads(&self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        // Threads: a panic anywhere, or a thread that stops beating, is a fault; the
        // steer thread beats with each command, the camera link with each status.
        if let Some(thread) = c.health.panicked {
            report(FaultCause::ThreadPanicked { thread });
        }
        let beats = [
            (ThreadName::Steer, Some(c.steer.t_s)),
            (ThreadName::CameraLink, Some(c.link.beat_s)),
            (ThreadName::Gui, c.health.gui_beat_s),
        ];
        for (thread, beat_s) in beats {
            let Some(beat_s) = beat_s else { continue };
            // The robot's time starts with the controller, so a beat at 0 is none yet.
            // The GUI thread runs at normal priority and draws with the processor: it
            // gets its own, longer time-out.
            let started = beat_s > 0.0;
            let timeout_s = match thread {
                _ if !started => FIRST_BEAT_S,
                ThreadName::Gui => self.rt.gui_heartbeat_timeout_s,
                _ => self.rt.heartbeat_timeout_s,
            };
            let for_s = now - beat_s;
            if for_s > timeout_s {
                let stopped = FaultCause::ThreadStopped {
                    thread,
                    for_s,
                    started,
                };
                report(stopped);
            }
        }
    }

    /// The supervisor's own timing: no stalled tick, no burst of overruns.
    pub(super) fn timing(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        // One stall is enough: for that long the amplifiers drove unwatched.
        let late_s = c.tick_gap_s - self.period_s;
        let limit_s = self.rt.max_late_periods * self.period_s;
        if late_s > limit_s {
            report(FaultCause::LateTick {
                late_ms: late_s * 1e3,
                limit_ms: limit_s * 1e3,
                load: c.health.cpu_load,
            });
        }

        // Deadline overruns: a few are tolerated, a burst means an overloaded computer.
        let new_overruns = c
            .health
            .supervisor_overruns
            .saturating_sub(self.overruns_seen);
        self.overruns_seen = c.health.supervisor_overruns;
        for _ in 0..new_overruns.min(self.rt.max_overruns as u64 + 1) {
            if self.overrun_times_s.len() > self.rt.max_overruns as usize {
                self.overrun_times_s.pop_front();
            }
            self.overrun_times_s.push_back(now);
        }
        if self.overrun_times_s.len() > self.rt.max_overruns as usize
            && let Some(&oldest) = self.overrun_times_s.front()
            && now - oldest <= self.rt.overrun_window_s
        {
            report(FaultCause::Overruns {
                count: self.overrun_times_s.len() as u32,
                window_s: self.rt.overrun_window_s,
                load: c.health.cpu_load,
            });
        }
    }
}

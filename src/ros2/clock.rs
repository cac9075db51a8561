//! The robot's run clock on its wall clock, for stamps: each status says when it was
//! published (`wall_s`) and at which supervisor time (`t_s`); their difference is the
//! offset, plus the status's wait before publishing. The least offset of the last few
//! seconds is taken: a wait only adds to it, and a robot whose wall clock steps (NTP
//! after boot) is followed within a window. A robot program that starts again begins a
//! new run clock, seen as a time well before the last.

use std::collections::VecDeque;

/// Statuses the least offset is taken over: 5 s of the robot's 10 a second.
const WINDOW: usize = 50;
/// A time this much before the last one seen is a new run, s. Ticks reach the bridge
/// up to a queue's drain after the status of the same moment.
const RESTART_S: f64 = 1.0;

#[derive(Debug, Default)]
pub struct RobotClock {
    offsets_s: VecDeque<f64>,
    last_t_s: Option<f64>,
}

impl RobotClock {
    /// A time of the robot's run clock seen: a new run when well before the last.
    fn seen(&mut self, t_s: f64) {
        if self.last_t_s.is_some_and(|last| t_s < last - RESTART_S) {
            self.offsets_s.clear();
            self.last_t_s = None;
        }
        self.last_t_s = Some(self.last_t_s.map_or(t_s, |last| last.max(t_s)));
    }

    /// A status published at `wall_s` (s since 1970) for the supervisor time `t_s`.
    pub fn status(&mut self, t_s: f64, wall_s: f64) {
        self.seen(t_s);
        if self.offsets_s.len() == WINDOW {
            self.offsets_s.pop_front();
        }
        self.offsets_s.push_back(wall_s - t_s);
    }

    /// A tick's time: a new run shows in the ticks as soon as in the statuses.
    pub fn tick(&mut self, t_s: f64) {
        if t_s.is_finite() {
            self.seen(t_s);
        }
    }

    /// `t_s` on the robot's wall clock, s since 1970; None until a status of this run.
    pub fn wall_s(&self, t_s: f64) -> Option<f64> {
        let least = self.offsets_s.iter().copied().reduce(f64::min)?;
        t_s.is_finite().then_some(least + t_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_offset_is_taken_and_a_wait_before_publishing_adds_nothing() {
        let mut clock = RobotClock::default();
        assert_eq!(clock.wall_s(1.0), None);
        clock.status(10.0, 1010.5);
        clock.status(10.1, 1010.9);
        assert_eq!(clock.wall_s(10.25), Some(1010.75));
        assert_eq!(clock.wall_s(f64::NAN), None);
    }

    #[test]
    fn a_step_of_the_robots_wall_clock_is_followed_within_the_window() {
        let mut clock = RobotClock::default();
        for i in 0..WINDOW {
            clock.status(i as f64 * 0.1, 1000.0 + i as f64 * 0.1);
        }
        // NTP steps the robot's clock 30 s forward.
        for i in WINDOW..2 * WINDOW {
            clock.status(i as f64 * 0.1, 1030.0 + i as f64 * 0.1);
        }
        assert_eq!(clock.wall_s(20.0), Some(1050.0));
    }

    #[test]
    fn a_robot_that_starts_again_has_no_offset_until_its_first_status() {
        let mut clock = RobotClock::default();
        clock.status(600.0, 1600.0);
        // A tick of the new run, before its first status.
        clock.tick(0.2);
        assert_eq!(clock.wall_s(0.2), None);
        clock.status(0.3, 1700.3);
        assert_eq!(clock.wall_s(0.4), Some(1700.4));
        // A tick a little older than the status is the same run.
        clock.tick(0.25);
        assert_eq!(clock.wall_s(0.25), Some(1700.25));
    }
}

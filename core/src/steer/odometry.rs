//! The robot's own motion over the last seconds, from odometry at each steer tick: the
//! distance its wheels drove and the heading its steering turned. It says how far the
//! robot moved since a camera image was taken, to bring the row seen then to now.

use super::filter::Travel;
use crate::state::measure::Measured;

/// Steer ticks kept: at the shipped 10 Hz and as many estimates a second, about 50 s,
/// longer than a gap in the row is held (camera_hold.rs) at any speed the robot weeds
/// at; at the highest [steer] rate_hz, 200, about 5 s. An image older than the ticks kept
/// is not steered by when repeated (sources.rs).
const HISTORY: usize = 1024;

/// Odometry at one steer tick: time, distance driven, heading turned.
#[derive(Debug, Clone, Copy, Default)]
struct Pose {
    t_s: f64,
    distance_m: f64,
    heading_rad: f64,
}

#[derive(Debug, Clone)]
pub(crate) struct OdometryHistory {
    poses: [Pose; HISTORY],
    newest: usize,
    filled: usize,
}

impl Default for OdometryHistory {
    fn default() -> OdometryHistory {
        OdometryHistory {
            poses: [Pose::default(); HISTORY],
            newest: 0,
            filled: 0,
        }
    }
}

impl OdometryHistory {
    /// Forget every tick (entering autonomous mode).
    pub fn clear(&mut self) {
        self.filled = 0;
    }

    /// Keep the odometry of the tick at `now_s`, and return the motion since the last
    /// tick (None for the first).
    pub fn remember(&mut self, now_s: f64, m: &Measured) -> Option<Travel> {
        let last = self.poses[self.newest];
        let dt_s = (now_s - last.t_s).max(0.0);
        let now = Pose {
            t_s: now_s,
            distance_m: m.distance_m,
            heading_rad: match self.filled {
                0 => 0.0,
                _ => last.heading_rad + m.yaw_rate_rps * dt_s,
            },
        };
        self.newest = (self.newest + 1) % HISTORY;
        self.poses[self.newest] = now;
        self.filled = (self.filled + 1).min(HISTORY);
        (self.filled > 1).then(|| between(&last, &now))
    }

    /// The motion from `t_s` to the newest tick; from the oldest tick kept if `t_s` is
    /// older, and then also `false`.
    pub fn since(&self, t_s: f64) -> (Travel, bool) {
        let newest = self.poses[self.newest];
        let mut later = newest;
        for back in 1..self.filled {
            let earlier = self.poses[(self.newest + HISTORY - back) % HISTORY];
            if earlier.t_s <= t_s {
                let span_s = later.t_s - earlier.t_s;
                let k = if span_s > 0.0 {
                    (t_s - earlier.t_s) / span_s
                } else {
                    0.0
                };
                let then = Pose {
                    t_s,
                    distance_m: earlier.distance_m + k * (later.distance_m - earlier.distance_m),
                    heading_rad: earlier.heading_rad
                        + k * (later.heading_rad - earlier.heading_rad),
                };
                return (between(&then, &newest), true);
            }
            later = earlier;
        }
        (between(&later, &newest), later.t_s <= t_s)
    }
}

fn between(then: &Pose, now: &Pose) -> Travel {
    Travel {
        travelled_m: now.distance_m - then.distance_m,
        turned_rad: now.heading_rad - then.heading_rad,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(history: &mut OdometryHistory, t_s: f64, distance_m: f64, yaw_rate_rps: f64) {
        let m = Measured {
            distance_m,
            yaw_rate_rps,
            ..Measured::default()
        };
        history.remember(t_s, &m);
    }

    #[test]
    fn the_motion_since_a_moment_between_ticks_is_interpolated() {
        let mut h = OdometryHistory::default();
        // 1 m/s, turning at 0.1 rad/s from t = 1 s (the heading integrates the rate
        // measured at each tick over the interval before it).
        for k in 0..=10 {
            let t = k as f64 * 0.1;
            at(&mut h, t, t, if t > 0.95 { 0.1 } else { 0.0 });
        }
        at(&mut h, 1.1, 1.1, 0.1);
        at(&mut h, 1.2, 1.2, 0.1);
        let (since, known) = h.since(0.85);
        assert!(known);
        assert!((since.travelled_m - 0.35).abs() < 1e-9, "{since:?}");
        // Turned 0.01 rad in each of the intervals ending at 1.0 (its rate 0.1), 1.1 and 1.2 s.
        assert!((since.turned_rad - 0.03).abs() < 1e-9, "{since:?}");
    }

    #[test]
    fn a_moment_before_the_oldest_tick_is_not_known() {
        let mut h = OdometryHistory::default();
        for k in 0..(HISTORY + 10) {
            let t = k as f64 * 0.1;
            at(&mut h, t, t * 0.5, 0.0);
        }
        let oldest_s = 10.0 * 0.1;
        let (since, known) = h.since(oldest_s - 0.5);
        assert!(!known);
        let newest_s = (HISTORY + 9) as f64 * 0.1;
        assert!((since.travelled_m - (newest_s - oldest_s) * 0.5).abs() < 1e-9);
        let (_, known) = h.since(oldest_s + 0.05);
        assert!(known);
        h.clear();
        at(&mut h, 100.0, 50.0, 0.0);
        assert!(!h.since(99.0).1, "cleared");
    }

    #[test]
    fn the_first_tick_gives_no_motion_and_the_next_the_step() {
        let mut h = OdometryHistory::default();
        let first = h.remember(0.0, &Measured::default());
        assert_eq!(first, None);
        let m = Measured {
            distance_m: 0.2,
            yaw_rate_rps: 0.5,
            ..Measured::default()
        };
        let step = h.remember(0.1, &m).expect("a step");
        assert!((step.travelled_m - 0.2).abs() < 1e-12);
        assert!((step.turned_rad - 0.05).abs() < 1e-12);
    }
}

//! The steering law replayed beside the supervisor: the steer thread's core given, at
//! each recorded steer command's time, the status the supervisor had published before
//! it and the camera estimate the link had then, its command compared with the
//! recorded one.
//!
//! Not exact, and why: the record is written once per supervisor tick, so it holds
//! the last steer command of each 10 ms, not every one. When the steer thread ran twice
//! between two supervisor ticks (a camera frame woke it just before its own 10 Hz
//! tick) the first command is not in the record, yet it moved the law's filters and
//! integral; and which status the thread copied, the one published just before it or
//! the one before that, is decided by microseconds the record does not keep. The
//! commands are therefore compared within a tolerance, and the count beyond it said.

use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerSettings};
use crate::gnss::GnssStatus;
use crate::state::status::Status;
use crate::steer::{SteerCommand, SteerCore};

/// Commands within this of the recorded count as the same.
pub const ANGLE_TOLERANCE_DEG: f64 = 0.1;
pub const SPEED_TOLERANCE_MPS: f64 = 0.001;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct SteerFigures {
    /// Steer commands compared.
    pub commands: usize,
    pub max_angle_diff_deg: f64,
    pub max_speed_diff_mps: f64,
    /// Commands beyond the tolerance.
    pub beyond: usize,
    /// The first of them: (time, recorded deg, replayed deg).
    pub first_beyond: Option<(f64, f64, f64)>,
}

pub(crate) struct SteerReplay {
    core: SteerCore,
    last_t_s: f64,
    /// The status published after the previous supervisor tick, and its link.
    published: Status,
    link_before: LinkStatus,
    pub figures: SteerFigures,
}

impl SteerReplay {
    pub fn new(settings: &Settings) -> SteerReplay {
        SteerReplay {
            core: SteerCore::new(settings),
            last_t_s: f64::NEG_INFINITY,
            published: Status::default(),
            link_before: LinkStatus::default(),
            figures: SteerFigures::default(),
        }
    }

    /// New steering-law parameters, accepted by the supervisor.
    pub fn settings(&mut self, s: &SteerSettings) {
        self.core.set_law_settings(s);
    }

    /// Before supervisor tick `recorded`: if it saw a new steer command, make it again
    /// and compare. `in_window`: compare (else only run the law).
    pub(crate) fn before_tick(
        &mut self,
        recorded: &SteerCommand,
        link: &LinkStatus,
        in_window: bool,
    ) {
        let t_s = recorded.t_s;
        if t_s <= self.last_t_s || t_s <= 0.0 {
            return;
        }
        self.last_t_s = t_s;
        // The estimate the link had at the steer tick: this tick's, unless it came later.
        let link = if link.last_usable_s <= t_s {
            link
        } else {
            &self.link_before
        };
        // Records hold no GNSS fixes yet: the camera's steering is replayed.
        let again = self
            .core
            .tick(t_s, &self.published, link, &GnssStatus::default());
        if !in_window {
            return;
        }
        let f = &mut self.figures;
        f.commands += 1;
        let angle_deg = (again.wheel_angle_rad - recorded.wheel_angle_rad)
            .to_degrees()
            .abs();
        let speed = (again.speed_mps - recorded.speed_mps).abs();
        f.max_angle_diff_deg = f.max_angle_diff_deg.max(angle_deg);
        f.max_speed_diff_mps = f.max_speed_diff_mps.max(speed);
        if angle_deg > ANGLE_TOLERANCE_DEG || speed > SPEED_TOLERANCE_MPS {
            f.beyond += 1;
            let degrees = (
                recorded.wheel_angle_rad.to_degrees(),
                again.wheel_angle_rad.to_degrees(),
            );
            f.first_beyond.get_or_insert((t_s, degrees.0, degrees.1));
        }
    }

    /// After supervisor tick: what it published, and the link it was given.
    pub(crate) fn after_tick(&mut self, status: &Status, link: &LinkStatus) {
        self.published = *status;
        self.link_before = *link;
    }
}

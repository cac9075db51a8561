//! The simulated robot, field and camera computer (the [sim] settings in config/robot.ini).
//!
//! [`SimRobot`] is the plant on simulated time: the controller (or a test) calls
//! `advance_to` and reads sensors and truth in lockstep. [`SimHw`] is the same plant on
//! the wall clock, behind the [`crate::Hw`] trait, for running the real controller.
//!
//! One file per idea: `drive` (a drive wheel and its brake), `steering` (the steered
//! wheel and its sensors), `body` (the bicycle model), `field` (the row), `tool` (the
//! tool's path along the row), `sight` (what the camera sees), `camera` (the camera
//! computer), `robot` (all of it together; `robot_events`, what the scripted events do
//! to it; `miswire`, how it is wired), `realtime` (on the wall clock), plus `params`,
//! `events`, `pipe`, `crosstrack` (the plant's figures) and `crosstrack_ticks` (a run's,
//! from its ticks); `field_tier` adds what real fields add.

pub mod camera;
pub mod crosstrack;
pub mod crosstrack_ticks;
pub mod events;
pub mod field;
pub mod field_map;
pub mod field_tier;
pub mod gauss_markov;
pub mod gnss;
pub mod gnss_model;
pub mod miswire;
pub mod params;
pub mod pipe;

mod body;
mod drive;
mod realtime;
mod robot;
mod sight;
mod steering;
mod tool;

#[cfg(test)]
pub(crate) mod alloc_tests;

pub use crosstrack::{CrossTrackStats, CrossTrackSummary, SAMPLE_SPACING_M};
pub use crosstrack_ticks::TickCrossTrack;
pub use events::{ActionHelp, EventAction, OperatorMode, SimEvent, action_list, parse_events};
pub use miswire::Miswire;
pub use params::{CROSS_TRACK_FROM_M, FieldKind, FieldTierParams, RowShape, SimParams};
pub use pipe::{PipeEnd, byte_pipe};
pub use realtime::{SimControl, SimHw, TruthHandle};
pub use robot::SimRobot;

/// Each random subsystem draws from its own stream, seeded with `seed + offset`, so that
/// changing one subsystem does not shift another's noise.
const SEED_PLANTS: u64 = 1;
const SEED_POT: u64 = 2;
const SEED_CAMERA_NOISE: u64 = 3;
const SEED_CAMERA_TIMING: u64 = 4;
const SEED_CAMERA_CORRUPT: u64 = 5;
const SEED_FIELD: u64 = 6;
const SEED_CAMERA_BIAS: u64 = 7;
const SEED_MAP: u64 = 8;

/// Ground truth for tests, reports and the GUI.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Truth {
    pub t_s: f64,
    /// Rear axle centre in the field frame, m.
    pub x_m: f64,
    pub y_m: f64,
    /// Heading in the field frame, rad (counter-clockwise from +x, not wrapped).
    pub heading_rad: f64,
    /// (v_left + v_right) / 2.
    pub speed_mps: f64,
    /// Steered wheel angle, rad (positive = left).
    pub wheel_angle_rad: f64,
    pub v_left_mps: f64,
    pub v_right_mps: f64,
    /// The tool point's offset from the row's centre line, m; positive = tool is LEFT of the row.
    pub tool_cross_track_m: f64,
    /// Travelled by the rear axle centre, m.
    pub distance_m: f64,
    /// The tool point has passed the end of the row.
    pub row_done: bool,
}

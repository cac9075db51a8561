//! What the fault checks look at each tick (mod.rs), gathered by the supervisor.

use mechweed_hw::{Inputs, Side};

use crate::camlink::LinkStatus;
use crate::rt::health::ThreadHealth;
use crate::state::measure::Measured;
use crate::state::modes::Mode;
use crate::state::status::PowerState;
use crate::steer::SteerCommand;

/// What the checks look at, gathered by the supervisor each tick.
pub struct CheckContext<'a> {
    pub now_s: f64,
    /// Time since the previous supervisor tick, s (one period on the first tick).
    pub tick_gap_s: f64,
    pub mode: Mode,
    /// When the current mode was entered, s.
    pub mode_since_s: f64,
    pub power: PowerState,
    pub inputs: &'a Inputs,
    pub measured: &'a Measured,
    /// Amplifier voltages written last tick: left, right, steering.
    pub driven_v: [f64; 3],
    /// The motor contactor's relay as written last tick (true = commanded closed).
    pub relay_closed: bool,
    /// The drive wheels' brakes as written last tick (true = released): left, right.
    pub brakes_released: [bool; 2],
    /// The speed each drive wheel was asked to move at last tick, m/s: its reference
    /// while driving; in Test, what the panel's voltage gives with the brake released.
    pub expected_mps: [f64; 2],
    /// Encoder counts moved since last tick: left, right, steering.
    pub counts_moved: [bool; 3],
    /// An end switch closed while driving, and when (latched by the supervisor).
    pub endswitch_hit: Option<(Side, f64)>,
    pub steer: &'a SteerCommand,
    pub link: &'a LinkStatus,
    pub health: &'a ThreadHealth,
}

/// Starts a timer when `condition` becomes true; returns how long it has been true.
pub(super) fn held_for(timer: &mut Option<f64>, condition: bool, now_s: f64) -> f64 {
    if !condition {
        *timer = None;
        return 0.0;
    }
    now_s - *timer.get_or_insert(now_s)
}

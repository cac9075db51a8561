//! When the operator GUI draws a frame. A frame costs a computer without a graphics
//! driver (software rendering) tens of milliseconds of CPU time, so the GUI draws only
//! when something it shows has changed, at a rate that fits what changed:
//!
//! 1. operator input (a click, a key): at once (egui itself asks for that frame);
//! 2. a change the operator must see at once (mode, fault, power, an e-stop, the
//!    dead-man, the camera link's state, a notice, a silent controller, each further
//!    second a watched robot stays silent): at the next look, within `LOOK_S`;
//! 3. any other value: every `MOVING_S` while the robot may move (numbers ten times a
//!    second are enough for a person), every `PLOTS_MOVING_S` on the Plots tab, and
//!    every `STANDING_S` while it stands (loop figures, counters);
//! 4. nothing changed: no frame at all.
//!
//! The pacer thread looks at the controller every `LOOK_S` and asks for the frames;
//! `Pace` is its decision, kept apart from the thread so it can be tested with views
//! and times made by hand.
//!
//! The GUI's heartbeat comes from the same look: the GUI is alive while every frame
//! asked for has begun (its pass has run). While one is owed the pacer does not beat, so
//! a GUI thread that hangs stops the beat at the next frame asked of it (within 0.2 s
//! while the robot may move, 1 s standing) and the supervisor faults
//! `[rt] gui_heartbeat_timeout_s` later.

use std::hash::{DefaultHasher, Hasher};

use super::app::Tab;
use super::header::SUPERVISOR_SILENT_S;
use super::view::View;
use crate::bus::BusState;
use crate::camlink::{LinkProblem, OpenStep};
use crate::state::fault_cause::FaultCause;
use crate::state::modes::Mode;
use crate::state::status::{FaultRecord, Notice, PowerState};
use mechweed_hw::Side;

/// The pacer looks this often, s (also the plots' sample period).
pub(crate) const LOOK_S: f64 = 1.0 / 30.0;
/// Frame period for values while the robot may move, on the Plots tab, and standing, s.
pub(crate) const MOVING_S: f64 = 0.1;
pub(crate) const PLOTS_MOVING_S: f64 = 0.2;
pub(crate) const STANDING_S: f64 = 1.0;

/// What must show at once when it changes.
#[derive(Debug, Clone, PartialEq)]
struct AtOnce {
    mode: Mode,
    fault: Option<FaultRecord>,
    power: PowerState,
    standing_cause: Option<FaultCause>,
    notice: Option<Notice>,
    endswitch_hit: Option<Side>,
    /// E-stops front and back, motor power, dead-man, end switches left and right.
    switches: [bool; 6],
    /// Main power relay, brakes left and right, tool.
    relays: [bool; 4],
    calibrated: bool,
    link: (Option<LinkProblem>, Option<OpenStep>, bool, bool),
    bus: BusState,
    /// The supervisor's first tick: the operator script starts from it.
    started: bool,
    controller_silent: bool,
    /// Watching over the bus: whole seconds without a status while stale (the header
    /// counts them, so a frame each second), the robot's fault in words.
    remote_silent_s: Option<u64>,
    remote_fault: bool,
    /// The gamepad connected, and its dead-man counting as held.
    gamepad: Option<(bool, bool)>,
}

impl AtOnce {
    fn of(view: &View) -> AtOnce {
        let st = &view.status;
        let (i, o) = (&st.inputs, &st.outputs);
        AtOnce {
            mode: st.mode,
            fault: st.fault,
            power: st.power,
            standing_cause: st.standing_cause,
            notice: st.notice,
            endswitch_hit: st.endswitch_hit,
            switches: [
                i.estop_front_released,
                i.estop_back_released,
                i.motor_power_present,
                i.joystick_enable,
                i.end_switch_left,
                i.end_switch_right,
            ],
            relays: [
                o.main_power_on,
                o.brake_release_left,
                o.brake_release_right,
                o.tool_on,
            ],
            calibrated: st.measured.calibrated,
            link: (
                view.link.problem,
                view.link.opening,
                view.link.streaming,
                view.link.connected,
            ),
            bus: view.bus.state,
            started: st.tick > 0,
            controller_silent: st.tick > 0 && view.now_s - st.t_s > SUPERVISOR_SILENT_S,
            remote_silent_s: view.remote.as_ref().and_then(|link| link.silent_whole_s()),
            remote_fault: view
                .remote
                .as_ref()
                .is_some_and(|link| link.fault.is_some()),
            gamepad: (view.gamepad.as_ref())
                .map(|pad| (pad.state.pad.connected, pad.joystick.enable)),
        }
    }
}

/// A fingerprint of every value in the view but the clock's `now_s` (NaN included:
/// a value that stays NaN is no change).
fn values_key(view: &View) -> u64 {
    struct HashWriter(DefaultHasher);
    impl std::fmt::Write for HashWriter {
        fn write_str(&mut self, s: &str) -> std::fmt::Result {
            self.0.write(s.as_bytes());
            Ok(())
        }
    }
    let mut w = HashWriter(DefaultHasher::new());
    let _ = std::fmt::write(
        &mut w,
        format_args!(
            "{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
            view.status, view.link, view.steer, view.loops, view.truth, view.bus, view.simulated
        ),
    );
    w.0.finish()
}

/// The robot may move: values change fast.
fn may_move(view: &View) -> bool {
    let st = &view.status;
    st.mode.drives() || st.mode == Mode::Test || st.measured.speed_mps.abs() > 0.01
}

/// The frame period that fits what the view shows on `tab`, s.
pub(crate) fn period_s(view: &View, tab: Tab) -> f64 {
    match (may_move(view), tab) {
        (true, Tab::Plots) => PLOTS_MOVING_S,
        (true, _) => MOVING_S,
        (false, _) => STANDING_S,
    }
}

/// What the pacer should do after a look.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Look {
    /// Ask the GUI thread for a frame now.
    pub draw: bool,
    /// Every frame asked for has been drawn: beat for the GUI.
    pub beat: bool,
}

/// The pacer's memory: what the last frame asked for was to show, and whether it came.
#[derive(Debug, Default)]
pub struct Pace {
    shown: Option<(AtOnce, u64, Tab)>,
    /// The GUI's pass count when the owed frame was asked for.
    owed_after_pass: Option<u64>,
    last_ask_s: f64,
}

impl Pace {
    /// Look at `view` (the controller now) with `tab` shown, after the GUI thread has
    /// run `passes` passes, at `t_s` on the pacer's clock.
    pub fn look(&mut self, view: &View, tab: Tab, passes: u64, t_s: f64) -> Look {
        if self.owed_after_pass.is_some_and(|p| passes > p) {
            self.owed_after_pass = None;
        }
        if self.owed_after_pass.is_some() {
            // One frame at a time: the one asked for will show the newest view.
            return Look {
                draw: false,
                beat: false,
            };
        }
        let now = (AtOnce::of(view), values_key(view), tab);
        let draw = match &self.shown {
            None => true,
            Some((at_once, _, shown_tab)) if *at_once != now.0 || *shown_tab != tab => true,
            Some((_, values, _)) if *values != now.1 => {
                t_s - self.last_ask_s >= period_s(view, tab) - LOOK_S / 2.0
            }
            Some(_) => false,
        };
        if draw {
            self.shown = Some(now);
            self.owed_after_pass = Some(passes);
            self.last_ask_s = t_s;
        }
        Look { draw, beat: true }
    }
}

#[cfg(test)]
#[path = "pace_tests.rs"]
mod tests;

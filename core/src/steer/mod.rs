//! The steer thread's work, as a plain tick function: in autonomous mode the steering
//! law turns the camera's row estimate into a wheel angle; in joystick mode the
//! joystick gives speed and angle; while driving, an end switch starts the end-switch
//! procedure. It runs at [steer] rate_hz and on every new camera estimate.

mod camera_hold;
pub mod endswitch;
pub mod filter;
mod filter_config;
mod fix_checks;
pub mod joystick;
pub mod law;
mod law_lqr;
pub(crate) mod lqr;
mod odometry;
mod receiver;
pub mod sources;

use mechweed_hw::Side;

use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerLaw, SteerSettings};
use crate::gnss::GnssStatus;
use crate::gnss::place::RowPlace;
use crate::state::measure::Measured;
use crate::state::modes::Mode;
use crate::state::status::Status;
use endswitch::EndSwitchProcedure;
pub use endswitch::EndSwitchState;
use law::{LawOutput, Motion, RowFollower};
use law_lqr::LqrLaw;
use sources::RowSources;
pub use sources::{FilterFigures, RowFigures, SourceHealth, Steering};

/// What the steer thread asks of the supervisor, published after every tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SteerCommand {
    /// When this command was made, s (the supervisor watches that it keeps coming).
    pub t_s: f64,
    /// The mode it was made for: the supervisor uses it in that mode only.
    pub mode: Mode,
    pub speed_mps: f64,
    pub wheel_angle_rad: f64,
    /// The camera link should stream row frames: while driving, so that switching
    /// from joystick to autonomous finds a fresh estimate at hand.
    pub wants_rows: bool,
    pub endswitch: EndSwitchState,
    pub endswitch_done_count: u32,
    pub endswitch_last_side: Option<Side>,
    /// The steering law's workings, for plots (zero outside autonomous mode).
    pub law: LawOutput,
    /// Which sensors steer (autonomous mode), and since when each has been lost.
    pub sources: SourceHealth,
    /// The GNSS fix and the row filter's estimate, for the operator and the record.
    pub row: RowFigures,
}

pub struct SteerCore {
    settings: Settings,
    law: RowFollower,
    lqr: LqrLaw,
    rows: RowSources,
    endswitch: EndSwitchProcedure,
    last_mode: Mode,
}

impl SteerCore {
    /// Without a row map: the camera steers ([steer] source = camera).
    pub fn new(settings: &Settings) -> SteerCore {
        SteerCore::with_map(settings, None)
    }

    /// With the row map seen from the robot, for GNSS ([steer] source = gnss or fused).
    pub fn with_map(settings: &Settings, place: Option<RowPlace>) -> SteerCore {
        SteerCore {
            settings: settings.clone(),
            law: RowFollower::new(&settings.steer, &settings.robot),
            lqr: LqrLaw::new(settings),
            rows: RowSources::new(settings, place),
            endswitch: EndSwitchProcedure::default(),
            last_mode: Mode::Halt,
        }
    }

    /// New steering-law parameters (sent by the supervisor, which takes them only in
    /// Halt). The thread's rate and the end-switch procedure's angle stay as at start:
    /// the rate is the thread's period, and the supervisor limits angles with the other.
    pub fn set_law_settings(&mut self, new: &SteerSettings) {
        let s = &mut self.settings.steer;
        *s = SteerSettings {
            rate_hz: s.rate_hz,
            endswitch_back_deg: s.endswitch_back_deg,
            ..*new
        };
        self.law = RowFollower::new(s, &self.settings.robot);
        self.lqr.retune(&self.settings);
    }

    /// The steering-law parameters in use.
    pub fn law_settings(&self) -> SteerSettings {
        self.settings.steer
    }

    /// The row filter and which sensors steer.
    pub fn rows(&self) -> &RowSources {
        &self.rows
    }

    /// One steer tick at `now_s`, from the supervisor's, the camera link's and the GNSS
    /// link's latest state.
    pub fn tick(
        &mut self,
        now_s: f64,
        sup: &Status,
        link: &LinkStatus,
        gnss: &GnssStatus,
    ) -> SteerCommand {
        let mode = sup.mode;
        self.follow_mode(mode, now_s);
        let m = &sup.measured;
        if mode == Mode::Autonomous {
            self.rows.watch(now_s, m, link);
        }
        let mut law_output = LawOutput::default();
        let procedure = if mode.drives() {
            self.endswitch.tick(
                sup.endswitch_hit,
                &sup.inputs,
                m.speed_mps,
                m.wheel_angle_rad,
                // The procedure's angle is limited on its own, inside the robot's.
                self.settings
                    .steer
                    .endswitch_back_deg
                    .min(self.settings.robot.max_wheel_angle_deg),
                now_s,
            )
        } else {
            None
        };
        let (speed_mps, wheel_angle_rad) = match (procedure, mode) {
            (Some(command), _) => command,
            (None, Mode::Joystick) => {
                joystick::command(&sup.inputs, &self.settings.joystick, m.wheel_angle_rad)
            }
            (None, Mode::Autonomous) => {
                let (command, law) = self.follow_row(now_s, m, link, gnss);
                law_output = law;
                command
            }
            (None, _) => (0.0, m.wheel_angle_rad),
        };
        SteerCommand {
            t_s: now_s,
            mode,
            speed_mps,
            wheel_angle_rad,
            wants_rows: mode.drives(),
            endswitch: self.endswitch.state,
            endswitch_done_count: self.endswitch.done_count,
            endswitch_last_side: self.endswitch.last_side,
            law: law_output,
            sources: self.rows.health(),
            row: self.rows.figures(gnss),
        }
    }

    /// A new mode: autonomous starts its law and its row sources afresh; standing ends
    /// an end-switch procedure.
    fn follow_mode(&mut self, mode: Mode, now_s: f64) {
        if mode == self.last_mode {
            return;
        }
        if mode == Mode::Autonomous {
            self.law.reset();
            self.lqr.reset();
            self.rows.reset(now_s);
        }
        if !mode.drives() {
            self.endswitch.cancel();
        }
        self.last_mode = mode;
    }

    /// Autonomous: the row as the sources see it, and the steering law's wheel angle for
    /// it; (speed, wheel angle) and the law's figures.
    fn follow_row(
        &mut self,
        now_s: f64,
        m: &Measured,
        link: &LinkStatus,
        gnss: &GnssStatus,
    ) -> ((f64, f64), LawOutput) {
        let speed_mps = self.settings.steer.speed_mps;
        match self.rows.tick(now_s, m, link, gnss, speed_mps) {
            Some(row) => {
                let motion = Motion {
                    speed_mps: m.speed_mps,
                    yaw_rate_rps: m.yaw_rate_rps,
                    wheel_angle_rad: m.wheel_angle_rad,
                };
                let law = match self.settings.steer.law {
                    SteerLaw::Lqr => (self.lqr).update(&self.rows.filter().state(), now_s, &motion),
                    SteerLaw::Pursuit => {
                        (self.law).update_moved(&row.estimate, row.since, now_s, &motion)
                    }
                };
                ((row.speed_mps, law.wheel_angle_rad), law)
            }
            // No fresh estimate yet (or any more): do not drive blind. The supervisor
            // faults if this lasts beyond the camera's link time-out.
            None => ((0.0, m.wheel_angle_rad), LawOutput::default()),
        }
    }
}

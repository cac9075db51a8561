//! The supervisor: once per tick (100 Hz) it takes every input, checks every fault,
//! runs the three regulators and decides every output. It is a plain state machine:
//! the real-time thread (threads/supervisor.rs, started by the program's src/run/)
//! and the lockstep simulation (threads/lockstep.rs) both call `tick`, so there is
//! one copy of the control logic.
//!
//! Modes: Halt at start; Joystick, Autonomous and Test from Halt (and Joystick <->
//! Autonomous directly, bumpless); any fault latches Fault with safe outputs in the
//! same tick, until the cause is gone and the operator powers up again.

mod came_back;
mod commission;
mod drive;
mod endswitch;
mod follow;
pub mod pid;
mod requests;
pub mod row_end;
pub mod rules;
pub mod sensors;
pub mod test_mode;

use mechweed_hw::{Inputs, Outputs};

use crate::camlink::LinkStatus;
use crate::config::Settings;
use crate::config::SteerSettings;
use crate::faults::{CheckContext, FaultChecks};
use crate::rt::health::ThreadHealth;
use crate::state::commission::TestStep;
use crate::state::fault_cause::FaultCause;
use crate::state::measure::{Measured, Measurement};
use crate::state::modes::{Gains, Mode};
use crate::state::status::{FaultRecord, Notice, PowerState, Status};
use crate::state::steering::Steering;
use crate::steer::SteerCommand;
use crate::supervisor::pid::{Pd, Pi};
use endswitch::{EndSwitchLatch, guard_steering};
use row_end::RowEnd;

/// Faults and notices kept for the report; fixed capacity so the tick never allocates.
const LOG_CAPACITY: usize = 256;

pub struct Supervisor {
    settings: Settings,
    period_s: f64,
    measure: Measurement,
    checks: FaultChecks,
    left: Pi,
    right: Pi,
    steering: Pd,
    mode_since_s: f64,
    endswitch: EndSwitchLatch,
    row_end: RowEnd,
    test_outputs: Outputs,
    /// Who holds a control in Test (test_mode.rs).
    test_hold: test_mode::Hold,
    /// The commissioning step running in Test, if any (commission.rs).
    commissioning: commission::Commissioning,
    /// Steering-law parameters accepted in Halt, not yet passed to the steer thread.
    steer_settings: Option<SteerSettings>,
    /// The steering law's parameters as last accepted (the steer thread follows).
    steer_in_force: SteerSettings,
    status: Status,
    fault_log: Vec<FaultRecord>,
    notice_log: Vec<Notice>,
    /// Which sensors steered at the last notice of it, and why (autonomous by GNSS or
    /// fused).
    steering_said: Option<(Steering, Option<&'static str>)>,
    /// When the joystick's dead-man was last held, s: a person at the robot, whom the
    /// bus never overrides (rules.rs, remote_refusal).
    deadman_held_s: f64,
    /// The cause the last power-up cleared, and when: a fault of it again soon came back.
    last_cleared: came_back::LastCleared,
}

impl Supervisor {
    pub fn new(settings: &Settings) -> Supervisor {
        let s = settings;
        Supervisor {
            settings: s.clone(),
            period_s: 1.0 / s.supervisor.rate_hz,
            measure: Measurement::new(&s.robot, &s.supervisor, &s.faults),
            checks: FaultChecks::new(s),
            left: Pi::new(s.pid_left),
            right: Pi::new(s.pid_right),
            steering: Pd::new(s.pid_steer),
            mode_since_s: 0.0,
            endswitch: EndSwitchLatch::default(),
            row_end: RowEnd::new(s),
            test_outputs: Outputs::SAFE,
            test_hold: test_mode::Hold::RELEASED,
            commissioning: commission::Commissioning::default(),
            steer_settings: None,
            steer_in_force: s.steer,
            status: Status::default(),
            fault_log: Vec::with_capacity(LOG_CAPACITY),
            notice_log: Vec::with_capacity(LOG_CAPACITY),
            steering_said: None,
            deadman_held_s: f64::NEG_INFINITY,
            last_cleared: came_back::LastCleared::default(),
        }
    }

    pub fn status(&self) -> &Status {
        &self.status
    }

    pub fn mode(&self) -> Mode {
        self.status.mode
    }

    /// Every fault of the run so far, oldest first (at most 256 kept).
    pub fn faults(&self) -> &[FaultRecord] {
        &self.fault_log
    }

    /// Every notice of the run so far, oldest first (at most 256 kept).
    pub fn notices(&self) -> &[Notice] {
        &self.notice_log
    }

    /// The regulator gains in use.
    pub fn gains(&self) -> Gains {
        Gains {
            left: self.left.gains,
            right: self.right.gains,
            steer: self.steering.gains,
        }
    }

    /// The gains and steering-law parameters in force: what a change of one of them
    /// (from the bus) starts from.
    pub fn tuning(&self) -> (Gains, SteerSettings) {
        (self.gains(), self.steer_in_force)
    }

    /// Steering-law parameters accepted since the last call, for the steer thread.
    pub fn take_steer_settings(&mut self) -> Option<SteerSettings> {
        self.steer_settings.take()
    }

    fn set_mode(&mut self, mode: Mode) {
        if mode != self.status.mode {
            self.status.mode = mode;
            self.mode_since_s = self.status.t_s;
        }
    }

    /// Leaving Halt: the robot stands, so the regulators start from rest and the
    /// references from where the robot is. Between Joystick and Autonomous nothing is
    /// reset: the references ramp on from their present values (bumpless transfer).
    fn start_driving(&mut self) {
        self.left.reset();
        self.right.reset();
        self.steering.reset();
        self.status.speed_ref_mps = 0.0;
        self.status.wheel_angle_ref_rad = self.status.measured.wheel_angle_rad;
    }

    fn enter_fault(&mut self, cause: FaultCause) {
        let record = FaultRecord {
            cause,
            t_s: self.status.t_s,
            tick_seen: self.status.tick,
            tick_safe: self.status.tick,
            came_back_after_s: self.last_cleared.came_back_after_s(&cause, self.status.t_s),
        };
        if self.fault_log.len() < LOG_CAPACITY {
            self.fault_log.push(record);
        }
        self.status.fault = Some(record);
        self.status.power = PowerState::Off;
        self.test_hold = test_mode::Hold::RELEASED;
        let pot_deg = self.status.measured.pot_angle_filtered_rad.to_degrees();
        let (inputs, s) = (&self.status.inputs, &self.settings);
        if let Some(report) = self.commissioning.end_by_fault(inputs, pot_deg, s) {
            self.say(Notice::StepDone {
                report,
                t_s: self.status.t_s,
            });
        }
        self.set_mode(Mode::Fault);
    }

    /// The hardware (`card`, by name) could not be read or written: fault now, safe
    /// outputs.
    pub fn hardware_failed(&mut self, now_s: f64, card: &'static str) -> Outputs {
        self.status.t_s = now_s;
        self.status.tick += 1;
        if self.status.mode != Mode::Fault {
            self.enter_fault(FaultCause::Hardware { card });
        }
        self.status.outputs = Outputs::SAFE;
        Outputs::SAFE
    }

    /// One supervisor tick at `now_s`: inputs in, outputs out.
    pub fn tick(
        &mut self,
        now_s: f64,
        inputs: &Inputs,
        steer: &SteerCommand,
        link: &LinkStatus,
        health: &ThreadHealth,
    ) -> Outputs {
        let (gap_s, measured) = self.take_in(now_s, inputs);
        self.status.sensor_down = sensors::down(&self.settings, link, steer, now_s);
        self.follow_power(now_s, inputs);
        // A finished end-switch procedure and the row's end first: a robot that stops
        // in Halt there is not checked for a row the camera no longer sees.
        self.follow_endswitch_procedure(steer, now_s);
        self.follow_row_end(now_s, measured.distance_m);
        self.say_steering(steer, now_s);
        let driving = self.status.mode.drives();
        self.endswitch
            .latch(&mut self.status.endswitch_hit, driving, inputs, now_s);
        self.check_faults(gap_s, inputs, &measured, steer, link, health);
        let outputs = self.regulate(now_s, gap_s, inputs, &measured, steer);
        self.status.outputs = outputs;
        outputs
    }

    /// The tick's inputs into the status, and the measurements made from them; returns
    /// the time since the last tick and the measurements.
    fn take_in(&mut self, now_s: f64, inputs: &Inputs) -> (f64, Measured) {
        let gap_s = if self.status.tick == 0 {
            self.period_s
        } else {
            now_s - self.status.t_s
        };
        self.status.t_s = now_s;
        self.status.tick += 1;
        self.status.inputs = *inputs;
        if inputs.joystick_enable {
            self.deadman_held_s = now_s;
        }
        self.status.standing_cause = self.checks.standing_cause(inputs);
        // Speeds are counts over the true interval.
        let measured = self.measure.update(inputs, gap_s);
        self.status.measured = measured;
        (gap_s, measured)
    }

    /// Motor power as the test panel asks it, and a closing contactor that has closed.
    fn follow_power(&mut self, now_s: f64, inputs: &Inputs) {
        if self.status.mode == Mode::Test {
            self.status.power = test_mode::power_after_panel(
                self.test_outputs.main_power_on,
                self.status.power,
                now_s,
            );
        }
        if let PowerState::Closing { .. } = self.status.power
            && inputs.motor_power_present
        {
            self.status.power = PowerState::On;
        }
    }

    /// Every fault check (faults/mod.rs); the first cause found enters Fault.
    fn check_faults(
        &mut self,
        gap_s: f64,
        inputs: &Inputs,
        measured: &Measured,
        steer: &SteerCommand,
        link: &LinkStatus,
        health: &ThreadHealth,
    ) {
        let last = self.status.outputs;
        let expected_mps = match self.status.mode {
            Mode::Test => test_mode::expected_mps(&last, &self.left.gains, &self.right.gains),
            _ => [self.status.v_left_ref_mps, self.status.v_right_ref_mps],
        };
        let context = CheckContext {
            now_s: self.status.t_s,
            tick_gap_s: gap_s,
            mode: self.status.mode,
            mode_since_s: self.mode_since_s,
            power: self.status.power,
            inputs,
            measured,
            driven_v: [last.amp_left_v, last.amp_right_v, last.amp_steer_v],
            relay_closed: last.main_power_on,
            brakes_released: [last.brake_release_left, last.brake_release_right],
            expected_mps,
            counts_moved: self.measure.counts_moved,
            endswitch_hit: self.endswitch.hit(self.status.endswitch_hit),
            steer,
            link,
            health,
        };
        if let Some(cause) = self.checks.check(&context)
            && self.status.mode != Mode::Fault
        {
            self.enter_fault(cause);
        }
    }

    /// The outputs the mode asks for: safe in Fault, standing in Halt, the panel's
    /// through the guards in Test, the regulators' while driving.
    fn regulate(
        &mut self,
        now_s: f64,
        gap_s: f64,
        inputs: &Inputs,
        measured: &Measured,
        steer: &SteerCommand,
    ) -> Outputs {
        let outputs = match self.status.mode {
            Mode::Fault => Outputs::SAFE,
            Mode::Halt => self.standing_outputs(),
            Mode::Test => self.test_outputs_now(now_s, inputs, measured),
            Mode::Joystick | Mode::Autonomous => self.drive(now_s, steer, inputs, gap_s),
        };
        if !self.status.mode.drives() {
            // Standing: no speed is asked of either wheel, and the steering holds.
            self.status.speed_ref_mps = 0.0;
            self.status.v_left_ref_mps = 0.0;
            self.status.v_right_ref_mps = 0.0;
            self.status.wheel_angle_ref_rad = measured.wheel_angle_rad;
        }
        outputs
    }

    /// Test's outputs: the panel's, or a commissioning step's, through hold-to-run and
    /// the steering's guard; the voltmeter step's need no hold, as the contactor is open.
    fn test_outputs_now(&mut self, now_s: f64, inputs: &Inputs, measured: &Measured) -> Outputs {
        // The dead-man on the cards is a hold as good as the panel's button.
        let held = self.test_hold.held(inputs.joystick_enable, now_s);
        let asked = test_mode::limit_amplifiers(self.test_outputs);
        let pot_deg = measured.pot_angle_filtered_rad.to_degrees();
        let s = &self.settings;
        let (asked, said) = self
            .commissioning
            .outputs(asked, held, now_s, inputs, pot_deg, s);
        if let Some(report) = said {
            self.say(Notice::StepDone { report, t_s: now_s });
        }
        if self.commissioning.running() == Some(TestStep::Voltmeter) {
            return asked;
        }
        let test = &self.settings.test;
        guard_steering(test_mode::hold_to_run(asked, held, test, measured), inputs)
    }

    /// Publish a notice for the operator and keep it for the report.
    fn say(&mut self, notice: Notice) {
        self.status.notice = Some(notice);
        if self.notice_log.len() < LOG_CAPACITY {
            self.notice_log.push(notice);
        }
    }

    fn standing_outputs(&self) -> Outputs {
        Outputs {
            main_power_on: self.status.power != PowerState::Off,
            ..Outputs::SAFE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fault_and_notice_logs_stop_at_their_capacity_and_never_grow_in_a_tick() {
        // A long run can have hundreds of notices (each change of the sensors that
        // steer): the logs keep the first LOG_CAPACITY, and a push beyond would
        // allocate in the supervisor's tick.
        let mut supervisor = Supervisor::new(&Settings::shipped());
        for k in 0..LOG_CAPACITY + 10 {
            let t_s = k as f64;
            supervisor.say(Notice::RowEnded { driven_m: 1.0, t_s });
            supervisor.enter_fault(FaultCause::PowerUpFailed);
        }
        assert_eq!(supervisor.notices().len(), LOG_CAPACITY);
        assert_eq!(supervisor.faults().len(), LOG_CAPACITY);
        assert_eq!(supervisor.notice_log.capacity(), LOG_CAPACITY);
        assert_eq!(supervisor.fault_log.capacity(), LOG_CAPACITY);
    }
}

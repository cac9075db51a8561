//! How the supervisor answers the requests of other threads (the GUI, the operator
//! script, the command line): the same refusal rules the GUI greys its buttons with
//! (modes.rs), then the change, all between two ticks.

use crate::state::commission::TestStep;
use crate::state::modes::{Gains, Mode, Refusal, Request};
use crate::state::status::{Notice, PowerState};

use super::rules::{mode_refusal, power_up_refusal, remote_refusal};

use super::Supervisor;
use super::{commission, test_mode};

impl Supervisor {
    /// Act on a request; `from_bus`: it came from another program over the bus, and a
    /// person at the robot comes first. The answer says why not, if not.
    pub(crate) fn handle_from(&mut self, request: Request, from_bus: bool) -> Result<(), Refusal> {
        if from_bus
            && let Some(refusal) = remote_refusal(&request, &self.status, self.deadman_held_s)
        {
            return Err(refusal);
        }
        self.handle(request)
    }

    /// Act on a request from another thread; the answer says why not, if not.
    pub fn handle(&mut self, request: Request) -> Result<(), Refusal> {
        let st = &self.status;
        if st.tick == 0 && request != Request::Mode(Mode::Halt) {
            return Err(Refusal::NotStarted);
        }
        match request {
            Request::PowerUp => {
                if let Some(refusal) = power_up_refusal(st) {
                    return Err(refusal);
                }
                if st.mode == Mode::Fault {
                    // After any fault the steering encoder's zero may be what went wrong
                    // (a slipped coupling, a potentiometer that read wrong): take it
                    // again from the potentiometer, with the robot standing.
                    self.measure.recalibrate();
                    self.set_mode(Mode::Halt);
                    if let Some(fault) = self.status.fault.take() {
                        self.last_cleared.cleared(&fault.cause, self.status.t_s);
                    }
                }
                self.status.power = PowerState::Closing {
                    since_s: self.status.t_s,
                };
                Ok(())
            }
            Request::Mode(mode) => {
                if let Some(refusal) = mode_refusal(mode, st) {
                    return Err(refusal);
                }
                match mode {
                    Mode::Test => {
                        self.test_outputs = test_mode::first_outputs(st.power);
                        self.test_hold = test_mode::Hold::RELEASED;
                        self.say(Notice::TestOnStand {
                            t_s: self.status.t_s,
                        });
                    }
                    // Leaving Test restores the safe outputs, contactor open: whatever
                    // the panel switched stays behind on the bench, not in Halt.
                    Mode::Halt if st.mode == Mode::Test => {
                        self.status.power = PowerState::Off;
                        self.test_hold = test_mode::Hold::RELEASED;
                        self.commissioning.stop();
                    }
                    Mode::Joystick | Mode::Autonomous if st.mode == Mode::Halt => {
                        self.start_driving()
                    }
                    _ => {}
                }
                self.set_mode(mode);
                Ok(())
            }
            Request::Gains(gains) => {
                if st.mode != Mode::Halt {
                    return Err(Refusal::OnlyInHalt);
                }
                self.set_gains(&gains);
                Ok(())
            }
            Request::Tuning(gains, steer_law) => {
                if st.mode != Mode::Halt {
                    return Err(Refusal::OnlyInHalt);
                }
                self.set_gains(&gains);
                self.steer_settings = Some(steer_law);
                self.steer_in_force = steer_law;
                Ok(())
            }
            Request::TestOutputs(outputs) => {
                if st.mode != Mode::Test {
                    return Err(Refusal::NotInTest);
                }
                self.test_outputs = outputs;
                Ok(())
            }
            Request::TestHold(held) => {
                if st.mode != Mode::Test {
                    return Err(Refusal::NotInTest);
                }
                self.test_hold.panel(held, st.t_s);
                Ok(())
            }
            Request::TestStep(step) => self.start_step(step),
        }
    }

    /// A commissioning step (commission.rs): an actuator's needs motor power on, the
    /// voltmeter's needs it off.
    fn start_step(&mut self, step: TestStep) -> Result<(), Refusal> {
        let st = &self.status;
        if st.mode != Mode::Test {
            return Err(Refusal::NotInTest);
        }
        let running = self.commissioning.running();
        match step {
            TestStep::Stop => {}
            _ if running.is_some() => return Err(Refusal::StepRunning),
            TestStep::Actuator(_) if st.power != PowerState::On => return Err(Refusal::NotPowered),
            TestStep::Voltmeter if st.power != PowerState::Off || st.inputs.motor_power_present => {
                return Err(Refusal::ContactorClosed);
            }
            TestStep::Voltmeter => {
                let reading = commission::meter_reading(&self.settings);
                let t_s = st.t_s;
                self.say(Notice::Voltmeter { reading, t_s });
            }
            TestStep::Actuator(_) => {}
        }
        let st = &self.status;
        let pot_deg = st.measured.pot_angle_filtered_rad.to_degrees();
        self.commissioning.start(step, st.t_s, &st.inputs, pot_deg);
        Ok(())
    }

    fn set_gains(&mut self, gains: &Gains) {
        self.left.gains = gains.left;
        self.right.gains = gains.right;
        self.steering.gains = gains.steer;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camlink::LinkStatus;
    use crate::config::Settings;
    use crate::rt::health::ThreadHealth;
    use crate::steer::SteerCommand;
    use mechweed_hw::Inputs;

    #[test]
    fn a_request_from_the_bus_is_refused_while_a_person_holds_the_dead_man() {
        let mut supervisor = Supervisor::new(&Settings::shipped());
        let held = Inputs {
            pot_v: 2.5,
            battery_v: 25.0,
            estop_front_released: true,
            estop_back_released: true,
            joystick_enable: true,
            ..Inputs::default()
        };
        let link = LinkStatus::default();
        supervisor.tick(
            0.01,
            &held,
            &SteerCommand::default(),
            &link,
            &ThreadHealth::default(),
        );
        let auto = Request::Mode(Mode::Autonomous);
        assert_eq!(
            supervisor.handle_from(auto, true),
            Err(Refusal::PersonAtTheRobot)
        );
        // The same request from the robot's own GUI meets the other rules only.
        assert_eq!(
            supervisor.handle_from(auto, false),
            Err(Refusal::NotPowered)
        );
    }

    #[test]
    fn halt_is_taken_before_the_first_tick_and_nothing_else_is() {
        // A HALT tool that asks the moment the robot program starts (a CI run's
        // `bus request halt` did) was refused "the robot's inputs have not been read yet".
        let mut supervisor = Supervisor::new(&Settings::shipped());
        assert_eq!(supervisor.status.tick, 0);
        assert_eq!(
            supervisor.handle_from(Request::Mode(Mode::Halt), true),
            Ok(())
        );
        assert_eq!(supervisor.status.mode, Mode::Halt);
        for request in [Request::PowerUp, Request::Mode(Mode::Joystick)] {
            assert_eq!(
                supervisor.handle_from(request, true),
                Err(Refusal::NotStarted),
                "{request:?}"
            );
        }
    }
}

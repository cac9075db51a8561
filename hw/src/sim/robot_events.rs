//! The scripted events' effects on the plant ([sim] events, events.rs): each action
//! changes the simulated robot, its field or its camera computer from the step at or
//! after its time. Operator actions are for the controller, not the plant.

use super::SimRobot;
use crate::sim::events::EventAction;

impl SimRobot {
    pub(super) fn apply_due_events(&mut self) {
        let now_s = self.time_s() + 1e-9;
        while let Some(event) = self.events.get(self.next_event).copied() {
            if event.t_s > now_s {
                break;
            }
            self.next_event += 1;
            self.apply(&event.action);
        }
    }

    /// Apply an action now. Operator actions are for the controller and ignored here.
    pub fn apply(&mut self, action: &EventAction) {
        let now_s = self.time_s();
        match *action {
            EventAction::EstopFront => self.estop_front_released = false,
            EventAction::EstopBack => self.estop_back_released = false,
            EventAction::EstopRelease => {
                self.estop_front_released = true;
                self.estop_back_released = true;
            }
            EventAction::PowerUp | EventAction::Mode(_) => {}
            EventAction::PowerLoss => self.power_lost = true,
            EventAction::PowerRestore => self.power_lost = false,
            EventAction::EncoderStuck(id) => {
                let count = self.encoder(id);
                self.stuck_counts[id as usize].get_or_insert(count);
            }
            EventAction::LinkSilent(duration_s) => self.camera.silence(now_s, duration_s),
            EventAction::CameraReboot => self.camera.reboot(now_s),
            EventAction::EndSwitch(side) => self.steering.kick(side),
            EventAction::Battery(volts) if volts.is_finite() && volts >= 0.0 => {
                self.battery_v = volts
            }
            EventAction::Battery(_) => {}
            EventAction::PotBroken => self.pot_broken = true,
            EventAction::ContactorWelded => self.contactor_welded = true,
            EventAction::Joystick { steer_v, speed_v } => {
                let (enable, finite) = (self.joystick.enable, |v: f64| v.is_finite());
                if finite(steer_v) && finite(speed_v) {
                    self.set_joystick(steer_v, speed_v, enable);
                }
            }
            EventAction::Deadman(held) => self.joystick.enable = held,
            EventAction::Gnss(state) => {
                if let Some(gnss) = &mut self.gnss {
                    gnss.set_state(state, now_s);
                }
            }
            EventAction::Miswire(miswire) => self.rewire(miswire),
            EventAction::SteerSlip(deg) => {
                // `as` saturates, so no slip can make this panic.
                self.steer_slip_counts += (deg * self.p.steer_counts_per_deg).round() as i64
            }
        }
    }
}

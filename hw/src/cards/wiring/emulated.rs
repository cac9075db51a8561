//! The wiring's inverse conversions, for the emulated robot in tests and simulations:
//! what the wires carry for given physical signals, and what the card's outputs mean
//! physically.

use super::{AnalogOut, CardInputs, CardOutputs, Switch, Wiring, get_level, set_level};
use crate::{Inputs, Outputs};

impl Wiring {
    /// For the emulated robot: what the wires carry for these physical inputs.
    pub(crate) fn wires_for(&self, inputs: &Inputs) -> CardInputs {
        let mut c = CardInputs::default();
        let volts = [
            inputs.pot_v,
            inputs.joystick_steer_v,
            inputs.joystick_speed_v,
            inputs.battery_v,
        ];
        for (a, v) in self.analog_inputs().into_iter().zip(volts) {
            c.das08_ai_v[usize::from(a.channel % 8)] = v / a.scale;
        }
        let on = [
            inputs.estop_front_released,
            inputs.estop_back_released,
            inputs.motor_power_present,
            inputs.end_switch_left,
            inputs.end_switch_right,
            inputs.joystick_enable,
        ];
        for ((_, s), signal) in self.switch_inputs().zip(on) {
            set_level(s.bit, s.level(signal), &mut c.das08_ip, &mut c.dda06_ports);
        }
        // A two-contact dead-man's closed contact opens while it is held.
        if let Some(s) = self.joystick_released {
            let level = s.level(!inputs.joystick_enable);
            set_level(s.bit, level, &mut c.das08_ip, &mut c.dda06_ports);
        }
        let counts = [
            inputs.enc_left_counts,
            inputs.enc_right_counts,
            inputs.enc_steer_counts,
        ];
        for (e, n) in self.encoders().into_iter().zip(counts) {
            c.quad04_counts[usize::from(e.channel.clamp(1, 4) - 1)] = n * e.sign;
        }
        c
    }

    /// For the emulated robot: the physical outputs that these card outputs mean.
    pub(crate) fn outputs_from(&self, c: &CardOutputs) -> Outputs {
        let volts = |a: AnalogOut| c.dda06_ao_v[usize::from(a.channel % 6)] / a.scale;
        let on = |s: Switch| s.signal(get_level(s.bit, c.das08_op, &c.dda06_ports));
        Outputs {
            amp_left_v: volts(self.amp_left_v),
            amp_right_v: volts(self.amp_right_v),
            amp_steer_v: volts(self.amp_steer_v),
            main_power_on: on(self.main_power_on),
            brake_release_left: on(self.brake_release_left),
            brake_release_right: on(self.brake_release_right),
            tool_on: on(self.tool_on),
        }
    }
}

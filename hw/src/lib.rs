//! The hardware layer of mechweed: one trait through which the controller reaches the
//! robot, whether that is the real I/O cards or the simulated robot.
//!
//! Once per supervisor tick the controller calls [`Hw::read`] for every input and
//! [`Hw::write`] for every output. Values are in physical units after the robot's
//! wiring (docs/function_spec.md section 4a): volts at the connector, encoder counts, switch states.
//! Scaling to angles and speeds is the controller's job, so the same numbers can be
//! checked with a voltmeter on the real robot.

pub mod camproto;
pub mod cards;
pub mod emulated;
pub mod geo;
pub mod nmea;
pub mod sim;

mod error;

pub use cards::open_error::{CardOpenError, OpenError, Refusal, StartError};
pub use error::{CardFault, HwError};

/// Every input of the robot, read once per supervisor tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Inputs {
    /// Steering potentiometer, volts (0.5 V at -30 deg .. 4.5 V at +30 deg).
    pub pot_v: f64,
    /// Joystick steer axis, volts (-4 V full left .. +4 V full right).
    pub joystick_steer_v: f64,
    /// Joystick speed axis, volts (-4 V full reverse .. +4 V full forward).
    pub joystick_speed_v: f64,
    /// Battery (main power) voltage in volts, after the card's divide-by-ten wiring.
    pub battery_v: f64,
    /// True while the front emergency stop is released (false: pressed or wire broken).
    pub estop_front_released: bool,
    /// True while the back emergency stop is released (false: pressed or wire broken).
    pub estop_back_released: bool,
    /// True while the motor contactor is closed.
    pub motor_power_present: bool,
    /// True while the steering is at its left limit switch.
    pub end_switch_left: bool,
    /// True while the steering is at its right limit switch.
    pub end_switch_right: bool,
    /// True while the joystick's dead-man button is held.
    pub joystick_enable: bool,
    /// Left wheel encoder, counts (x4 quadrature, up when driving forward).
    pub enc_left_counts: i64,
    /// Right wheel encoder, counts (x4 quadrature, up when driving forward).
    pub enc_right_counts: i64,
    /// Steering motor encoder, counts (x4 quadrature, up when turning left); relative:
    /// it reads 0 wherever the steering was at power-up.
    pub enc_steer_counts: i64,
}

/// Every output of the robot, written once per supervisor tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs {
    /// Left drive amplifier command, volts (-10..+10, positive = forward).
    pub amp_left_v: f64,
    /// Right drive amplifier command, volts (-10..+10, positive = forward).
    pub amp_right_v: f64,
    /// Steering amplifier command, volts (-10..+10, positive = turn left).
    pub amp_steer_v: f64,
    /// Close the motor contactor (main power relay).
    pub main_power_on: bool,
    /// Release the left spring brake (false = brake on).
    pub brake_release_left: bool,
    /// Release the right spring brake (false = brake on).
    pub brake_release_right: bool,
    /// Weeding tool motor on.
    pub tool_on: bool,
}

impl Outputs {
    /// What every fault, every exit and every panic leaves behind: amplifiers 0 V,
    /// motor power off, brakes on, tool off.
    pub const SAFE: Outputs = Outputs {
        amp_left_v: 0.0,
        amp_right_v: 0.0,
        amp_steer_v: 0.0,
        main_power_on: false,
        brake_release_left: false,
        brake_release_right: false,
        tool_on: false,
    };

    /// True if these outputs are exactly the safe outputs.
    pub fn is_safe(&self) -> bool {
        *self == Outputs::SAFE
    }
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs::SAFE
    }
}

/// A side of the robot, facing forward (the robot frame's +y is left): the drive
/// wheels, their brakes and the steering's end switches come in a left and a right.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// One of the robot's three quadrature encoders (the counts in [`Inputs`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EncoderId {
    /// The left drive wheel's encoder (`Inputs::enc_left_counts`).
    Left,
    /// The right drive wheel's encoder (`Inputs::enc_right_counts`).
    Right,
    /// The steering motor's encoder (`Inputs::enc_steer_counts`).
    Steer,
}

/// The robot's inputs and outputs, as the supervisor thread sees them.
///
/// Implementations do no heap allocation in `read` and `write` after start, not even
/// when they fail ([`HwError`] is numbers), so that the supervisor tick stays
/// allocation-free. A `write` that fails leaves the safe outputs on whatever still
/// answers.
pub trait Hw: Send {
    /// Read every input once.
    fn read(&mut self) -> Result<Inputs, HwError>;
    /// Write every output once.
    fn write(&mut self, outputs: &Outputs) -> Result<(), HwError>;
    /// A short name for messages ("simulated robot", "I/O cards").
    fn name(&self) -> &'static str;
}

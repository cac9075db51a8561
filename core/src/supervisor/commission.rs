//! The commissioning steps of Test (state/commission.rs has what is asked and said),
//! run with the robot on its stand. Each says what a first power-up must know before
//! the robot drives itself: which way an amplifier turns its motor, and which way its
//! encoder counts.
//!
//! An actuator step puts `STEP_V` on one amplifier for `STEP_S` (its wheel's brake
//! released, every other amplifier at 0 V), only while Hold to run is held like every
//! volt of Test, then waits `SETTLE_S` for the motion to end and says how far the
//! encoder and the potentiometer moved. +volts must turn a drive forwards and the
//! steering left, and count up.
//!
//! The voltmeter step writes `METER_V` on AO0..AO2 with the relay forced open and the
//! brakes on, while motor power is absent: the amplifiers are unpowered, so nothing can
//! move and no hold is needed. It goes on until stopped (or the relay is switched on),
//! so that a meter can be moved from one output to the next.

use mechweed_hw::{EncoderId, Inputs, Outputs};

use crate::config::Settings;
use crate::state::commission::{MeterChannel, MeterReading, StepReport, StepVerdict, TestStep};

/// The step's volts: well above a drive's dead band (0.3 V) and a tenth of full
/// scale, so that a free wheel turns a few centimetres and the steering a few degrees.
pub const STEP_V: f64 = 2.0;
pub const STEP_S: f64 = 0.2;
/// After the volts, the motion must stop before it is measured, s (the steering's lag
/// is 0.05 s, a drive's time constant 0.1 s on the simulated robot).
pub const SETTLE_S: f64 = 0.15;
/// Less motion than this tells nothing: a drive, m; the steering, deg.
const TELLS_M: f64 = 0.005;
const TELLS_DEG: f64 = 0.5;
/// The voltmeter step's volts: a value that each range switch puts out differently.
pub const METER_V: f64 = 2.0;

#[derive(Debug, Clone, Copy)]
struct Running {
    step: TestStep,
    since_s: f64,
    counts: [i64; 3],
    pot_deg: f64,
}

#[derive(Debug, Default)]
pub(crate) struct Commissioning {
    running: Option<Running>,
}

impl Commissioning {
    pub fn running(&self) -> Option<TestStep> {
        self.running.map(|r| r.step)
    }

    /// Start `step` now (or, with `Stop`, end the one running).
    pub fn start(&mut self, step: TestStep, now_s: f64, inputs: &Inputs, pot_deg: f64) {
        self.running = match step {
            TestStep::Stop => None,
            _ => Some(Running {
                step,
                since_s: now_s,
                counts: [
                    inputs.enc_left_counts,
                    inputs.enc_right_counts,
                    inputs.enc_steer_counts,
                ],
                pot_deg,
            }),
        };
    }

    /// Leaving Test: no step goes on.
    pub fn stop(&mut self) {
        self.running = None;
    }

    /// A fault ends the step running: what it saw until then (a reversed steering
    /// encoder makes the potentiometer disagree within the step).
    pub fn end_by_fault(
        &mut self,
        inputs: &Inputs,
        pot_deg: f64,
        s: &Settings,
    ) -> Option<StepReport> {
        let run = self.running.take()?;
        match run.step {
            TestStep::Actuator(actuator) => Some(report(&run, actuator, inputs, pot_deg, s, None)),
            _ => None,
        }
    }

    /// The outputs of the step running over the panel's `asked`, and the report of a
    /// step that ended in this tick. `held`: someone holds a control now.
    pub fn outputs(
        &mut self,
        asked: Outputs,
        held: bool,
        now_s: f64,
        inputs: &Inputs,
        pot_deg: f64,
        s: &Settings,
    ) -> (Outputs, Option<StepReport>) {
        let Some(run) = self.running else {
            return (asked, None);
        };
        let for_s = now_s - run.since_s;
        match run.step {
            TestStep::Actuator(actuator) => {
                let volts_on = for_s < STEP_S;
                if (volts_on && !held) || for_s >= STEP_S + SETTLE_S {
                    self.running = None;
                    let verdict = (volts_on && !held).then_some(StepVerdict::LetGo);
                    let report = report(&run, actuator, inputs, pot_deg, s, verdict);
                    return (step_outputs(asked, actuator, 0.0), Some(report));
                }
                let volts = if volts_on { STEP_V } else { 0.0 };
                (step_outputs(asked, actuator, volts), None)
            }
            // [io]'s scales take these volts to the card (meter_reading says what comes out).
            TestStep::Voltmeter if !inputs.motor_power_present && !asked.main_power_on => {
                let outputs = Outputs {
                    amp_left_v: METER_V,
                    amp_right_v: METER_V,
                    amp_steer_v: METER_V,
                    ..Outputs::SAFE
                };
                (outputs, None)
            }
            // Motor power came on, or the panel's relay switch asks for it: the
            // amplifiers would drive what the step writes, so it ends.
            TestStep::Voltmeter | TestStep::Stop => {
                self.running = None;
                (Outputs::SAFE, None)
            }
        }
    }
}

/// The panel's outputs with `volts` on one amplifier, 0 V on the others, and that
/// drive's brake released for the step (the other's as the panel has it, with 0 V).
fn step_outputs(asked: Outputs, actuator: EncoderId, volts: f64) -> Outputs {
    let mut o = Outputs {
        amp_left_v: 0.0,
        amp_right_v: 0.0,
        amp_steer_v: 0.0,
        tool_on: false,
        ..asked
    };
    match actuator {
        EncoderId::Left => {
            o.amp_left_v = volts;
            o.brake_release_left = true;
        }
        EncoderId::Right => {
            o.amp_right_v = volts;
            o.brake_release_right = true;
        }
        EncoderId::Steer => o.amp_steer_v = volts,
    }
    o
}

/// How far the step moved the actuator, and what that says.
fn report(
    run: &Running,
    actuator: EncoderId,
    inputs: &Inputs,
    pot_deg: f64,
    s: &Settings,
    verdict: Option<StepVerdict>,
) -> StepReport {
    let counts = [
        inputs.enc_left_counts,
        inputs.enc_right_counts,
        inputs.enc_steer_counts,
    ];
    let k = actuator as usize;
    let moved_counts = counts[k].wrapping_sub(run.counts[k]) as f64;
    let (encoder_moved, pot_moved_deg, tells) = match actuator {
        EncoderId::Steer => (
            moved_counts / s.robot.steer_counts_per_deg,
            pot_deg - run.pot_deg,
            TELLS_DEG,
        ),
        _ => (moved_counts / s.robot.enc_counts_per_m, 0.0, TELLS_M),
    };
    let sign = |x: f64, limit: f64| {
        if x > limit {
            1
        } else if x < -limit {
            -1
        } else {
            0
        }
    };
    let verdict = verdict.unwrap_or(
        match (
            actuator,
            sign(encoder_moved, tells),
            sign(pot_moved_deg, TELLS_DEG),
        ) {
            // An encoder that counted nothing tells nothing, whatever the potentiometer saw.
            (_, 0, _) => StepVerdict::NoMotion,
            (EncoderId::Steer, 1, -1) => StepVerdict::PotentiometerReversed,
            (EncoderId::Steer, -1, 1) => StepVerdict::SteerEncoderReversed,
            (EncoderId::Steer, -1, _) => StepVerdict::SteerAmplifierReversed,
            (_, 1, _) => StepVerdict::Right,
            (_, _, _) => StepVerdict::DriveReversed,
        },
    );
    StepReport {
        actuator,
        volts: STEP_V,
        for_s: STEP_S,
        encoder_moved,
        pot_moved_deg,
        verdict,
    }
}

/// What the voltmeter step writes on AO0..AO2 and what the meter must read, from
/// [hw] dda06_ranges_v and [io]'s scales.
pub fn meter_reading(s: &Settings) -> MeterReading {
    let outputs = [s.io.amp_left_v, s.io.amp_right_v, s.io.amp_steer_v];
    MeterReading {
        channels: outputs.map(|a| MeterChannel {
            channel: a.channel,
            range: s.cards.dda06_ranges[usize::from(a.channel % 6)],
            card_v: METER_V * a.scale,
        }),
    }
}

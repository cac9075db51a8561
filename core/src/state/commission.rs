//! The commissioning steps of Test, as the operator asks for them and as the supervisor
//! reports them (supervisor/commission.rs runs them): a small, short voltage step on one
//! amplifier, and whether its encoder (and for the steering the potentiometer) moved
//! the way +volts should move it; and the voltmeter step, a known voltage on AO0..AO2
//! with the contactor open, with what a meter must read for robot.ini's range switches.

use std::fmt;

use mechweed_hw::EncoderId;
use mechweed_hw::cards::dda06::DacRange;

/// What the operator asks in Test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TestStep {
    /// A step on one amplifier: left drive, right drive or steering.
    Actuator(EncoderId),
    /// The known voltage on AO0..AO2, contactor open, until stopped.
    Voltmeter,
    /// End a step now.
    Stop,
}

/// Every step with its name, as a record's request says it ("test_step step=left").
const STEPS: [(&str, TestStep); 5] = [
    ("left", TestStep::Actuator(EncoderId::Left)),
    ("right", TestStep::Actuator(EncoderId::Right)),
    ("steer", TestStep::Actuator(EncoderId::Steer)),
    ("voltmeter", TestStep::Voltmeter),
    ("stop", TestStep::Stop),
];

impl TestStep {
    pub fn name(self) -> &'static str {
        STEPS
            .iter()
            .find(|(_, s)| *s == self)
            .map_or("stop", |(name, _)| *name)
    }

    pub fn from_name(name: &str) -> Option<TestStep> {
        STEPS.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
    }
}

/// What a step showed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepVerdict {
    /// The encoder (and the potentiometer) moved the way +volts should.
    Right,
    /// A drive's encoder counted backwards: its amplifier or its encoder is reversed
    /// (one encoder cannot tell which: the person sees which way the wheel turned).
    DriveReversed,
    /// The steering turned right on +volts, potentiometer and encoder agreeing.
    SteerAmplifierReversed,
    /// The potentiometer saw the steering turn left, the encoder counted right.
    SteerEncoderReversed,
    /// The encoder counted left, the potentiometer saw right.
    PotentiometerReversed,
    /// Nothing moved enough to tell.
    NoMotion,
    /// The hold to run was let go before the step ended.
    LetGo,
}

/// One actuator step's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    pub actuator: EncoderId,
    pub volts: f64,
    pub for_s: f64,
    /// How far the encoder counted: m for a drive, deg for the steering.
    pub encoder_moved: f64,
    /// The steering's potentiometer, deg (0 for a drive).
    pub pot_moved_deg: f64,
    pub verdict: StepVerdict,
}

/// One amplifier output in the voltmeter step: its DAC, its range as robot.ini
/// [hw] dda06_ranges_v has it, and the volts written at the card.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeterChannel {
    pub channel: u8,
    pub range: DacRange,
    pub card_v: f64,
}

/// What the meter must read on AO0..AO2 (left drive, right drive, steering).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeterReading {
    pub channels: [MeterChannel; 3],
}

fn actuator_name(actuator: EncoderId) -> &'static str {
    match actuator {
        EncoderId::Left => "left drive",
        EncoderId::Right => "right drive",
        EncoderId::Steer => "steering",
    }
}

impl fmt::Display for StepReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = actuator_name(self.actuator);
        let (moved, unit) = (
            self.encoder_moved,
            if self.actuator == EncoderId::Steer {
                "deg"
            } else {
                "m"
            },
        );
        let key = match self.actuator {
            EncoderId::Left => "left",
            EncoderId::Right => "right",
            EncoderId::Steer => "steer",
        };
        write!(
            f,
            "{name} step ({:+.1} V for {:.1} s): the encoder counted {moved:+.3} {unit}",
            self.volts, self.for_s
        )?;
        if self.actuator == EncoderId::Steer {
            write!(f, ", the potentiometer {:+.1} deg", self.pot_moved_deg)?;
        }
        let forwards = if self.actuator == EncoderId::Steer {
            "left"
        } else {
            "forwards"
        };
        match self.verdict {
            StepVerdict::Right => write!(f, ": {forwards}, the right way"),
            StepVerdict::DriveReversed => write!(
                f,
                ": backwards. Either the amplifier turns the wheel backwards (swap its motor leads, or [io] amp_{key}_v scale -1) or the encoder counts backwards ([io] enc_{key}_counts scale -1): the way the wheel turned says which"
            ),
            StepVerdict::SteerAmplifierReversed => write!(
                f,
                ": the steering turned right on +volts: swap the steering amplifier's motor leads (or [io] amp_steer_v scale -1)"
            ),
            StepVerdict::SteerEncoderReversed => write!(
                f,
                ": the steering turned left but its encoder counted right: swap its A and B wires (or [io] enc_steer_counts scale -1)"
            ),
            StepVerdict::PotentiometerReversed => write!(
                f,
                ": the encoder counted left but the potentiometer fell: its end wires are swapped (or [robot] pot_v_per_deg's sign)"
            ),
            StepVerdict::NoMotion => write!(
                f,
                ": too little to tell. Check the contactor, the brake, the amplifier's enable and the encoder's cable"
            ),
            StepVerdict::LetGo => {
                write!(f, ": Hold to run let go before the step ended, try again")
            }
        }
    }
}

impl fmt::Display for MeterReading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "voltmeter step, contactor open: between each output and ground the meter must read"
        )?;
        for (k, c) in self.channels.iter().enumerate() {
            let name = actuator_name([EncoderId::Left, EncoderId::Right, EncoderId::Steer][k]);
            let code = c.range.code(c.card_v);
            write!(
                f,
                "; AO{} ({name}) {:+.2} V",
                c.channel,
                c.range.volts(code)
            )?;
            // What a switch set otherwise puts out for the same code.
            let others: Vec<String> = DacRange::ALL
                .iter()
                .filter(|r| **r != c.range)
                .map(|r| format!("{:+.2} V: {}", r.volts(code), r.name()))
                .collect();
            write!(f, " (a switch at another range: {})", others.join(", "))?;
        }
        Ok(())
    }
}

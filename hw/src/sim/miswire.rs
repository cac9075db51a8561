//! Wiring mistakes made on purpose ([sim] miswire, or a scripted `miswire` event), so
//! that the checks which must catch them on the real robot are tried and shown on the
//! simulated one. Each behaves as the real mistake does:
//!
//! - an amplifier reversed (its motor leads swapped): the motor turns the other way
//!   for the same volts;
//! - an encoder reversed (its A and B channels swapped): it counts down where it
//!   should count up;
//! - `dda06_unipolar`: the DDA06's range switches of AO0..AO2 at the unipolar range
//!   of robot.ini's full scale (0..10 V for +-10 V), so that every code the driver
//!   writes for a bipolar range comes out shifted: "0 V" (0x8000) is half of full
//!   scale, and each volt commanded is half a volt.

use std::fmt;

/// One wiring mistake, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Miswire {
    #[default]
    None,
    SteerAmpReversed,
    SteerEncoderReversed,
    LeftAmpReversed,
    LeftEncoderReversed,
    RightAmpReversed,
    Dda06Unipolar,
}

/// Every mistake with its name as written in robot.ini and in events.
pub const MISWIRES: [(&str, Miswire); 7] = [
    ("none", Miswire::None),
    ("steer_amp_reversed", Miswire::SteerAmpReversed),
    ("steer_encoder_reversed", Miswire::SteerEncoderReversed),
    ("left_amp_reversed", Miswire::LeftAmpReversed),
    ("left_encoder_reversed", Miswire::LeftEncoderReversed),
    ("right_amp_reversed", Miswire::RightAmpReversed),
    ("dda06_unipolar", Miswire::Dda06Unipolar),
];

/// The actuators in the order of the signs below.
const LEFT: usize = 0;
const RIGHT: usize = 1;
const STEER: usize = 2;

impl Miswire {
    pub fn parse(word: &str) -> Option<Miswire> {
        MISWIRES
            .iter()
            .find(|(name, _)| *name == word)
            .map(|(_, m)| *m)
    }

    pub fn name(self) -> &'static str {
        MISWIRES
            .iter()
            .find(|(_, m)| *m == self)
            .map_or("none", |(name, _)| *name)
    }

    /// Which way each motor turns for its amplifier's volts: left, right, steering.
    pub fn amplifier_signs(self) -> [f64; 3] {
        let mut signs = [1.0; 3];
        match self {
            Miswire::SteerAmpReversed => signs[STEER] = -1.0,
            Miswire::LeftAmpReversed => signs[LEFT] = -1.0,
            Miswire::RightAmpReversed => signs[RIGHT] = -1.0,
            _ => {}
        }
        signs
    }

    /// Which way each encoder counts for its motion: left, right, steering.
    pub fn encoder_signs(self) -> [i64; 3] {
        let mut signs = [1; 3];
        match self {
            Miswire::SteerEncoderReversed => signs[STEER] = -1,
            Miswire::LeftEncoderReversed => signs[LEFT] = -1,
            _ => {}
        }
        signs
    }

    /// What an amplifier gets for `commanded_v` (within +-`full_scale_v`) from a DDA06
    /// written for a bipolar range, V.
    pub fn dac_v(self, commanded_v: f64, full_scale_v: f64) -> f64 {
        match self {
            // The code for -FS..+FS is 0..65535; a unipolar switch puts out 0..FS for it.
            Miswire::Dda06Unipolar => 0.5 * (commanded_v + full_scale_v),
            _ => commanded_v,
        }
    }
}

impl fmt::Display for Miswire {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The plant's wires from its amplifiers to its motors and from its encoders, as they
/// are wired now.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Wires {
    pub miswire: Miswire,
    /// The amplifiers' commands come through emulated cards, whose DDA06 models its
    /// own range switches: `dda06_unipolar` is theirs to apply, not the plant's.
    pub dacs_on_cards: bool,
    /// Added to each encoder's count, so that a mistake made while running starts
    /// from the count it had instead of jumping.
    pub count_offsets: [i64; 3],
}

impl Wires {
    /// The volts motor `k` (left, right, steering) gets from its amplifier's `amp_v`
    /// (within +-`full_scale_v`).
    pub fn motor_v(&self, k: usize, amp_v: f64, full_scale_v: f64) -> f64 {
        let v = if self.dacs_on_cards {
            amp_v
        } else {
            self.miswire.dac_v(amp_v, full_scale_v)
        };
        v * self.miswire.amplifier_signs()[k]
    }

    /// What encoder `k` reads for `counts` of motion in its own positive direction.
    pub fn count(&self, k: usize, counts: i64) -> i64 {
        let sign = self.miswire.encoder_signs()[k];
        counts
            .saturating_mul(sign)
            .saturating_add(self.count_offsets[k])
    }

    /// Wire as `miswire` from now on; `counts` are each encoder's motion now.
    pub fn rewire(&mut self, miswire: Miswire, counts: [i64; 3]) {
        let before: [i64; 3] = std::array::from_fn(|k| self.count(k, counts[k]));
        self.miswire = miswire;
        let signs = miswire.encoder_signs();
        for k in 0..3 {
            self.count_offsets[k] = before[k].saturating_sub(counts[k].saturating_mul(signs[k]));
        }
    }
}

/// The names, for error messages: "none, steer_amp_reversed, ... or dda06_unipolar".
pub fn miswire_names() -> Vec<&'static str> {
    MISWIRES.iter().map(|(name, _)| *name).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back_as_itself_and_nothing_else_reads() {
        for (name, m) in MISWIRES {
            assert_eq!(Miswire::parse(name), Some(m));
            assert_eq!(m.name(), name);
        }
        assert_eq!(Miswire::parse("steer_reversed"), None);
    }

    #[test]
    fn a_unipolar_switch_puts_half_scale_out_for_zero_and_halves_each_volt() {
        let m = Miswire::Dda06Unipolar;
        assert_eq!(m.dac_v(0.0, 10.0), 5.0);
        assert_eq!(m.dac_v(-10.0, 10.0), 0.0);
        assert_eq!(m.dac_v(2.0, 10.0), 6.0);
        assert_eq!(Miswire::None.dac_v(2.0, 10.0), 2.0);
    }
}

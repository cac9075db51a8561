//! [pid.left], [pid.right] and [pid.steer]: the regulators' gains and limits
//! (supervisor/pid.rs runs them).

use super::reader::Reader;

/// PI speed regulator of one drive wheel, with feed-forward.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PiSettings {
    /// Proportional gain, V per m/s of speed error.
    pub kp: f64,
    /// Integral gain, V per m of accumulated speed error.
    pub ki: f64,
    /// Feed-forward, V per m/s of speed reference.
    pub kff: f64,
    pub out_max_v: f64,
}

/// PD angle regulator of the steering.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdSettings {
    /// Proportional gain, V per rad of angle error.
    pub kp: f64,
    /// Derivative gain on the measured angle, V per rad/s.
    pub kd: f64,
    /// Time constant of the derivative's low-pass filter, s.
    pub d_filter_s: f64,
    pub out_max_v: f64,
}

pub(super) fn pi(r: &mut Reader, s: &str) -> PiSettings {
    PiSettings {
        kp: r.f64(s, "kp", 0.0, 1000.0),
        ki: r.f64(s, "ki", 0.0, 10000.0),
        kff: r.f64(s, "kff", 0.0, 1000.0),
        out_max_v: r.f64(s, "out_max_v", 0.0, 10.0),
    }
}

pub(super) fn pd(r: &mut Reader, s: &str) -> PdSettings {
    PdSettings {
        kp: r.f64(s, "kp", 0.0, 10000.0),
        kd: r.f64(s, "kd", 0.0, 1000.0),
        d_filter_s: r.f64(s, "d_filter_s", 0.0, 1.0),
        out_max_v: r.f64(s, "out_max_v", 0.0, 10.0),
    }
}

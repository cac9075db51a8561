//! [steer]: the steer thread and its steering law.

use super::reader::Reader;

/// The steering law and the steer thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteerSettings {
    /// Which steering law turns the row into a wheel angle.
    pub law: SteerLaw,
    pub rate_hz: f64,
    pub speed_mps: f64,
    pub lookahead_m: f64,
    pub ki_per_m2: f64,
    pub integral_max_deg: f64,
    pub curvature_filter_m: f64,
    pub latency_s: f64,
    pub endswitch_back_deg: f64,
}

/// The steering laws ([steer] law).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SteerLaw {
    /// Linear-quadratic on the row filter's whole state (steer/law_lqr.rs).
    Lqr,
    /// Pure pursuit of a look-ahead point, with an integral on the tool (steer/law.rs).
    Pursuit,
}

impl SteerLaw {
    /// Every law, in the order of `NAMES`.
    const ALL: [SteerLaw; 2] = [SteerLaw::Lqr, SteerLaw::Pursuit];
    pub const NAMES: [&str; 2] = ["lqr", "pursuit"];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    pub fn from_name(name: &str) -> Option<SteerLaw> {
        Self::ALL.into_iter().find(|law| law.name() == name)
    }
}

pub(super) fn load(r: &mut Reader) -> SteerSettings {
    let s = "steer";
    SteerSettings {
        law: SteerLaw::ALL[r.choice(s, "law", &SteerLaw::NAMES)],
        rate_hz: r.f64(s, "rate_hz", 1.0, 200.0),
        speed_mps: r.f64(s, "speed_mps", 0.0, 3.0),
        lookahead_m: r.f64(s, "lookahead_m", 0.1, 10.0),
        ki_per_m2: r.f64(s, "ki_per_m2", 0.0, 10.0),
        integral_max_deg: r.f64(s, "integral_max_deg", 0.0, 30.0),
        curvature_filter_m: r.f64(s, "curvature_filter_m", 0.01, 100.0),
        latency_s: r.f64(s, "latency_s", 0.0, 1.0),
        endswitch_back_deg: r.f64(s, "endswitch_back_deg", 0.0, 45.0),
    }
}

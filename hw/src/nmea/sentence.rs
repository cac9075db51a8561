//! The GNSS receiver's sentences as this program uses them: small `Copy` values in SI
//! units, already checked for range, with no trace of the NMEA text they came from.
//!
//! Fields the receiver may legitimately leave empty (no fix yet, no corrections) are
//! `Option`s; a field without which a sentence means nothing is never empty here,
//! because the decoder counts such a line as malformed instead of passing it on.

/// What kind of solution the receiver reports (GGA's fix quality field).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FixQuality {
    /// 0: no position.
    None,
    /// 1: autonomous GNSS, metres.
    Gps,
    /// 2: differential (DGPS, SBAS), decimetres.
    Dgps,
    /// 4: RTK with integer ambiguities fixed, centimetres.
    RtkFixed,
    /// 5: RTK float, decimetres.
    RtkFloat,
    /// Any other code: 3 PPS, 6 dead reckoning, 7 manual input, 8 simulation, ...
    Other(u8),
}

impl FixQuality {
    /// The quality for a GGA fix-quality code.
    pub fn from_code(code: u8) -> FixQuality {
        match code {
            0 => FixQuality::None,
            1 => FixQuality::Gps,
            2 => FixQuality::Dgps,
            4 => FixQuality::RtkFixed,
            5 => FixQuality::RtkFloat,
            other => FixQuality::Other(other),
        }
    }

    /// The GGA fix-quality code.
    pub fn code(self) -> u8 {
        match self {
            FixQuality::None => 0,
            FixQuality::Gps => 1,
            FixQuality::Dgps => 2,
            FixQuality::RtkFixed => 4,
            FixQuality::RtkFloat => 5,
            FixQuality::Other(code) => code,
        }
    }

    /// True when a sentence of this quality must carry a latitude and longitude. Dead
    /// reckoning, manual and simulated positions count: they are positions, and whether
    /// to trust them is the consumer's decision, not the decoder's.
    pub(crate) fn carries_position(self) -> bool {
        self.code() != 0
    }

    /// A receiver's usual error for this fix when it sends no GST, m (1 s.d.).
    pub fn typical_sd_m(self) -> f64 {
        match self {
            FixQuality::RtkFixed => 0.02,
            FixQuality::RtkFloat => 0.2,
            FixQuality::Dgps => 0.5,
            _ => 3.0,
        }
    }

    /// In words, for the operator.
    pub fn words(self) -> &'static str {
        match self {
            FixQuality::None => "no fix",
            FixQuality::Gps => "GPS",
            FixQuality::Dgps => "DGPS",
            FixQuality::RtkFixed => "RTK fixed",
            FixQuality::RtkFloat => "RTK float",
            FixQuality::Other(_) => "other",
        }
    }

    /// True for RTK fixed and float: the solutions that use the base station.
    pub fn is_rtk(self) -> bool {
        matches!(self, FixQuality::RtkFixed | FixQuality::RtkFloat)
    }
}

/// A horizontal position on the WGS-84 ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatLon {
    /// Positive north, within -90..=90.
    pub lat_deg: f64,
    /// Positive east, within -180..=180.
    pub lon_deg: f64,
}

/// GGA: the position fix and how good the receiver thinks it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gga {
    /// UTC seconds since midnight; empty only in a no-fix sentence.
    pub utc_s_of_day: Option<f64>,
    /// Present whenever `quality.carries_position()`; may also be present without a fix.
    pub position: Option<LatLon>,
    pub quality: FixQuality,
    pub satellites: Option<u8>,
    pub hdop: Option<f32>,
    /// Height above mean sea level, m.
    pub altitude_m: Option<f64>,
    /// Age of the differential corrections, s (empty without corrections).
    pub correction_age_s: Option<f32>,
}

/// RMC's FAA mode indicator (NMEA 2.3 and later), reduced to what a consumer acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RmcMode {
    /// A
    Autonomous,
    /// D, and P (precise): corrected, but not RTK.
    Differential,
    /// R
    RtkFixed,
    /// F
    RtkFloat,
    /// E: dead reckoning.
    Estimated,
    /// N
    NotValid,
    /// M manual, S simulator, C caution, U unsafe.
    Other,
}

/// RMC: the recommended minimum: time, validity, position, speed and course.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rmc {
    /// Empty only while the receiver has no valid fix.
    pub utc_s_of_day: Option<f64>,
    /// Status A or D; false for V (warning).
    pub valid: bool,
    /// Present whenever `valid`.
    pub position: Option<LatLon>,
    pub speed_mps: Option<f64>,
    /// True course over ground, 0..=360 deg.
    pub course_deg: Option<f64>,
    pub mode: Option<RmcMode>,
}

/// VTG: course and speed over ground. It has no time of its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vtg {
    /// True course over ground, 0..=360 deg.
    pub course_deg: Option<f64>,
    pub speed_mps: Option<f64>,
}

/// GST: the receiver's estimate of its own position error, one standard deviation.
/// These are the numbers a filter should trust, rather than HDOP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gst {
    /// Always present: a GST that cannot be matched to its fix is no use.
    pub utc_s_of_day: f64,
    pub sd_lat_m: Option<f64>,
    pub sd_lon_m: Option<f64>,
    pub sd_alt_m: Option<f64>,
}

/// One sentence that passed its checksum and every range check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sentence {
    Gga(Gga),
    Rmc(Rmc),
    Vtg(Vtg),
    Gst(Gst),
}

impl Sentence {
    /// The UTC time the sentence belongs to, if it says.
    pub fn utc_s_of_day(&self) -> Option<f64> {
        match self {
            Sentence::Gga(gga) => gga.utc_s_of_day,
            Sentence::Rmc(rmc) => rmc.utc_s_of_day,
            Sentence::Vtg(_) => None,
            Sentence::Gst(gst) => Some(gst.utc_s_of_day),
        }
    }
}

//! NMEA 0183 lines as an RTK receiver writes them, for the simulated receiver: GGA,
//! RMC, VTG and GST with the XOR checksum and `\r\n`.
//!
//! Latitude and longitude carry seven decimals of arc minutes (0.2 mm), as survey-grade
//! receivers print them, so positions survive the text to well under a millimetre.
//! Each line is built in a fixed buffer: encoding never allocates. Written by hand
//! because the `nmea` crate only reads.

use core::fmt::{self, Write};

use super::sentence::FixQuality;

/// The longest line written, `$` to checksum: what the `nmea` crate will read back.
const MAX_LINE_LEN: usize = ::nmea::SENTENCE_MAX_LEN;
/// Room for `\r\n`.
const BUF_LEN: usize = MAX_LINE_LEN + 2;
const KNOTS_PER_MPS: f64 = 3600.0 / 1852.0;
const KMH_PER_MPS: f64 = 3.6;
/// Arc-minute units on the wire: 1e-7 minute.
const UNITS_PER_MIN: u64 = 10_000_000;
const UNITS_PER_DEG: u64 = 60 * UNITS_PER_MIN;
const CENTISECONDS_PER_DAY: i64 = 8_640_000;

/// What the receiver knows at one epoch, in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReceiverEpoch {
    pub utc_s_of_day: f64,
    pub lat_deg: f64,
    pub lon_deg: f64,
    /// Above mean sea level.
    pub altitude_m: f64,
    /// `None`: no fix; the position fields are written empty.
    pub quality: FixQuality,
    pub satellites: u8,
    pub hdop: f64,
    pub correction_age_s: Option<f64>,
    /// The receiver's own error estimate, 1 s.d., as GST reports it.
    pub sd_lat_m: f64,
    pub sd_lon_m: f64,
    pub sd_alt_m: f64,
    pub speed_mps: f64,
    pub course_deg: f64,
}

/// Why a line could not be written; names the field to fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum EncodeError {
    #[error("{0} is not a finite number")]
    NotFinite(&'static str),
    #[error("{0} is out of range")]
    OutOfRange(&'static str),
    #[error("the line would be longer than {MAX_LINE_LEN} characters")]
    TooLong,
    #[error("a talker id is two capital letters")]
    BadTalker,
}

/// One finished line, `$` to `\n`.
#[derive(Clone, Copy)]
pub struct NmeaLine {
    buf: [u8; BUF_LEN],
    len: usize,
}

impl NmeaLine {
    pub fn as_bytes(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or(&[])
    }
}

impl fmt::Debug for NmeaLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", String::from_utf8_lossy(self.as_bytes()))
    }
}

impl Write for NmeaLine {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let slot = self.buf.get_mut(self.len..end).ok_or(fmt::Error)?;
        slot.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// `value` if it is finite and within `lo..=hi`; else which field to fix.
fn within(value: f64, lo: f64, hi: f64, name: &'static str) -> Result<f64, EncodeError> {
    if !value.is_finite() {
        return Err(EncodeError::NotFinite(name));
    }
    if !(lo..=hi).contains(&value) {
        return Err(EncodeError::OutOfRange(name));
    }
    Ok(value)
}

/// Refuse what the decoder would refuse, so that every line written can be read.
fn validate(e: &ReceiverEpoch) -> Result<(), EncodeError> {
    within(e.utc_s_of_day, f64::MIN, f64::MAX, "time")?;
    if e.quality.carries_position() {
        within(e.lat_deg, -90.0, 90.0, "latitude")?;
        within(e.lon_deg, -180.0, 180.0, "longitude")?;
    }
    within(e.altitude_m, f64::MIN, f64::MAX, "altitude")?;
    within(e.hdop, 0.0, 99.9, "hdop")?;
    within(f64::from(e.satellites), 0.0, 99.0, "satellite count")?;
    if let Some(age_s) = e.correction_age_s {
        within(age_s, 0.0, 86_400.0, "correction age")?;
    }
    within(e.sd_lat_m, 0.0, 1e5, "latitude s.d.")?;
    within(e.sd_lon_m, 0.0, 1e5, "longitude s.d.")?;
    within(e.sd_alt_m, 0.0, 1e5, "altitude s.d.")?;
    within(e.speed_mps, 0.0, 500.0, "speed")?;
    within(e.course_deg, f64::MIN, f64::MAX, "course")?;
    Ok(())
}

/// `hhmmss.ss`, wrapped into one day.
struct Time(f64);

impl fmt::Display for Time {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cs = ((self.0 * 100.0).round() as i64).rem_euclid(CENTISECONDS_PER_DAY);
        let (h, m, s, frac) = (cs / 360_000, cs / 6_000 % 60, cs / 100 % 60, cs % 100);
        write!(f, "{h:02}{m:02}{s:02}.{frac:02}")
    }
}

/// `ddmm.mmmmmmm,N` or `dddmm.mmmmmmm,E`; whole numbers of 1e-7 minute, so rounding
/// can never print 60 minutes.
struct Angle {
    deg: f64,
    degree_digits: usize,
    hemispheres: [char; 2],
}

impl fmt::Display for Angle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let units = (self.deg.abs() * UNITS_PER_DEG as f64).round() as u64;
        let (deg, rem) = (units / UNITS_PER_DEG, units % UNITS_PER_DEG);
        let (min, frac) = (rem / UNITS_PER_MIN, rem % UNITS_PER_MIN);
        let [positive, negative] = self.hemispheres;
        let hemisphere = if self.deg < 0.0 { negative } else { positive };
        let width = self.degree_digits;
        write!(f, "{deg:0width$}{min:02}.{frac:07},{hemisphere}")
    }
}

/// GGA's fix quality as RMC's and VTG's mode letter.
fn mode_letter(quality: FixQuality) -> char {
    match quality.code() {
        0 => 'N',
        1 => 'A',
        2 => 'D',
        3 => 'P',
        4 => 'R',
        5 => 'F',
        6 => 'E',
        7 => 'M',
        8 => 'S',
        _ => 'N',
    }
}

/// Writes lines for one talker id.
#[derive(Debug, Clone, Copy)]
pub struct NmeaEncoder {
    talker: [u8; 2],
}

impl Default for NmeaEncoder {
    fn default() -> Self {
        NmeaEncoder { talker: *b"GN" }
    }
}

impl NmeaEncoder {
    /// Talker "GN": a multi-constellation solution.
    pub fn new() -> Self {
        Self::default()
    }

    pub fn with_talker(talker: [u8; 2]) -> Result<Self, EncodeError> {
        if talker.iter().all(u8::is_ascii_uppercase) {
            Ok(NmeaEncoder { talker })
        } else {
            Err(EncodeError::BadTalker)
        }
    }

    /// GGA, RMC, VTG and GST for one epoch, in that order (as a Trimble sends them).
    pub fn epoch(&self, epoch: &ReceiverEpoch) -> Result<[NmeaLine; 4], EncodeError> {
        Ok([
            self.gga(epoch)?,
            self.rmc(epoch)?,
            self.vtg(epoch)?,
            self.gst(epoch)?,
        ])
    }

    pub(crate) fn gga(&self, e: &ReceiverEpoch) -> Result<NmeaLine, EncodeError> {
        let (altitude_m, hdop) = (e.altitude_m, e.hdop);
        self.line(
            "GGA",
            |w| {
                write!(w, "{},", Time(e.utc_s_of_day))?;
                self.position(w, e)?;
                write!(
                    w,
                    ",{},{:02},{hdop:.1},{altitude_m:.3},M,,,",
                    e.quality.code(),
                    e.satellites
                )?;
                if let Some(age_s) = e.correction_age_s {
                    write!(w, "{age_s:.1}")?;
                }
                write!(w, ",")
            },
            e,
        )
    }

    pub(crate) fn rmc(&self, e: &ReceiverEpoch) -> Result<NmeaLine, EncodeError> {
        let knots = e.speed_mps * KNOTS_PER_MPS;
        // Any angle is a course; the wire wants 0..360.
        let course_deg = e.course_deg.rem_euclid(360.0);
        let status = if e.quality.carries_position() {
            'A'
        } else {
            'V'
        };
        self.line(
            "RMC",
            |w| {
                write!(w, "{},{status},", Time(e.utc_s_of_day))?;
                self.position(w, e)?;
                // The date is left empty: the simulation has none, and nothing here reads it.
                write!(
                    w,
                    ",{knots:.3},{course_deg:.2},,,,{}",
                    mode_letter(e.quality)
                )
            },
            e,
        )
    }

    pub(crate) fn vtg(&self, e: &ReceiverEpoch) -> Result<NmeaLine, EncodeError> {
        let (knots, kmh) = (e.speed_mps * KNOTS_PER_MPS, e.speed_mps * KMH_PER_MPS);
        let course_deg = e.course_deg.rem_euclid(360.0);
        let mode = mode_letter(e.quality);
        self.line(
            "VTG",
            |w| write!(w, "{course_deg:.2},T,,M,{knots:.3},N,{kmh:.3},K,{mode}"),
            e,
        )
    }

    pub(crate) fn gst(&self, e: &ReceiverEpoch) -> Result<NmeaLine, EncodeError> {
        let (sd_lat_m, sd_lon_m, sd_alt_m) = (e.sd_lat_m, e.sd_lon_m, e.sd_alt_m);
        // An error ellipse along the axes: this receiver model's errors are per axis.
        let (major_m, minor_m, orientation_deg) = if sd_lat_m >= sd_lon_m {
            (sd_lat_m, sd_lon_m, 0.0)
        } else {
            (sd_lon_m, sd_lat_m, 90.0)
        };
        self.line(
            "GST",
            |w| {
                write!(
                    w,
                    "{},,{major_m:.3},{minor_m:.3},{orientation_deg:.1},",
                    Time(e.utc_s_of_day)
                )?;
                write!(w, "{sd_lat_m:.3},{sd_lon_m:.3},{sd_alt_m:.3}")
            },
            e,
        )
    }

    /// Latitude and longitude, or four empty fields without a fix.
    fn position(&self, w: &mut NmeaLine, e: &ReceiverEpoch) -> fmt::Result {
        if !e.quality.carries_position() {
            return write!(w, ",,,");
        }
        let lat = Angle {
            deg: e.lat_deg,
            degree_digits: 2,
            hemispheres: ['N', 'S'],
        };
        let lon = Angle {
            deg: e.lon_deg,
            degree_digits: 3,
            hemispheres: ['E', 'W'],
        };
        write!(w, "{lat},{lon}")
    }

    /// `$`, talker, kind, `,`, the fields `body` writes, `*HH\r\n`.
    fn line(
        &self,
        kind: &str,
        body: impl FnOnce(&mut NmeaLine) -> fmt::Result,
        e: &ReceiverEpoch,
    ) -> Result<NmeaLine, EncodeError> {
        validate(e)?;
        let mut w = NmeaLine {
            buf: [0; BUF_LEN],
            len: 0,
        };
        let [t0, t1] = self.talker;
        write!(w, "${}{}{kind},", char::from(t0), char::from(t1))
            .map_err(|_| EncodeError::TooLong)?;
        body(&mut w).map_err(|_| EncodeError::TooLong)?;
        let sum = w
            .as_bytes()
            .get(1..)
            .unwrap_or(&[])
            .iter()
            .fold(0u8, |acc, &b| acc ^ b);
        if w.len + 3 > MAX_LINE_LEN {
            return Err(EncodeError::TooLong);
        }
        write!(w, "*{sum:02X}\r\n").map_err(|_| EncodeError::TooLong)?;
        Ok(w)
    }
}

#[cfg(test)]
#[path = "encode_tests.rs"]
mod tests;

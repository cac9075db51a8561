//! From the `nmea` crate's parsed sentences to ours: units converted, and every number
//! checked, because the crate passes on whatever a field held (`nan`, `inf`, `1e300`,
//! latitudes beyond the pole) as long as it parses as a number.
//!
//! Each function returns the reason a person can act on when a value is unusable.

use ::nmea::sentences::rmc::RmcStatusOfFix;
use ::nmea::sentences::{FaaMode, FixType, GgaData, GstData, RmcData, VtgData};

use super::sentence::{FixQuality, Gga, Gst, LatLon, Rmc, RmcMode, Vtg};

/// One knot in m/s (1852 m per nautical mile, by definition).
const MPS_PER_KNOT: f64 = 1852.0 / 3600.0;
/// GGA's satellite field has two digits.
const MAX_SATELLITES: u32 = 99;
/// Receivers print 99.99 for an unknown HDOP; above 100 the field is garbage.
const MAX_HDOP: f32 = 100.0;
/// Altitude beyond this is no place a ground vehicle (or a receiver's firmware) goes.
const MAX_ABS_ALTITUDE_M: f64 = 100_000.0;
/// A day; older corrections than that are a broken counter, not old data.
const MAX_CORRECTION_AGE_S: f32 = 86_400.0;
/// Faster than any aircraft: the field is garbage, not a fast robot.
const MAX_SPEED_MPS: f64 = 1_000.0;
/// A receiver without a fix may report huge error estimates; beyond this it is garbage.
const MAX_SD_M: f64 = 1_000_000.0;
/// GGA's fields after the talker and kind, counted from 0: the age of corrections.
/// The crate stops reading GGA after the geoid separation, so this one is ours to read.
const GGA_CORRECTION_AGE_FIELD: usize = 12;
/// Where the latitude is in GGA and RMC (the longitude two fields on).
const GGA_LATITUDE_FIELD: usize = 1;
const RMC_LATITUDE_FIELD: usize = 2;

/// Seconds since midnight of an `Option<NaiveTime>` from the crate. A macro, because
/// the crate's time type comes from a crate this one does not depend on, so it cannot
/// be named in a function signature; `Default` for that type is midnight.
macro_rules! seconds_of_day {
    ($time:expr) => {
        $time
            .and_then(|t| {
                t.signed_duration_since(Default::default())
                    .num_nanoseconds()
            })
            .map(|ns| ns as f64 / 1e9)
    };
}

/// The GGA fix-quality code the crate read (it keeps only the digits 0 to 8).
fn quality(fix_type: FixType) -> FixQuality {
    FixQuality::from_code(match fix_type {
        FixType::Invalid => 0,
        FixType::Gps => 1,
        FixType::DGps => 2,
        FixType::Pps => 3,
        FixType::Rtk => 4,
        FixType::FloatRtk => 5,
        FixType::Estimated => 6,
        FixType::Manual => 7,
        FixType::Simulation => 8,
    })
}

fn position(lat_deg: Option<f64>, lon_deg: Option<f64>) -> Result<Option<LatLon>, &'static str> {
    let (Some(lat_deg), Some(lon_deg)) = (lat_deg, lon_deg) else {
        return Ok(None);
    };
    if !(lat_deg.is_finite() && lat_deg.abs() <= 90.0) {
        return Err("latitude beyond 90 degrees");
    }
    if !(lon_deg.is_finite() && lon_deg.abs() <= 180.0) {
        return Err("longitude beyond 180 degrees");
    }
    Ok(Some(LatLon { lat_deg, lon_deg }))
}

fn speed_mps(knots: Option<f32>) -> Result<Option<f64>, &'static str> {
    match knots.map(|k| f64::from(k) * MPS_PER_KNOT) {
        Some(mps) if !(mps.is_finite() && (0.0..=MAX_SPEED_MPS).contains(&mps)) => {
            Err("speed out of range")
        }
        other => Ok(other),
    }
}

fn course_deg(course: Option<f32>) -> Result<Option<f64>, &'static str> {
    match course.map(f64::from) {
        Some(deg) if !(deg.is_finite() && (0.0..=360.0).contains(&deg)) => {
            Err("course out of range")
        }
        other => Ok(other),
    }
}

fn sd_m(sd: Option<f32>) -> Result<Option<f64>, &'static str> {
    match sd.map(f64::from) {
        Some(m) if !(m.is_finite() && (0.0..=MAX_SD_M).contains(&m)) => {
            Err("standard deviation out of range")
        }
        other => Ok(other),
    }
}

/// The sentence's data fields, counted from 0 after the talker and kind, without the
/// checksum: for what the crate does not read, or reads too kindly.
fn data_field(line: &str, index: usize) -> &str {
    let data = line.split_once(',').map_or("", |(_, rest)| rest);
    let data = data.rsplit_once('*').map_or(data, |(fields, _)| fields);
    data.split(',').nth(index).unwrap_or("")
}

/// Latitude (ddmm.mmmm) and longitude (dddmm.mmmm) fields whose minutes are minutes:
/// the crate adds any number as minutes, so `5275.000` would pass as 53.25 degrees.
fn minutes_in_range(line: &str, lat_field: usize) -> Result<(), &'static str> {
    for index in [lat_field, lat_field + 2] {
        let field = data_field(line, index);
        if field.is_empty() {
            continue;
        }
        match field.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 && v % 100.0 < 60.0 => {}
            _ => return Err("minutes of a latitude or longitude not between 0 and 60"),
        }
    }
    Ok(())
}

/// GGA's age of corrections, read from the checksummed line the crate parsed.
fn correction_age_s(line: &str) -> Result<Option<f32>, &'static str> {
    let field = data_field(line, GGA_CORRECTION_AGE_FIELD);
    if field.is_empty() {
        return Ok(None);
    }
    match field.parse::<f32>() {
        Ok(age_s) if age_s.is_finite() && (0.0..=MAX_CORRECTION_AGE_S).contains(&age_s) => {
            Ok(Some(age_s))
        }
        Ok(_) => Err("correction age out of range"),
        Err(_) => Err("unreadable correction age"),
    }
}

/// `line` is the whole sentence the crate parsed into `data`, for the fields it skips.
pub(crate) fn gga(data: &GgaData, line: &str) -> Result<Gga, &'static str> {
    let quality = quality(data.fix_type.ok_or("empty fix quality")?);
    minutes_in_range(line, GGA_LATITUDE_FIELD)?;
    let position = position(data.latitude, data.longitude)?;
    let utc_s_of_day = seconds_of_day!(data.fix_time);
    if quality.carries_position() {
        if position.is_none() {
            return Err("fix without a position");
        }
        if utc_s_of_day.is_none() {
            return Err("fix without a time");
        }
    }
    let satellites = match data.fix_satellites {
        Some(n) if n > MAX_SATELLITES => return Err("satellite count above 99"),
        Some(n) => u8::try_from(n).ok(),
        None => None,
    };
    if let Some(hdop) = data.hdop
        && !(hdop.is_finite() && (0.0..=MAX_HDOP).contains(&hdop))
    {
        return Err("hdop out of range");
    }
    let altitude_m = data.altitude.map(f64::from);
    if let Some(alt) = altitude_m
        && !(alt.is_finite() && alt.abs() <= MAX_ABS_ALTITUDE_M)
    {
        return Err("altitude out of range");
    }
    Ok(Gga {
        utc_s_of_day,
        position,
        quality,
        satellites,
        hdop: data.hdop,
        altitude_m,
        correction_age_s: correction_age_s(line)?,
    })
}

fn rmc_mode(mode: FaaMode) -> RmcMode {
    match mode {
        FaaMode::Autonomous => RmcMode::Autonomous,
        FaaMode::Differential | FaaMode::Precise => RmcMode::Differential,
        FaaMode::FixedRtk => RmcMode::RtkFixed,
        FaaMode::FloatRtk => RmcMode::RtkFloat,
        FaaMode::Estimated => RmcMode::Estimated,
        FaaMode::DataNotValid => RmcMode::NotValid,
        FaaMode::Manual | FaaMode::Simulator | FaaMode::Caution | FaaMode::Unsafe => RmcMode::Other,
    }
}

pub(crate) fn rmc(data: &RmcData, line: &str) -> Result<Rmc, &'static str> {
    minutes_in_range(line, RMC_LATITUDE_FIELD)?;
    let valid = data.status_of_fix != RmcStatusOfFix::Invalid;
    let position = position(data.lat, data.lon)?;
    let utc_s_of_day = seconds_of_day!(data.fix_time);
    if valid {
        if position.is_none() {
            return Err("valid fix without a position");
        }
        if utc_s_of_day.is_none() {
            return Err("valid fix without a time");
        }
    }
    Ok(Rmc {
        utc_s_of_day,
        valid,
        position,
        speed_mps: speed_mps(data.speed_over_ground)?,
        course_deg: course_deg(data.true_course)?,
        mode: data.faa_mode.map(rmc_mode),
    })
}

pub(crate) fn vtg(data: &VtgData) -> Result<Vtg, &'static str> {
    Ok(Vtg {
        course_deg: course_deg(data.true_course)?,
        speed_mps: speed_mps(data.speed_over_ground)?,
    })
}

pub(crate) fn gst(data: &GstData) -> Result<Gst, &'static str> {
    Ok(Gst {
        utc_s_of_day: seconds_of_day!(data.time).ok_or("empty time")?,
        sd_lat_m: sd_m(data.lat_sd)?,
        sd_lon_m: sd_m(data.long_sd)?,
        sd_alt_m: sd_m(data.alt_sd)?,
    })
}

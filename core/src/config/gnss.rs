//! [gnss]: the RTK GNSS receiver and the row map; and [steer] source: which sensors
//! steer in autonomous mode, and when one of them falls back to the other.

use std::path::PathBuf;

use mechweed_hw::geo::Geodetic;
use mechweed_hw::nmea::FixQuality;

use super::camera_port::{BAUD_RATES, CameraPort};
use super::reader::Reader;

/// Where the receiver is: `none`, or any place a camera computer can be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GnssPort {
    /// No receiver: the robot steers by the camera alone.
    None,
    /// The simulated robot's receiver, or a real one on a serial device or TCP.
    Link(CameraPort),
}

/// Where the rows' lines come from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MapSource {
    /// The simulated field's own map (its planting record).
    Sim,
    /// A row map file (docs/gnss.md).
    File(PathBuf),
}

#[derive(Debug, Clone, PartialEq)]
pub struct GnssSettings {
    pub port: GnssPort,
    /// The antenna on the robot: ahead of the rear axle and left of the centre line, m.
    pub antenna_ahead_m: f64,
    pub antenna_left_m: f64,
    pub map: MapSource,
    /// The local east-north frame's reference point (None: the map's first point).
    pub origin: Option<Geodetic>,
    /// Fix qualities whose positions steer, by their GGA code (bit n = code n).
    pub trusted: u16,
    /// No trusted fix for this long: GNSS is lost, s.
    pub timeout_s: f64,
    /// From the receiver measuring a position to its sentences arriving, s.
    pub latency_s: f64,
    /// A fix whose corrections are older than this (GGA's correction age) is not
    /// trusted, s.
    pub max_correction_age_s: f64,
    /// Steering by GNSS without the camera to confirm it, RTK float fixes steer (slowly)
    /// for at most this far past the last RTK fixed one, m.
    pub float_hold_m: f64,
    /// `mechweed teach` warns when the taught path ran farther than this from the row
    /// the camera saw, m (median over the drive).
    pub teach_warn_off_row_m: f64,
}

impl GnssSettings {
    pub(crate) fn trusts(&self, quality: FixQuality) -> bool {
        let code = quality.code();
        code < 16 && self.trusted & (1 << code) != 0
    }
}

/// The words [gnss] trust takes, with their GGA codes.
const QUALITIES: [(&str, u8); 4] = [("rtk_fixed", 4), ("rtk_float", 5), ("dgps", 2), ("gps", 1)];

/// Which sensors steer in autonomous mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SteerSource {
    /// The row camera alone, as the robot always did.
    Camera,
    /// GNSS on the row map alone.
    Gnss,
    /// The row filter: camera, GNSS and odometry together, with fallbacks.
    Fused,
}

/// [steer] source and its fallbacks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceSettings {
    pub source: SteerSource,
    /// Fused: no trusted fix for this long steers by the camera alone, s.
    pub gnss_fallback_s: f64,
    /// Fused: the camera seeing no row for this long steers by GNSS alone, s. The camera
    /// alone, begun with no row in sight, stands this long before it searches ([camera]
    /// first_row_m): keep it below [camera] link_timeout_s, or the camera's fault comes
    /// first.
    pub camera_fallback_s: f64,
    /// ... at this speed at most, m/s.
    pub gnss_only_speed_mps: f64,
}

pub(super) fn load(r: &mut Reader) -> GnssSettings {
    let s = "gnss";
    let names = BAUD_RATES.map(|b| b.to_string());
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let baud = BAUD_RATES[r.choice(s, "baud", &names)];
    let port = r
        .parsed(s, "port", |text| match text {
            "none" => Ok(GnssPort::None),
            "bus" => Err("the bus carries no GNSS positions: none, sim, a device such as /dev/ttyACM0, or tcp://HOST:PORT".to_string()),
            _ => CameraPort::parse(text, baud).map(GnssPort::Link),
        })
        .unwrap_or(GnssPort::None);
    let map = r
        .parsed(s, "map", |text| match text {
            "sim" => Ok(MapSource::Sim),
            "" => Err("names no file: sim, or a row map file such as config/rows.csv".to_string()),
            _ => Ok(MapSource::File(PathBuf::from(text))),
        })
        .unwrap_or(MapSource::Sim);
    GnssSettings {
        port,
        antenna_ahead_m: r.f64(s, "antenna_ahead_m", -5.0, 5.0),
        antenna_left_m: r.f64(s, "antenna_left_m", -5.0, 5.0),
        map,
        origin: r.parsed(s, "origin", origin).unwrap_or(None),
        trusted: r.parsed(s, "trust", trusted_codes).unwrap_or(1 << 4),
        timeout_s: r.f64(s, "timeout_s", 0.05, 10.0),
        latency_s: r.f64(s, "latency_s", 0.0, 1.0),
        max_correction_age_s: r.f64(s, "max_correction_age_s", 0.1, 60.0),
        float_hold_m: r.f64(s, "float_hold_m", 0.0, 100.0),
        teach_warn_off_row_m: r.f64(s, "teach_warn_off_row_m", 0.0, 1.0),
    }
}

/// "map" (the map's first point) or "LAT,LON" in degrees.
fn origin(text: &str) -> Result<Option<Geodetic>, String> {
    if text == "map" {
        return Ok(None);
    }
    let bad = || format!("'{text}' is not map or LAT,LON in degrees (for example 52.0,5.66)");
    let (lat, lon) = text.split_once(',').ok_or_else(bad)?;
    let lat_deg: f64 = lat.trim().parse().map_err(|_| bad())?;
    let lon_deg: f64 = lon.trim().parse().map_err(|_| bad())?;
    if !(-85.0..=85.0).contains(&lat_deg) || !(-180.0..=180.0).contains(&lon_deg) {
        return Err(format!(
            "{text}: the latitude must be -85..85 and the longitude -180..180 degrees"
        ));
    }
    Ok(Some(Geodetic {
        lat_deg,
        lon_deg,
        height_m: 0.0,
    }))
}

/// "rtk_fixed, rtk_float" -> the bits of codes 4 and 5.
fn trusted_codes(text: &str) -> Result<u16, String> {
    let mut bits = 0u16;
    for word in text.split(',').map(str::trim) {
        let Some(&(_, code)) = QUALITIES.iter().find(|(name, _)| *name == word) else {
            let names: Vec<&str> = QUALITIES.iter().map(|(name, _)| *name).collect();
            return Err(format!(
                "'{word}' is not a fix quality (one or more of {}, comma-separated)",
                names.join(", ")
            ));
        };
        bits |= 1 << code;
    }
    Ok(bits)
}

pub(super) fn sources(r: &mut Reader) -> SourceSettings {
    let s = "steer";
    SourceSettings {
        source: [SteerSource::Camera, SteerSource::Gnss, SteerSource::Fused]
            [r.choice(s, "source", &["camera", "gnss", "fused"])],
        gnss_fallback_s: r.f64(s, "gnss_fallback_s", 0.0, 60.0),
        camera_fallback_s: r.f64(s, "camera_fallback_s", 0.0, 60.0),
        gnss_only_speed_mps: r.f64(s, "gnss_only_speed_mps", 0.0, 3.0),
    }
}

/// GNSS steering needs a receiver.
pub(super) fn check(s: &super::Settings, r: &mut Reader) {
    let keys = [("steer", "source"), ("gnss", "port")];
    if s.sources.source != SteerSource::Camera && s.gnss.port == GnssPort::None && r.all_read(&keys)
    {
        let source = if s.sources.source == SteerSource::Gnss {
            "gnss"
        } else {
            "fused"
        };
        r.cross_error(
            &keys,
            format!("[steer] source = {source} steers by GNSS, but [gnss] port = none: name the receiver's port (sim on the simulated robot), or set source = camera"),
        );
    }
}

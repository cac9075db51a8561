//! The simulated RTK GNSS receiver: NMEA lines on its end of a pipe, as a real receiver
//! writes them on its serial port.
//!
//! Every 1/rate s it measures where its antenna is (mounted `antenna_ahead_m` ahead of the
//! rear axle and `antenna_left_m` to its left) through the receiver's error model
//! (gnss_model.rs), turns the position into latitude and longitude, and writes GGA, RMC,
//! VTG and GST for that epoch after the latency. The field's frame is the local
//! east-north frame at `origin` (x east, y north), so the field's metres are the
//! receiver's metres. Nothing here allocates after `new`.

use super::body::Pose;
use super::gnss_model::{FloatSchedule, GnssState, Measured, ReceiverModel};
use super::params::{FieldKind, SimParams};
use super::pipe::PipeEnd;
use crate::geo::{Enu, Geodetic, LocalFrame};
use crate::nmea::FixQuality;
use crate::nmea::encode::{NmeaEncoder, ReceiverEpoch};

/// The simulated day starts at 10:00 UTC, so a run never crosses midnight.
const START_UTC_S: f64 = 36_000.0;
/// Epochs that can wait for their send time at once.
const RING: usize = 4;
/// The antenna's height above the field, m (written in GGA; nothing uses it).
const ANTENNA_HEIGHT_M: f64 = 1.5;

/// The receiver on the robot and the field's place on the earth ([sim] gnss_*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimGnssParams {
    pub rate_hz: f64,
    /// From the epoch to its lines on the wire, s.
    pub latency_s: f64,
    pub antenna_ahead_m: f64,
    pub antenna_left_m: f64,
    /// The field's origin (the row's start), degrees.
    pub origin_lat_deg: f64,
    pub origin_lon_deg: f64,
    /// The realistic field's RTK float episodes: one every this far on average, m ...
    pub float_every_m: f64,
    /// ... lasting this long, s.
    pub float_s: f64,
    /// The map's row line is off the true row by the planting machine's own RTK error:
    /// s.d., m ...
    pub map_error_sd_m: f64,
    /// ... changing over this length of row, m.
    pub map_error_length_m: f64,
}

impl Default for SimGnssParams {
    fn default() -> Self {
        SimGnssParams {
            rate_hz: 10.0,
            latency_s: 0.05,
            antenna_ahead_m: 0.5,
            antenna_left_m: 0.0,
            // A field in the Netherlands' clay (any place on the earth serves).
            origin_lat_deg: 52.0,
            origin_lon_deg: 5.66,
            float_every_m: 200.0,
            float_s: 20.0,
            map_error_sd_m: 0.01,
            map_error_length_m: 20.0,
        }
    }
}

impl SimGnssParams {
    pub(crate) fn sanitized(&self) -> SimGnssParams {
        let d = SimGnssParams::default();
        let ok = |v: f64, lo: f64, hi: f64, default: f64| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                v
            } else {
                default
            }
        };
        SimGnssParams {
            rate_hz: ok(self.rate_hz, 0.1, 100.0, d.rate_hz),
            latency_s: ok(self.latency_s, 0.0, 1.0, d.latency_s),
            antenna_ahead_m: ok(self.antenna_ahead_m, -10.0, 10.0, d.antenna_ahead_m),
            antenna_left_m: ok(self.antenna_left_m, -10.0, 10.0, d.antenna_left_m),
            origin_lat_deg: ok(self.origin_lat_deg, -85.0, 85.0, d.origin_lat_deg),
            origin_lon_deg: ok(self.origin_lon_deg, -180.0, 180.0, d.origin_lon_deg),
            float_every_m: ok(self.float_every_m, 1.0, 1e7, d.float_every_m),
            float_s: ok(self.float_s, 0.1, 1e5, d.float_s),
            map_error_sd_m: ok(self.map_error_sd_m, 0.0, 10.0, d.map_error_sd_m),
            map_error_length_m: ok(self.map_error_length_m, 0.01, 1e5, d.map_error_length_m),
        }
    }
}

/// What the simulated receiver has done, for tests and the GUI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SimGnssCounters {
    pub epochs: u64,
    /// Epochs with a position.
    pub fixes: u64,
    pub lines_written: u64,
    /// Epochs lost because the ring of waiting epochs was full.
    pub ring_full: u64,
}

pub struct SimReceiver {
    pipe: PipeEnd,
    p: SimGnssParams,
    model: ReceiverModel,
    frame: LocalFrame,
    encoder: NmeaEncoder,
    next_epoch_t_s: f64,
    pending: [(f64, Option<ReceiverEpoch>); RING],
    head: usize,
    waiting: usize,
    counters: SimGnssCounters,
}

impl SimReceiver {
    /// `params` must be sanitized; `pipe` is the receiver's end.
    pub(crate) fn new(params: &SimParams, pipe: PipeEnd) -> SimReceiver {
        let p = params.gnss;
        let mut model = ReceiverModel::new(params.seed);
        if params.field == FieldKind::Realistic
            && let Ok(schedule) = FloatSchedule::new(p.float_every_m, p.float_s)
        {
            model = model.with_float_schedule(schedule, 0.0);
        }
        SimReceiver {
            pipe,
            model,
            frame: LocalFrame::new(Geodetic {
                lat_deg: p.origin_lat_deg,
                lon_deg: p.origin_lon_deg,
                height_m: 0.0,
            }),
            encoder: NmeaEncoder::default(),
            next_epoch_t_s: 0.0,
            pending: [(0.0, None); RING],
            head: 0,
            waiting: 0,
            counters: SimGnssCounters::default(),
            p,
        }
    }

    pub fn counters(&self) -> SimGnssCounters {
        self.counters
    }

    /// The solution's state now (events and the realistic field's episodes change it).
    pub fn state(&self) -> GnssState {
        self.model.state()
    }

    /// An event: the solution becomes `state` at `t_s`.
    pub(crate) fn set_state(&mut self, state: GnssState, t_s: f64) {
        self.model.set_state(state, t_s);
    }

    /// One integration step at `t_s`: measure if an epoch is due, send what is due.
    pub(crate) fn tick(&mut self, t_s: f64, pose: &Pose, speed_mps: f64, distance_m: f64) {
        if t_s >= self.next_epoch_t_s {
            self.measure(t_s, pose, speed_mps, distance_m);
            self.next_epoch_t_s += 1.0 / self.p.rate_hz;
            if self.next_epoch_t_s <= t_s {
                self.next_epoch_t_s = t_s + 1.0 / self.p.rate_hz;
            }
        }
        while self.waiting > 0 && self.pending[self.head].0 <= t_s {
            let (_, epoch) = self.pending[self.head];
            self.head = (self.head + 1) % RING;
            self.waiting -= 1;
            if let Some(epoch) = epoch {
                self.write(&epoch);
            }
        }
    }

    fn measure(&mut self, t_s: f64, pose: &Pose, speed_mps: f64, distance_m: f64) {
        self.counters.epochs += 1;
        let (sin, cos) = pose.heading_rad.sin_cos();
        let (east_m, north_m) = pose.point_ahead(self.p.antenna_ahead_m);
        let east_m = east_m - self.p.antenna_left_m * sin;
        let north_m = north_m + self.p.antenna_left_m * cos;
        // Course over ground: clockwise from north, as NMEA gives it.
        let course_deg = (90.0 - pose.heading_rad.to_degrees()).rem_euclid(360.0);
        let measured = self.model.measure(t_s, distance_m, east_m, north_m);
        if measured.is_some() {
            self.counters.fixes += 1;
        }
        let motion = (speed_mps.abs(), course_deg);
        let epoch = epoch_of(START_UTC_S + t_s, measured.as_ref(), &self.frame, motion);
        if self.waiting == RING {
            self.counters.ring_full += 1;
            return;
        }
        self.pending[(self.head + self.waiting) % RING] = (t_s + self.p.latency_s, Some(epoch));
        self.waiting += 1;
    }

    fn write(&mut self, epoch: &ReceiverEpoch) {
        // An epoch the encoder cannot write (a number it cannot print) is not sent, as a
        // receiver with a bad solution sends nothing.
        if let Ok(lines) = self.encoder.epoch(epoch) {
            for line in &lines {
                self.pipe.send(line.as_bytes());
                self.counters.lines_written += 1;
            }
        }
    }
}

/// What a receiver writes for one epoch at UTC `utc_s_of_day`: the position the error
/// model `measured` gives (in `frame`'s metres), or no fix; `(speed_mps, course_deg)`
/// over ground. Shared with `mechweed gnsssim`.
pub fn epoch_of(
    utc_s_of_day: f64,
    measured: Option<&Measured>,
    frame: &LocalFrame,
    (speed_mps, course_deg): (f64, f64),
) -> ReceiverEpoch {
    let no_fix = ReceiverEpoch {
        utc_s_of_day,
        lat_deg: 0.0,
        lon_deg: 0.0,
        altitude_m: ANTENNA_HEIGHT_M,
        quality: FixQuality::None,
        satellites: 0,
        hdop: 99.9,
        correction_age_s: None,
        sd_lat_m: 0.0,
        sd_lon_m: 0.0,
        sd_alt_m: 0.0,
        speed_mps,
        course_deg,
    };
    let Some(m) = measured else {
        return no_fix;
    };
    let place = frame.to_geodetic(Enu {
        east_m: m.east_m,
        north_m: m.north_m,
        up_m: ANTENNA_HEIGHT_M,
    });
    ReceiverEpoch {
        lat_deg: place.lat_deg,
        lon_deg: place.lon_deg,
        quality: m.quality,
        satellites: m.satellites,
        hdop: m.hdop,
        correction_age_s: Some(1.0),
        sd_lat_m: m.sd_m,
        sd_lon_m: m.sd_m,
        sd_alt_m: 2.0 * m.sd_m,
        ..no_fix
    }
}

#[cfg(test)]
#[path = "gnss_tests.rs"]
mod tests;

//! Which sensors steer in autonomous mode, and the row filter that fuses them.
//!
//! The row filter (filter.rs) runs at every steer tick, whatever the source: predicted by
//! the robot's odometry, updated by each new camera estimate at the pose where its image
//! was taken (through the filter's gate) and, for gnss or fused, by each new trusted
//! GNSS fix against the row map at the pose where the receiver measured it
//! (sources_fuse.rs); the law steers by the filter's row now.
//!
//! Fused falls back as a controller manager's fallback controllers do:
//! - no trusted fix for `gnss_fallback_s`: the filter goes on with the camera alone;
//! - the camera sees no usable row for `camera_fallback_s`: the filter goes on with GNSS
//!   alone, and the robot slows to `gnss_only_speed_mps`;
//! - neither: nothing steers, the robot stops, and the supervisor faults with both
//!   causes named once that lasts the camera's link time-out.
//!
//! The same file decides for source = gnss: GNSS alone, or nothing.
//!
//! A camera that repeats its last estimate (a gap in the row) updates nothing: odometry
//! carries the filter's row, at [camera] gap_speed_mps at most, for at most [camera]
//! gap_hold_m (camera_hold.rs).

use mechweed_hw::camproto::RowEstimate;

#[path = "sources_fuse.rs"]
mod fuse;

use super::camera_hold::{CameraHold, Held};
use super::filter::{RowFilter, Travel};
use super::filter_config::filter_settings;
use super::fix_checks::{FixChecks, degraded};
use super::odometry::OdometryHistory;
use crate::camlink::LinkStatus;
use crate::config::{GnssSettings, Settings, SourceSettings, SteerSource};
use crate::gnss::GnssStatus;
use crate::gnss::place::RowPlace;
use crate::state::measure::Measured;
pub use crate::state::steering::Steering;

/// The camera link is up yet gives no row to steer by.
const NO_USABLE_ROW: &str = "the camera has given no estimate of [camera] min_quality or better for [steer] camera_fallback_s";
const SEARCHING: &str = "no row in sight yet: driving straight ahead at [camera] gap_speed_mps for at most [camera] first_row_m to find the first plants";
const IN_A_GAP: &str = "a gap in the row: the camera repeats its last row, carried by the robot's own motion at [camera] gap_speed_mps for at most [camera] gap_hold_m";
const AGAINST_MAP: &str =
    "the row is driven against its map's point order, and its line is followed that way";
const NEITHER: &str = "neither the camera nor GNSS has given a usable row";
use mechweed_hw::nmea::FixQuality;

/// Which sensors steer and how long each has been without a good measurement, for the
/// supervisor's fault check and the GUI (in the steer command).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SourceHealth {
    pub steering: Steering,
    /// When the camera's link last had a usable row (an estimate repeated unchanged only
    /// within [camera] gap_hold_m), and GNSS a trusted fix, s.
    pub camera_good_s: f64,
    pub gnss_good_s: f64,
    /// Autonomous by the camera alone, begun with no row in sight: the robot drives
    /// straight ahead to find its first plants, for at most [camera] first_row_m.
    pub searching: bool,
    /// The row filter's row offset at the rear axle, m. The off-the-row fault reads it
    /// only when GNSS steers: steering by the camera alone, losing the row is the
    /// camera's own fault (it sees no row).
    pub row_offset_m: f64,
    /// Why a sensor is not steering now (the camera's or GNSS's trouble), for the
    /// notice of each change; None where the chosen sensors are all there are.
    pub why: Option<&'static str>,
}

/// What the GNSS link and the row filter show, for the GUI, the record and the report
/// (in the steer command). No NaN in it: views are compared to tell what changed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RowFigures {
    /// The last fix: its GGA quality code (0: none), satellites, and the receiver's own
    /// s.d. of the position, m (None without a GST).
    pub gnss_quality: u8,
    pub gnss_satellites: u8,
    pub gnss_sd_m: Option<f64>,
    /// The antenna's latitude and longitude in that fix, degrees.
    pub gnss_position: Option<(f64, f64)>,
    /// When the receiver last sent an epoch, with or without a position (None: never),
    /// s: the supervisor refuses autonomous by GNSS while it is silent.
    pub gnss_heard_s: Option<f64>,
    /// The row filter (None when the camera steers alone: its figures are then the
    /// camera's own, and the record keeps those).
    pub filter: Option<FilterFigures>,
}

/// The row filter's estimate of the row at the rear axle, and what its gate did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterFigures {
    pub offset_m: f64,
    pub offset_sd_m: f64,
    pub heading_rad: f64,
    pub heading_sd_rad: f64,
    pub curvature_per_m: f64,
    pub map_bias_m: f64,
    /// Measurements the gate rejected so far.
    pub camera_rejected: u64,
    pub gnss_rejected: u64,
}

/// The row to steer by, for the law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowChoice {
    pub estimate: RowEstimate,
    /// The robot's motion since the estimate's image was taken, as the law takes it.
    pub since: Travel,
    pub speed_mps: f64,
}

pub struct RowSources {
    s: SourceSettings,
    gnss: GnssSettings,
    latency_s: f64,
    /// The age the law is told the filter's row has: see `tick`.
    law_age_s: f64,
    link_timeout_s: f64,
    camera_x_m: f64,
    filter: RowFilter,
    camera_sd_offset_m: f64,
    camera_sd_angle_rad: f64,
    fuse_min_quality: u8,
    place: Option<RowPlace>,
    odometry: OdometryHistory,
    hold: CameraHold,
    /// What the hold said of the camera's estimate at the last `watch`, and whether it
    /// may be steered by.
    held: Held,
    held_ok: bool,
    /// What is wrong with the camera's rows, as of the last `watch`.
    camera_trouble: &'static str,
    /// A new camera estimate came that the filter has not had yet.
    camera_unfused: bool,
    gap_hold_m: f64,
    gap_speed_mps: f64,
    first_row_m: f64,
    /// Odometry's distance at the first tick of this autonomous spell, m.
    start_distance_m: Option<f64>,
    searching: bool,
    used_fix_s: f64,
    /// What the last fix's epoch, corrections and quality allow.
    fix_checks: FixChecks,
    /// The quality and time of the last trusted fix used.
    last_fix_used: Option<(FixQuality, f64)>,
    /// The last time each sensor was good, s.
    camera_good_s: f64,
    gnss_good_s: f64,
    /// When autonomous mode began: sensors are given until their fall-back times to be
    /// heard from, but the robot does not move before one that steers has been.
    reset_s: f64,
    steering: Steering,
}

impl RowSources {
    /// `place` is the row map seen from the robot (None without a receiver or map).
    pub fn new(settings: &Settings, place: Option<RowPlace>) -> RowSources {
        RowSources {
            s: settings.sources,
            gnss: settings.gnss.clone(),
            latency_s: settings.steer.latency_s,
            law_age_s: settings.steer.latency_s + 0.5 / settings.steer.rate_hz,
            link_timeout_s: settings.camera.link_timeout_s,
            camera_x_m: settings.robot.camera_lookahead_m,
            filter: RowFilter::new(filter_settings(&settings.filter, settings.sources.source)),
            camera_sd_offset_m: settings.filter.camera_sd_offset_m,
            camera_sd_angle_rad: settings.filter.camera_sd_angle_rad,
            fuse_min_quality: settings.filter.fuse_min_quality,
            place,
            odometry: OdometryHistory::default(),
            hold: CameraHold::default(),
            held: Held::default(),
            held_ok: false,
            camera_trouble: NO_USABLE_ROW,
            camera_unfused: false,
            gap_hold_m: settings.camera.gap_hold_m,
            gap_speed_mps: settings.camera.gap_speed_mps,
            first_row_m: settings.camera.first_row_m,
            start_distance_m: None,
            searching: false,
            last_fix_used: None,
            fix_checks: FixChecks::default(),
            used_fix_s: f64::NEG_INFINITY,
            camera_good_s: f64::NEG_INFINITY,
            gnss_good_s: f64::NEG_INFINITY,
            reset_s: f64::NEG_INFINITY,
            steering: Steering::default(),
        }
    }

    pub fn health(&self) -> SourceHealth {
        SourceHealth {
            steering: self.steering,
            camera_good_s: self.camera_good_s,
            gnss_good_s: self.gnss_good_s,
            searching: self.searching,
            row_offset_m: self.filter.state().offset_m,
            why: match (self.steering, self.s.source) {
                (Steering::FilterGnss, SteerSource::Fused) => Some(self.camera_trouble),
                (Steering::FilterCamera, _) => Some(self.fix_checks.trouble),
                (Steering::Nothing, SteerSource::Fused) => Some(NEITHER),
                _ if self.searching => Some(SEARCHING),
                (Steering::Camera, _) if self.held.repeated => Some(IN_A_GAP),
                // The camera alone's other troubles are the supervisor's camera faults.
                (_, SteerSource::Camera) => None,
                (Steering::Nothing, _) => Some(self.fix_checks.trouble),
                _ if self.place.as_ref().is_some_and(RowPlace::against_map) => Some(AGAINST_MAP),
                _ => None,
            },
        }
    }

    /// The last fix's figures and, where the filter runs, its estimate.
    pub fn figures(&self, gnss: &GnssStatus) -> RowFigures {
        let mut f = RowFigures {
            gnss_heard_s: Some(gnss.last_epoch_s).filter(|t| t.is_finite()),
            ..RowFigures::default()
        };
        if let Some(fix) = gnss.last_fix {
            f.gnss_quality = fix.quality.code();
            f.gnss_satellites = fix.satellites.unwrap_or(0);
            f.gnss_sd_m = fix.sd_m();
            f.gnss_position = Some((fix.lat_deg, fix.lon_deg));
        }
        if self.s.source != SteerSource::Camera {
            let (x, sd, c) = (
                self.filter.state(),
                self.filter.sd(),
                self.filter.counters(),
            );
            f.filter = Some(FilterFigures {
                offset_m: x.offset_m,
                offset_sd_m: sd.offset_m,
                heading_rad: x.heading_rad,
                heading_sd_rad: sd.heading_rad,
                curvature_per_m: x.curvature_per_m,
                map_bias_m: x.map_bias_m,
                camera_rejected: c.camera_rejected,
                gnss_rejected: c.gnss_rejected,
            });
        }
        f
    }

    pub fn filter(&self) -> &RowFilter {
        &self.filter
    }

    /// Start afresh (entering autonomous mode): the filter wide open, the row chosen
    /// again at the next fix, both sensors judged from now.
    pub fn reset(&mut self, now_s: f64) {
        self.filter = RowFilter::new(*self.filter.settings());
        if let Some(place) = &mut self.place {
            place.choose_again();
        }
        self.odometry.clear();
        self.camera_unfused = false;
        self.start_distance_m = None;
        self.searching = false;
        self.fix_checks.reset();
        self.camera_good_s = now_s;
        self.gnss_good_s = now_s;
        self.reset_s = now_s;
        self.steering = match self.s.source {
            SteerSource::Camera => Steering::Camera,
            _ => Steering::Fused,
        };
    }

    /// Every steer tick in autonomous mode, whatever steers (an end-switch procedure
    /// too): the robot's motion into the odometry kept and the filter, and whether the
    /// camera still has a row.
    pub fn watch(&mut self, now_s: f64, m: &Measured, link: &LinkStatus) {
        let step = self.odometry.remember(now_s, m);
        if let Some(step) = step {
            self.filter.predict(step.travelled_m, step.turned_rad);
        }
        self.start_distance_m.get_or_insert(m.distance_m);
        self.held = self
            .hold
            .see(&link.last_usable, link.last_usable_s, m.distance_m);
        self.camera_unfused |= self.held.new;
        // The camera is there while its link has a usable row, whether or not the filter
        // takes it (a weed patch, a gap held at low quality); not when it has repeated
        // one estimate for longer than it may be held, nor when the odometry kept (which
        // starts afresh in each autonomous spell) no longer reaches back to its image.
        let (_, reaches) = self.odometry.since(self.held.first_s - self.latency_s);
        self.held_ok = self.held.held_m <= self.gap_hold_m && (reaches || !self.held.repeated);
        if self.held_ok {
            self.camera_good_s = self.camera_good_s.max(link.last_usable_s);
        }
        self.camera_trouble = if link.problem.is_some() {
            "the camera's link is down"
        } else if !self.held_ok {
            "the camera has sent the same estimate for longer than [camera] gap_hold_m (a gap in the row, or its end)"
        } else {
            NO_USABLE_ROW
        };
    }

    /// The steer tick in autonomous mode at `now_s`, after `watch`: the row to steer by,
    /// or None.
    pub fn tick(
        &mut self,
        now_s: f64,
        m: &Measured,
        link: &LinkStatus,
        gnss: &GnssStatus,
        cruise_mps: f64,
    ) -> Option<RowChoice> {
        let camera_fresh = now_s - link.last_usable_s < self.link_timeout_s && self.held_ok;
        // A repeated estimate tells the filter nothing new; a new one that came during
        // an end-switch procedure is fused now, at its capture pose.
        if self.s.source != SteerSource::Gnss && self.camera_unfused {
            self.camera_unfused = false;
            self.fuse_camera(link);
        }
        if self.s.source != SteerSource::Camera {
            self.fuse_gnss(gnss, m.distance_m);
        }
        self.steering = self.choose(now_s, camera_fresh);
        let searching = self.searching(now_s, m, link);
        let (camera_heard, gnss_heard) = (
            self.camera_good_s > self.reset_s,
            self.gnss_good_s > self.reset_s,
        );
        let heard = match self.steering {
            Steering::Fused => camera_heard || gnss_heard,
            Steering::FilterCamera | Steering::Camera => camera_heard,
            Steering::FilterGnss => gnss_heard,
            Steering::Nothing => false,
        };
        let speed_mps = match (self.steering, self.s.source) {
            _ if searching => cruise_mps.min(self.gap_speed_mps),
            _ if !heard => return None,
            (Steering::Camera, _) if self.held.repeated => cruise_mps.min(self.gap_speed_mps),
            // Fused that lost its camera slows down, and GNSS alone on a fix less than
            // RTK fixed; GNSS chosen alone on RTK fixed does not.
            (Steering::FilterGnss, source)
                if source == SteerSource::Fused
                    || self.last_fix_used.is_some_and(|(q, _)| degraded(q)) =>
            {
                cruise_mps.min(self.s.gnss_only_speed_mps)
            }
            _ => cruise_mps,
        };
        let (offset_m, angle_rad) = self.filter.row_at(self.camera_x_m);
        // The filter's row is of now, yet it goes to the law as old as a camera row is on
        // average (latency and half a steer period): moving a row through its age damps
        // the robot's turning and lengthens the look-ahead with speed, as the law's gains
        // expect. As of now, the fused robot at 2 m/s swung off its row in 8 of 30 runs.
        Some(RowChoice {
            estimate: RowEstimate {
                seq: 0,
                angle_rad,
                offset_m,
                quality: 100,
            },
            since: Travel::at_rates(m.speed_mps, m.yaw_rate_rps, self.law_age_s),
            speed_mps,
        })
    }

    /// The camera alone, with no row seen yet in this spell: after [steer]
    /// camera_fallback_s standing, and within [camera] first_row_m of where it began, the
    /// robot drives straight ahead to find its first plants, and only while the camera's
    /// link brings frames (of any quality): a silent camera would never see them.
    fn searching(&mut self, now_s: f64, m: &Measured, link: &LinkStatus) -> bool {
        let heard = self.camera_good_s > self.reset_s;
        let live = link.connected && now_s - link.last_row_s <= self.link_timeout_s;
        let driven_m = m.distance_m - self.start_distance_m.unwrap_or(m.distance_m);
        // Standing for the camera's fall-back time first: its first frames may be on the way.
        let waited = now_s - self.reset_s >= self.s.camera_fallback_s;
        self.searching = self.s.source == SteerSource::Camera
            && live
            && !heard
            && waited
            && driven_m < self.first_row_m;
        self.searching
    }

    /// Which sensors steer, from how long each has been without a good measurement:
    /// GNSS alone is lost after [gnss] timeout_s; fused falls back after its own times.
    fn choose(&self, now_s: f64, camera_fresh: bool) -> Steering {
        let camera_ok = now_s - self.camera_good_s <= self.s.camera_fallback_s;
        let gnss_lost_after_s = match self.s.source {
            SteerSource::Gnss => self.gnss.timeout_s,
            _ => self.s.gnss_fallback_s,
        };
        let gnss_ok = now_s - self.gnss_good_s <= gnss_lost_after_s;
        match (self.s.source, camera_ok, gnss_ok) {
            (SteerSource::Camera, _, _) if camera_fresh => Steering::Camera,
            (SteerSource::Gnss, _, true) => Steering::FilterGnss,
            (SteerSource::Fused, true, true) => Steering::Fused,
            (SteerSource::Fused, true, false) => Steering::FilterCamera,
            (SteerSource::Fused, false, true) => Steering::FilterGnss,
            _ => Steering::Nothing,
        }
    }
}

//! The run report: a short summary for a person at exit, and JSON for scripts.

use mechweed_hw::camproto::LinkCounters;
use mechweed_hw::sim::CrossTrackSummary;
use serde::Serialize;

use crate::bus::BusFigures;

use crate::record::RecordOutcome;
use crate::record::summary::cross_track_words;
use crate::rt::{LiuLayland, LoopSummary, liu_layland};
use crate::run::RunOutcome;
use crate::state::modes::Mode;

#[derive(Debug, Serialize)]
pub(crate) struct FaultEntry {
    pub t_s: f64,
    pub cause: String,
    pub what_to_check: &'static str,
    /// The same kind of cause came back this long after the power-up that cleared it,
    /// s; null: it did not.
    pub came_back_after_s: Option<f64>,
    /// Supervisor ticks from the first tick that saw the cause to the one that wrote
    /// safe outputs.
    pub safe_after_ticks: u64,
}

#[derive(Debug, Serialize)]
pub(crate) struct NoticeEntry {
    pub t_s: f64,
    pub what: String,
}

#[derive(Debug, Serialize)]
pub(crate) struct Loops {
    pub supervisor: LoopSummary,
    pub steer: LoopSummary,
    /// Liu and Layland's check of the two periodic loops' measured worst cases.
    pub liu_layland: LiuLayland,
}

/// The camera link's figures: every decoder counter and the link's own.
#[derive(Debug, Serialize)]
pub(crate) struct LinkReport {
    #[serde(flatten)]
    pub counters: LinkCounters,
    pub starts_sent: u64,
    pub stops_sent: u64,
    pub reconnects: u64,
    pub pings_sent: u64,
    /// Round trip of the last PING, ms (null if no PONG came back).
    pub ping_rtt_ms: Option<f64>,
}

/// The tool's cross-track figures in cm (share as a fraction 0..1 of distance); null
/// where nothing was measured, so that no data never reads as a perfect run.
#[derive(Debug, Serialize)]
pub(crate) struct CrossTrackReport {
    /// Travel before this distance is left out, m.
    pub from_m: f64,
    pub mean_cm: Option<f64>,
    pub sd_cm: Option<f64>,
    pub rms_cm: Option<f64>,
    pub p95_cm: Option<f64>,
    pub max_cm: Option<f64>,
    pub share_over_2cm: Option<f64>,
    /// Distance over which the error was measured, m.
    pub distance_m: f64,
}

impl CrossTrackReport {
    fn new(summary: Option<CrossTrackSummary>, from_m: f64) -> CrossTrackReport {
        let c = summary.filter(|c| c.distance_m > 0.0);
        CrossTrackReport {
            from_m,
            mean_cm: c.map(|c| c.mean_cm),
            sd_cm: c.map(|c| c.sd_cm),
            rms_cm: c.map(|c| c.rms_cm),
            p95_cm: c.map(|c| c.p95_cm),
            max_cm: c.map(|c| c.max_cm),
            share_over_2cm: c.map(|c| c.share_over_2cm),
            distance_m: c.map_or(0.0, |c| c.distance_m),
        }
    }
}

/// The exit status of a run that ended in Fault (docs/commands.md), so that a script or
/// the service manager sees it; 1 is a run that could not start, 2 a wrong command line.
pub const EXIT_FAULT: u8 = 3;

#[derive(Debug, Serialize)]
pub(crate) struct Report {
    pub mode_final: String,
    /// The program's exit status for this run: 0, or EXIT_FAULT when it ended in Fault.
    pub exit_code: u8,
    pub faults: Vec<FaultEntry>,
    pub notices: Vec<NoticeEntry>,
    pub distance_m: f64,
    pub cross_track_cm: CrossTrackReport,
    /// False on the real robot, where there are no cross-track figures.
    #[serde(skip)]
    simulated: bool,
    /// The simulated robot steered by an outside camera: its cross-track figures are null,
    /// since the camera's rows are not the simulated field's.
    pub outside_camera: bool,
    pub loops: Loops,
    pub link: LinkReport,
    /// Real-time settings the system refused (the run went on without them).
    pub rt_warnings: Vec<String>,
    /// The run's record: its files, ticks recorded and dropped, and any problem.
    pub record: RecordOutcome,
    /// What the bus published and answered.
    pub bus: BusFigures,
    /// Where the bus listened and connected.
    pub bus_endpoints: String,
    /// The GNSS receiver's link (null without a receiver).
    pub gnss: Option<GnssReport>,
    /// The row filter (null when the camera steered alone).
    pub filter: Option<FilterReport>,
}

/// What came from the GNSS receiver.
#[derive(Debug, Serialize)]
pub(crate) struct GnssReport {
    /// Epochs with a position, and without.
    pub fixes: u64,
    pub no_fix_epochs: u64,
    /// Every line by its kind, and every line skipped by why.
    pub sentences: mechweed_hw::nmea::NmeaCounters,
    /// The last fix's quality in words (null: none came).
    pub last_quality: Option<&'static str>,
}

/// What the row filter did.
#[derive(Debug, Serialize)]
pub(crate) struct FilterReport {
    /// Which sensors steered at the end.
    pub steering: &'static str,
    /// Measurements its gate rejected (a weed patch, an RTK jump).
    pub camera_rejected: u64,
    pub gnss_rejected: u64,
    /// Its estimate's s.d. at the end, cm.
    pub offset_sd_cm: f64,
}

/// Said at the start and in the summary of a simulated run with an outside camera.
pub(crate) const OUTSIDE_CAMERA: &str = "no cross-track figures: the camera is outside (camera.port), so the simulated field's rows are not the ones steered along and its cross-track is not meaningful";

/// One loop's figures on one line.
pub(crate) fn loop_line(name: &str, l: &LoopSummary) -> String {
    let (late, exec) = (&l.late_us, &l.exec_us);
    format!(
        "{name} loop: {} ticks at {} Hz, {} overruns, late p50/p99/p99.9/max {}/{}/{}/{} us, exec p50/p99/p99.9/max {}/{}/{}/{} us, worst lock {} us ({} busy)",
        l.ticks,
        l.rate_hz,
        l.overruns,
        late.p50,
        late.p99,
        late.p999,
        late.max,
        exec.p50,
        exec.p99,
        exec.p999,
        exec.max,
        l.worst_lock_us,
        l.locks_busy
    )
}

impl Report {
    pub(crate) fn from_run(run: &RunOutcome) -> Report {
        Report {
            mode_final: run.final_status.mode.name().to_string(),
            exit_code: match run.final_status.mode {
                _ if run.supervisor_panicked => EXIT_FAULT,
                Mode::Fault => EXIT_FAULT,
                _ => 0,
            },
            faults: run
                .faults
                .iter()
                .map(|f| FaultEntry {
                    t_s: f.t_s,
                    cause: f.cause.to_string(),
                    what_to_check: f.cause.what_to_check(),
                    came_back_after_s: f.came_back_after_s,
                    safe_after_ticks: f.tick_safe - f.tick_seen,
                })
                .collect(),
            notices: run
                .notices
                .iter()
                .map(|n| NoticeEntry {
                    t_s: n.t_s(),
                    what: n.to_string(),
                })
                .collect(),
            distance_m: run.final_status.measured.distance_m,
            cross_track_cm: CrossTrackReport::new(run.cross_track, run.cross_track_from_m),
            simulated: run.cross_track.is_some(),
            outside_camera: run.outside_camera,
            loops: Loops {
                supervisor: run.supervisor_loop,
                steer: run.steer_loop,
                liu_layland: liu_layland(&[run.supervisor_loop, run.steer_loop]),
            },
            rt_warnings: run.rt_warnings.clone(),
            link: LinkReport {
                counters: run.link.counters,
                starts_sent: run.link.starts_sent,
                stops_sent: run.link.stops_sent,
                reconnects: run.link.reconnects,
                pings_sent: run.link.pings_sent,
                ping_rtt_ms: (!run.link.ping_rtt_ms.is_nan()).then_some(run.link.ping_rtt_ms),
            },
            record: run.record.clone(),
            bus: run.bus,
            bus_endpoints: run.bus_endpoints.clone(),
            gnss: run.gnss.map(|g| GnssReport {
                fixes: g.fixes,
                no_fix_epochs: g.no_fix_epochs,
                sentences: g.sentences,
                last_quality: g.last_fix.map(|f| f.quality.words()),
            }),
            filter: run.steer.row.filter.map(|f| FilterReport {
                steering: run.steer.sources.steering.name(),
                camera_rejected: f.camera_rejected,
                gnss_rejected: f.gnss_rejected,
                offset_sd_cm: f.offset_sd_m * 100.0,
            }),
        }
    }

    /// A few lines for the terminal.
    pub(crate) fn human(&self) -> String {
        let mut out = String::new();
        out += &format!(
            "final mode: {}, distance {:.2} m\n",
            self.mode_final, self.distance_m
        );
        if self.exit_code == EXIT_FAULT {
            out += &format!("the run ended in fault: mechweed exits with status {EXIT_FAULT}\n");
        }
        if self.faults.is_empty() {
            out += "faults: none\n";
        }
        for f in &self.faults {
            out += &format!(
                "fault at {:.2} s: {} (safe outputs after {} ticks)\n",
                f.t_s, f.cause, f.safe_after_ticks
            );
            if let Some(after_s) = f.came_back_after_s {
                out += &format!("  {}\n", crate::state::fault_advice::CameBack { after_s });
            }
            out += &format!("  what to check: {}\n", f.what_to_check);
        }
        for n in &self.notices {
            out += &format!("at {:.2} s: {}\n", n.t_s, n.what);
        }
        out += &self.cross_track_line();
        for (name, l) in [
            ("supervisor", &self.loops.supervisor),
            ("steer", &self.loops.steer),
        ] {
            out += &loop_line(name, l);
            out += "\n";
        }
        out += &format!("Liu-Layland: {}\n", self.loops.liu_layland.words());
        for warning in &self.rt_warnings {
            out += &format!("real-time: {warning}\n");
        }
        out += &self.links_lines();
        out += &self.bus.line();
        if self.bus.state != crate::bus::BusState::Off {
            out += &format!(" ({})", self.bus_endpoints);
        }
        out += "\n";
        out += &record_lines(&self.record);
        out
    }

    /// The camera link's, the GNSS link's and the row filter's counters.
    fn links_lines(&self) -> String {
        let mut out = String::new();
        let k = &self.link.counters;
        out += &format!(
            "camera link: {} frames, {} CRC errors, {} resyncs, {} sequence gaps, {} duplicates, {} bytes skipped, {} bad estimates, {} reconnects, ping {}\n",
            k.frames_ok,
            k.crc_errors,
            k.resyncs,
            k.seq_gaps,
            k.duplicates,
            k.bytes_skipped,
            k.bad_values,
            self.link.reconnects,
            self.link
                .ping_rtt_ms
                .map_or("-".to_string(), |ms| format!("{ms:.1} ms")),
        );
        if let Some(g) = &self.gnss {
            let k = &g.sentences;
            out += &format!(
                "GNSS: {} fixes (last {}), {} epochs without one; {} checksum errors, {} unknown kinds, {} malformed, {} overlong lines\n",
                g.fixes,
                g.last_quality.unwrap_or("none"),
                g.no_fix_epochs,
                k.checksum_errors,
                k.unknown_kinds,
                k.malformed,
                k.overlong
            );
        }
        if let Some(f) = &self.filter {
            out += &format!(
                "row filter: steering by {} at the end; gate rejected {} camera rows and {} GNSS fixes; row s.d. {:.2} cm\n",
                f.steering, f.camera_rejected, f.gnss_rejected, f.offset_sd_cm
            );
        }
        out
    }

    /// The tool's cross-track figures, or why there are none.
    fn cross_track_line(&self) -> String {
        let c = &self.cross_track_cm;
        let from_m = c.from_m;
        match (
            c.mean_cm,
            c.sd_cm,
            c.rms_cm,
            c.p95_cm,
            c.max_cm,
            c.share_over_2cm,
        ) {
            (
                Some(mean_cm),
                Some(sd_cm),
                Some(rms_cm),
                Some(p95_cm),
                Some(max_cm),
                Some(share_over_2cm),
            ) => {
                let figures = CrossTrackSummary {
                    mean_cm,
                    sd_cm,
                    rms_cm,
                    p95_cm,
                    max_cm,
                    share_over_2cm,
                    distance_m: c.distance_m,
                };
                format!("{}\n", cross_track_words(&figures, from_m))
            }
            _ if self.outside_camera => format!("{OUTSIDE_CAMERA}\n"),
            _ if !self.simulated => {
                "tool cross-track: none (only the simulated robot knows where the row is)\n".into()
            }
            _ if self.distance_m < from_m => format!(
                "no cross-track figures: the robot drove {:.1} m, fewer than the first {from_m} m left out (--from-m)\n",
                self.distance_m
            ),
            _ => format!(
                "no cross-track figures: no travel along the row from {from_m} m on (--from-m)\n"
            ),
        }
    }
}

/// The summary a run prints as it ends (`mechweed run`), from its outcome.
pub fn closing_summary(run: &RunOutcome) -> String {
    Report::from_run(run).human()
}

/// Where a run's record went, and how whole it is (`run` and `bench loop`).
pub(crate) fn record_lines(r: &RecordOutcome) -> String {
    let mut out = String::new();
    if r.files.is_empty() {
        out += "record: none\n";
    } else {
        out += &format!(
            "record: {} ({} ticks recorded, {} dropped)\n",
            r.files.join(", "),
            r.ticks_recorded,
            r.ticks_dropped
        );
    }
    for problem in &r.problems {
        out += &format!("record: {problem}\n");
    }
    if r.events_dropped > 0 {
        out += &format!("record: {} events dropped\n", r.events_dropped);
    }
    out
}

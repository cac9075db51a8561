//! `mechweed record --bus`: an off-board recorder. On another computer (a laptop at the
//! field's edge) it writes the same CSV and MCAP files as the robot's own record, from
//! the ticks and events the robot publishes, and counts what the network dropped: a gap
//! in the tick numbers is written into the record as a `dropped` event, where it
//! happened. The robot publishes every `[bus] tick_every_n`th tick, so the record has
//! that many fewer rows than the robot's own. This file is the recorder's bus side (its
//! subscribers and its loop); what it does with a received tick is record/off_board.rs.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::bus::hearing::{Ear, Hearing};
use crate::config::{Backend, CameraPort, RecordSettings};
use crate::programs::bus::tools::Tool;
use crate::record::off_board::{Recording, RobotSays};
use crate::record::received::{parse_event, parse_tick};
use crate::state::cross_track::CrossTrackMeaning;

/// Messages waiting for the recorder's thread; beyond this they are dropped here and
/// counted (this computer fell behind).
const QUEUE: usize = 4096;
/// Bad messages are counted; the first few are also said.
const SAY_BAD: u64 = 5;

pub struct Options {
    pub connect: String,
    pub robot: String,
    /// Stop after this long (None: at Ctrl-C).
    pub seconds: Option<f64>,
    pub record: RecordSettings,
    /// This program's identity on a secured bus; None, plain TCP.
    pub tls: Option<crate::config::TlsFiles>,
}

/// Record until `stop` (Ctrl-C) or `seconds`; returns the closing summary.
pub fn record(opts: &Options, stop: &AtomicBool) -> Result<String, String> {
    let tool = Tool::connect(&opts.connect, &opts.robot, true, opts.tls.as_ref())?;
    let hearing = Hearing::start(Ear {
        endpoint: opts.connect.clone(),
        robot: opts.robot.clone(),
        tls: opts.tls.clone(),
        token: format!("alive/record-{}", std::process::id()),
        flows: vec![(true, "tick"), (false, "event")],
        program: "off-board recorder",
        queue: QUEUE,
    })?;
    println!(
        "off-board recorder: waiting for the ticks of {} at {}",
        opts.robot, opts.connect
    );
    let end = opts
        .seconds
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let setting = |key: &str| -> Option<String> {
        let answer = tool.ask(key, None).ok()?;
        let json: serde_json::Value = serde_json::from_str(&answer).ok()?;
        Some(json["value"].as_str()?.to_string())
    };
    let mut ask = || RobotSays {
        every_n: setting("config/bus/tick_every_n")
            .and_then(|n| n.parse().ok())
            .unwrap_or(1),
        cross_track: cross_track_of(
            setting("config/hw/backend").as_deref(),
            setting("config/camera/port").as_deref(),
        ),
    };
    let mut recording = Recording::new(&mut ask, &opts.record);
    while !stop.load(Ordering::Relaxed) && end.is_none_or(|end| Instant::now() < end) {
        let Ok((is_tick, bytes, _)) = hearing.rx.recv_timeout(Duration::from_millis(100)) else {
            continue;
        };
        let parsed = if is_tick {
            parse_tick(&bytes).map(|tick| recording.received_tick(&tick))
        } else {
            parse_event(&bytes).map(|event| recording.received_event(event))
        };
        if let Err(why) = parsed {
            recording.counts.bad += 1;
            hearing.unreadable();
            if recording.counts.bad <= SAY_BAD {
                let what = if is_tick { "a tick" } else { "an event" };
                eprintln!("off-board recorder: {what} that cannot be recorded: {why}");
            }
        }
        if let Some(why) = recording.broken.take() {
            recording.close();
            return Err(format!("off-board recorder: {why}"));
        }
    }
    recording.close();
    let c = &recording.counts;
    let files = if c.files.is_empty() {
        "no record (no tick arrived)".to_string()
    } else {
        c.files.join(", ")
    };
    Ok(format!(
        "off-board record of {}: {} ticks and {} events into {files}; {} ticks missing between those received (the network or the robot's bus queue dropped them), {} dropped on this computer, {} messages refused{}",
        opts.robot,
        c.ticks,
        c.events,
        c.missing,
        hearing.counts.dropped_here.load(Ordering::Relaxed),
        c.bad,
        hearing.line()
    ))
}

/// The robot's cross-track meaning from its `[hw] backend` and `[camera] port`, by the
/// one rule (cross_track.rs); a robot that does not say vouches for no figure.
fn cross_track_of(backend: Option<&str>, port: Option<&str>) -> CrossTrackMeaning {
    let backend = match backend {
        Some("sim") => Backend::Sim,
        Some("cards") => Backend::Cards,
        _ => return CrossTrackMeaning::Unknown,
    };
    // The baud does not matter to the rule; any of the camera's will do.
    match port.map(|p| CameraPort::parse(p, 115_200)) {
        Some(Ok(port)) => CrossTrackMeaning::of_robot(backend, &port),
        _ => CrossTrackMeaning::Unknown,
    }
}

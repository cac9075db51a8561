//! `mechweed replay RECORD [--set SECTION.KEY=VALUE]... [--from S] [--to S] [--json FILE]`:
//! the recorded inputs of every tick (the inputs, the steer command and link status as
//! the supervisor saw them, the threads' health, the operator's requests at their ticks)
//! fed through the same supervisor code, tick by tick, as fast as it goes.
//!
//! Without `--set` it must give every recorded output again, exactly: a test that the
//! code in hand is the code that drove. With `--set` it is a what-if on the same inputs
//! (open loop: the plant does not answer the new outputs) and writes a record of its
//! own beside the old. `--from`/`--to` limit what is compared and reported; the
//! supervisor still runs from the first tick, since its filters and integrators
//! remember everything before.

mod recorded;
mod row;
mod steer;

use std::path::{Path, PathBuf};

use mechweed_hw::Outputs;

use crate::config::Settings;
use crate::record::header::program;
use crate::record::request_text::{answer_text, request_text};
use crate::record::{self, Delivery, RecordTap};
use crate::state::modes::Mode;
use crate::supervisor::Supervisor;
pub use recorded::{Recorded, RecordedTick, read_for_replay};
use steer::SteerReplay;
pub use steer::{ANGLE_TOLERANCE_DEG, SPEED_TOLERANCE_MPS, SteerFigures};

pub struct ReplayOptions {
    pub record: PathBuf,
    pub set: Vec<String>,
    pub from_s: f64,
    pub to_s: f64,
}

/// The first place the replay and the record part.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    pub tick: u64,
    pub t_s: f64,
    pub what: String,
    pub recorded: String,
    pub replayed: String,
}

/// A fault: when, and in words.
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    pub tick: u64,
    pub t_s: f64,
    pub words: String,
}

pub struct Outcome {
    pub ticks: usize,
    /// Ticks inside --from/--to, compared.
    pub compared: usize,
    pub requests: usize,
    pub first_difference: Option<Difference>,
    pub faults_recorded: Vec<Fault>,
    pub faults_replayed: Vec<Fault>,
    /// The steering law replayed from the recorded estimates.
    pub steer: SteerFigures,
    /// The what-if's record (with --set).
    pub written: Vec<String>,
    pub notes: Vec<String>,
}

/// Replay a record; the error says why it cannot be replayed.
pub fn replay(opts: &ReplayOptions) -> Result<Outcome, String> {
    let rec = read_for_replay(&opts.record)?;
    let (settings, mut notes) = settings_and_notes(&rec, &opts.set)?;
    let mut whatif = match opts.set.is_empty() {
        true => None,
        false => Some(start_whatif(&rec.file, &settings)?),
    };
    let in_window = |t_s: f64| t_s >= opts.from_s && t_s <= opts.to_s;
    let mut sup = Supervisor::new(&settings);
    let mut steer = SteerReplay::new(&settings);
    let mut first: Option<Difference> = None;
    let mut compared = 0;
    let mut requests = 0;
    for t in &rec.ticks {
        for r in rec.requests.get(&t.tick).into_iter().flatten() {
            requests += 1;
            let answer = sup.handle(r.request);
            if let Some(law) = sup.take_steer_settings() {
                steer.settings(&law);
            }
            if let Some((tap, _)) = whatif.as_mut() {
                tap.requested(t.t_s, t.tick, r.request, answer);
            }
            let now = answer_text(&answer);
            if first.is_none() && in_window(t.t_s) && now != r.answer {
                first = Some(Difference {
                    tick: t.tick,
                    t_s: t.t_s,
                    what: format!("the answer to '{}'", request_text(&r.request)),
                    recorded: r.answer.clone(),
                    replayed: now,
                });
            }
        }
        steer.before_tick(&t.steer, &t.link, in_window(t.t_s));
        match t.given.hw_failed {
            Some(f) if f.during == "read" => {
                sup.hardware_failed(t.t_s, f.card);
            }
            failed => {
                sup.tick(t.t_s, &t.inputs, &t.steer, &t.link, &t.given.health);
                if let Some(f) = failed {
                    sup.hardware_failed(t.t_s, f.card);
                }
            }
        }
        let status = sup.status();
        steer.after_tick(status, &t.link);
        if in_window(t.t_s) {
            compared += 1;
            if first.is_none() {
                first = differ(t, &status.outputs, status.mode);
            }
        }
        if let Some((tap, _)) = whatif.as_mut() {
            tap.offer(status, &t.steer, &t.link, None, &t.given);
        }
    }
    let written = match whatif {
        Some((tap, recorder)) => {
            drop(tap);
            let outcome = recorder.finish();
            notes.extend(outcome.problems);
            outcome.files
        }
        None => Vec::new(),
    };
    let (faults_recorded, faults_replayed) = faults(&rec, &sup);
    Ok(Outcome {
        ticks: rec.ticks.len(),
        compared,
        requests,
        first_difference: first,
        faults_recorded,
        faults_replayed,
        steer: steer.figures,
        written,
        notes,
    })
}

/// The run's settings with `set`, and the notes a reader of the replay needs. A record
/// made before a setting existed has its settings upgraded as `config upgrade` would
/// (the values that keep the older behaviour), and the replay says so.
fn settings_and_notes(rec: &Recorded, set: &[String]) -> Result<(Settings, Vec<String>), String> {
    let unusable = |errors: Vec<crate::config::ConfigError>| {
        let lines: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        format!(
            "the run's settings with --set are not usable:\n{}",
            lines.join("\n")
        )
    };
    let mut notes = rec.notes.clone();
    let settings = match rec.header.settings(set) {
        Ok(settings) => settings,
        Err(errors)
            if errors.iter().any(|e| {
                e.what.ends_with(" is missing") || e.what.starts_with("missing section")
            }) =>
        {
            let Ok((text, added)) = crate::config::upgrade::upgrade(&rec.header.settings_text)
            else {
                return Err(unusable(errors));
            };
            let upgraded = crate::record::header::RunHeader {
                settings_text: text,
                ..rec.header.clone()
            };
            let settings = upgraded.settings(set).map_err(unusable)?;
            let names: Vec<String> = (added.iter().take(4))
                .map(|a| format!("[{}] {} = {}", a.section, a.key, a.value))
                .collect();
            notes.push(format!(
                "the record's settings are of an older release: {} settings it lacked were taken as `mechweed config upgrade` gives them ({}{})",
                added.len(),
                names.join(", "),
                if added.len() > 4 { ", ..." } else { "" }
            ));
            settings
        }
        Err(errors) => return Err(unusable(errors)),
    };
    if rec.header.program != program() {
        notes.push(format!(
            "recorded by {}, replayed by {}: a difference may be a change of the code",
            rec.header.program,
            program()
        ));
    }
    Ok((settings, notes))
}

/// The faults the record holds, and those the replay found, each with its tick and time.
fn faults(rec: &Recorded, sup: &Supervisor) -> (Vec<Fault>, Vec<Fault>) {
    let t_of = |tick: u64| {
        rec.ticks
            .get(tick.saturating_sub(1) as usize)
            .map_or(f64::NAN, |t| t.t_s)
    };
    let faults_recorded = (rec.faults.iter())
        .map(|(tick, words)| Fault {
            tick: *tick,
            t_s: t_of(*tick),
            words: words.clone(),
        })
        .collect();
    let faults_replayed = (sup.faults().iter())
        .map(|f| Fault {
            tick: f.tick_seen,
            t_s: f.t_s,
            words: f.cause.to_string(),
        })
        .collect();
    (faults_recorded, faults_replayed)
}

/// The first output (or the mode) in which the replayed tick parts from the recorded.
fn differ(t: &RecordedTick, out: &Outputs, mode: Mode) -> Option<Difference> {
    let r = &t.outputs;
    let numbers = [
        ("amp_left_v", r.amp_left_v, out.amp_left_v),
        ("amp_right_v", r.amp_right_v, out.amp_right_v),
        ("amp_steer_v", r.amp_steer_v, out.amp_steer_v),
    ];
    let flags = [
        ("main_power_on", r.main_power_on, out.main_power_on),
        (
            "brake_release_left",
            r.brake_release_left,
            out.brake_release_left,
        ),
        (
            "brake_release_right",
            r.brake_release_right,
            out.brake_release_right,
        ),
        ("tool_on", r.tool_on, out.tool_on),
    ];
    let found = |what: &str, recorded: String, replayed: String| {
        Some(Difference {
            tick: t.tick,
            t_s: t.t_s,
            what: what.into(),
            recorded,
            replayed,
        })
    };
    if t.mode != mode {
        return found("mode", t.mode.to_string(), mode.to_string());
    }
    for (what, a, b) in numbers {
        // Exactly: the record holds every number's shortest exact form.
        if a.to_bits() != b.to_bits() && !(a == 0.0 && b == 0.0) {
            return found(what, format!("{a:?}"), format!("{b:?}"));
        }
    }
    for (what, a, b) in flags {
        if a != b {
            return found(what, u8::from(a).to_string(), u8::from(b).to_string());
        }
    }
    None
}

/// The what-if's record: NAME-whatif beside NAME, every tick, waiting for the disk.
fn start_whatif(file: &Path, settings: &Settings) -> Result<(RecordTap, record::Recorder), String> {
    let mut settings = settings.clone();
    settings.record.folder = file
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    settings.record.every_n_ticks = 1;
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    record::start_named(
        &settings,
        &format!("{stem}-whatif"),
        0,
        None,
        Delivery::WaitForRoom,
    )
    .map_err(|e| format!("cannot write the what-if's record: {e}"))
}

//! `mechweed record summary FILE`: a record's figures, to check a run from the
//! terminal: duration, distance, modes, faults with their causes, notices, and the
//! tool's cross-track error.
//!
//! The cross-track figures are the run report's, by the same code on the same points
//! (mechweed_hw::sim::TickCrossTrack): each recorded tick's error weighs as much as the
//! distance the robot truly drove since the recorded tick before, from 5 m on until the
//! tool passes the row's end. A record of every tick gives the report's figures to the
//! last digit; `--from-m` moves the start, for short runs.

use std::fmt::Write;
use std::path::Path;

use mechweed_hw::sim::{CrossTrackSummary, TickCrossTrack};

use super::error::{ReadProblem, RecordError};
use super::header::RunHeader;
use super::read::{Record, read};
use crate::state::cross_track::CrossTrackMeaning;

/// The columns the summary needs.
const WANTED: [&str; 7] = [
    "t_s",
    "tick",
    "mode",
    "distance_m",
    "sim_tool_cross_track_m",
    "sim_distance_m",
    "sim_row_done",
];

#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub file: String,
    pub ticks: usize,
    pub ticks_dropped: u64,
    pub first_t_s: f64,
    pub last_t_s: f64,
    /// Odometry, from the first recorded tick to the last, m.
    pub distance_m: f64,
    /// (time, mode) at the first tick and at each change.
    pub modes: Vec<(f64, String)>,
    /// (time, cause); None if the record has no events.
    pub faults: Option<Vec<(f64, String)>>,
    pub notices: Vec<(f64, String)>,
    pub from_m: f64,
    /// None: not a simulated run, so no cross-track error was recorded.
    pub cross_track: Option<CrossTrackSummary>,
    /// What the record's header says the cross-track is worth (meaningful without one).
    pub cross_track_meaning: CrossTrackMeaning,
    pub notes: Vec<String>,
}

/// Read a record (CSV or MCAP) and work out its figures.
pub fn summarise(path: &Path, from_m: f64) -> Result<Summary, RecordError> {
    let record = read(path, &WANTED)?;
    let mut summary = figures(&record, from_m).map_err(|problem| RecordError::Read {
        file: path.to_path_buf(),
        problem,
    })?;
    // The header beside the record says whether the run's cross-track means anything.
    if let Some(header) = RunHeader::beside(path).filter(|h| h.exists()) {
        match RunHeader::read(&header) {
            Ok(header) => summary.cross_track_meaning = header.cross_track,
            Err(why) => summary
                .notes
                .push(format!("its header cannot be read: {why}")),
        }
    }
    Ok(summary)
}

/// The tool's cross-track figures in the words of the run report and `record summary`
/// alike, at the precision both show.
pub fn cross_track_words(c: &CrossTrackSummary, from_m: f64) -> String {
    format!(
        "tool cross-track (after the first {from_m} m, over {:.2} m): mean {:.2} cm, s.d. {:.2} cm, RMS {:.2} cm, p95 {:.2} cm, max {:.2} cm, {:.1} % of distance over 2 cm",
        c.distance_m,
        c.mean_cm,
        c.sd_cm,
        c.rms_cm,
        c.p95_cm,
        c.max_cm,
        c.share_over_2cm * 100.0
    )
}

fn figures(record: &Record, from_m: f64) -> Result<Summary, ReadProblem> {
    let t = &record.ticks;
    let n = t.rows.len();
    if n == 0 {
        return Err(ReadProblem::NoTicks);
    }
    // Columns exist: read() checked them.
    let [c_t, c_tick, c_mode, c_dist, c_err, c_sim_d, c_done] =
        WANTED.map(|w| t.column(w).unwrap_or(0));
    let num = |row: usize, col: usize| t.number(row, col);
    let need = |row: usize, col: usize| -> Result<f64, ReadProblem> {
        num(row, col)?.ok_or_else(|| ReadProblem::EmptyCell {
            place: t.places[row].clone(),
            column: t.columns[col].clone(),
        })
    };

    let mut modes: Vec<(f64, String)> = Vec::new();
    let mut gaps = Vec::new();
    let mut cross_track = TickCrossTrack::new(from_m);
    let mut simulated = false;
    let mut last_tick: Option<f64> = None;
    for row in 0..n {
        let mode = t.text(row, c_mode);
        if modes.last().is_none_or(|(_, m)| *m != mode) {
            modes.push((need(row, c_t)?, mode));
        }
        let tick = need(row, c_tick)?;
        if let Some(last) = last_tick.replace(tick) {
            gaps.push(tick - last);
        }
        let error_m = num(row, c_err)?;
        let sim_m = num(row, c_sim_d)?;
        simulated |= error_m.is_some();
        if let (Some(e), Some(d)) = (error_m, sim_m) {
            cross_track.tick(e, d, num(row, c_done)? == Some(1.0));
        }
    }
    // Recorded every Nth tick: the smallest gap is N; larger gaps are dropped ticks.
    let every = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    let dropped = gaps.iter().map(|g| (g / every).round() - 1.0).sum::<f64>();

    let (faults, notices) = events(record)?;
    let first_t_s = need(0, c_t)?;
    let last_t_s = need(n - 1, c_t)?;
    Ok(Summary {
        file: record.file.display().to_string(),
        ticks: n,
        ticks_dropped: if dropped.is_finite() {
            dropped as u64
        } else {
            0
        },
        first_t_s,
        last_t_s,
        distance_m: need(n - 1, c_dist)? - need(0, c_dist)?,
        modes,
        faults,
        notices,
        from_m,
        cross_track: simulated.then(|| cross_track.summary()),
        // Until the header beside the record says otherwise.
        cross_track_meaning: CrossTrackMeaning::Unknown,
        notes: record.notes.clone(),
    })
}

/// The record's faults (None without an events file) and notices, each with its time.
#[allow(clippy::type_complexity)]
fn events(
    record: &Record,
) -> Result<(Option<Vec<(f64, String)>>, Vec<(f64, String)>), ReadProblem> {
    let mut faults = None;
    let mut notices = Vec::new();
    if let Some(events) = &record.events {
        let mut found = Vec::new();
        for row in 0..events.rows.len() {
            let when = events.number(row, 0)?.unwrap_or(f64::NAN);
            match events.text(row, 2).as_str() {
                "fault" => found.push((when, events.text(row, 3))),
                "notice" => notices.push((when, events.text(row, 3))),
                _ => {}
            }
        }
        faults = Some(found);
    }
    Ok((faults, notices))
}

impl Summary {
    /// A few lines for the terminal, like the run report's.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "record: {}", self.file);
        let _ = writeln!(
            out,
            "ticks: {} recorded, {} dropped; t = {:.2} .. {:.2} s, duration {:.2} s",
            self.ticks,
            self.ticks_dropped,
            self.first_t_s,
            self.last_t_s,
            self.last_t_s - self.first_t_s
        );
        let _ = writeln!(out, "distance: {:.2} m (odometry)", self.distance_m);
        let modes: Vec<String> = self
            .modes
            .iter()
            .map(|(t_s, mode)| format!("{mode} at {t_s:.2} s"))
            .collect();
        let _ = writeln!(out, "modes: {}", modes.join(", "));
        match &self.faults {
            None => out += "faults: unknown (no events in this record)\n",
            Some(faults) if faults.is_empty() => out += "faults: none\n",
            Some(faults) => {
                for (t_s, cause) in faults {
                    let _ = writeln!(out, "fault at {t_s:.2} s: {cause}");
                }
            }
        }
        for (t_s, what) in &self.notices {
            let _ = writeln!(out, "at {t_s:.2} s: {what}");
        }
        let meaning = self.cross_track_meaning;
        // Without a header's word the figures are given, with a note that says so.
        let unvouched = meaning == CrossTrackMeaning::Unknown && self.cross_track.is_some();
        if unvouched {
            out += "tool cross-track: no header beside this record says whether it means anything (a record from before mechweed said so, or its .run.json removed): the figures hold only if the simulated robot steered by its own camera\n";
        }
        match &self.cross_track {
            _ if !meaning.meaningful() && !unvouched => {
                let words = self.cross_track_meaning.instead().unwrap_or_default();
                let _ = writeln!(out, "tool cross-track: {words}");
            }
            None => out += "tool cross-track: not in this record (not a simulated run)\n",
            Some(c) if c.distance_m <= 0.0 => {
                let _ = writeln!(
                    out,
                    "tool cross-track: no samples from {:.1} m on (see --from-m)",
                    self.from_m
                );
            }
            Some(c) => {
                let _ = writeln!(out, "{}", cross_track_words(c, self.from_m));
            }
        }
        for note in &self.notes {
            let _ = writeln!(out, "note: {note}");
        }
        out
    }
}

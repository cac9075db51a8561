//! A record made on another computer from the robot's flows (`mechweed record --bus`):
//! the same CSV and MCAP files as the robot's own record, from the ticks and events
//! the bus carried. Each message is checked against the record's columns before it is
//! written: a tick with a column missing, a field too many or a value of the wrong
//! kind is refused with the reason, never written half.

use std::time::{Instant, SystemTime};

use serde_json::{Map, Value};

use super::RecordError;
use super::header::RunHeader;
use super::read::ADDED_LATER;
use super::row::{COLUMNS, TickSample, Value as Kind};
use super::thread::Sink;
use crate::config::RecordSettings;
use crate::state::cross_track::CrossTrackMeaning;

/// One cell of a received tick, in the order of the record's columns.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A number; NaN for a missing one (JSON null).
    Num(f64),
    Int(i64),
    /// One of the record's fixed words (mode, power state, side).
    Word(String),
}

#[derive(Debug, Clone, PartialEq)]
pub struct ReceivedTick {
    pub t_s: f64,
    pub tick: u64,
    pub cells: Vec<Cell>,
    /// The message as it came, for MCAP (the same JSON the robot's record holds).
    pub json: String,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ReceivedEvent {
    pub t_s: f64,
    pub tick: u64,
    /// mode, fault, notice or dropped.
    pub kind: String,
    pub text: String,
}

fn object(bytes: &[u8]) -> Result<(String, Map<String, Value>), String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "not UTF-8 text".to_string())?;
    match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(map)) => Ok((text.to_string(), map)),
        Ok(_) => Err("JSON but not an object".to_string()),
        Err(e) => Err(format!("not JSON ({e})")),
    }
}

/// A `ROBOT/tick` payload: every column of the record, each of its kind, nothing else.
pub fn parse_tick(bytes: &[u8]) -> Result<ReceivedTick, String> {
    let (json, map) = object(bytes)?;
    if let Some(extra) = map.keys().find(|k| !COLUMNS.iter().any(|c| c.name == *k)) {
        return Err(format!("\"{extra}\" is not a column of a record"));
    }
    let sample = TickSample::default();
    let mut cells = Vec::with_capacity(COLUMNS.len());
    for column in COLUMNS {
        let name = column.name;
        // A robot of an older version sends no column added since: empty there.
        let value = match map.get(name) {
            Some(value) => value,
            None if ADDED_LATER.contains(&name) => &Value::Null,
            None => return Err(format!("the column {name} is missing")),
        };
        let cell = match ((column.value)(&sample), value) {
            (Kind::Num(_), Value::Null) => Cell::Num(f64::NAN),
            (Kind::Num(_), Value::Number(n)) => Cell::Num(n.as_f64().unwrap_or(f64::NAN)),
            (Kind::Int(_), Value::Number(n)) if n.as_i64().is_some() => {
                Cell::Int(n.as_i64().unwrap_or_default())
            }
            // Empty where there is nothing to say (no end switch hit).
            (Kind::Text(_), Value::String(word))
                if word
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') =>
            {
                Cell::Word(word.clone())
            }
            (kind, other) => {
                let wanted = match kind {
                    Kind::Num(_) => "a number or null",
                    Kind::Int(_) => "a whole number",
                    Kind::Text(_) => "a word",
                };
                return Err(format!("{name} = {other} is not {wanted}"));
            }
        };
        cells.push(cell);
    }
    let cell = |name: &str| {
        COLUMNS
            .iter()
            .position(|c| c.name == name)
            .map(|i| &cells[i])
    };
    let (t_s, tick) = match (cell("t_s"), cell("tick")) {
        (Some(Cell::Num(t_s)), Some(Cell::Int(tick))) if t_s.is_finite() && *tick >= 0 => {
            (*t_s, *tick as u64)
        }
        (t_s, tick) => {
            return Err(format!(
                "t_s = {t_s:?} and tick = {tick:?} do not make a tick"
            ));
        }
    };
    Ok(ReceivedTick {
        t_s,
        tick,
        cells,
        json,
    })
}

/// A `ROBOT/event` payload: `{t_s, tick, kind, text}`.
pub fn parse_event(bytes: &[u8]) -> Result<ReceivedEvent, String> {
    let (_, map) = object(bytes)?;
    if let Some(extra) = map
        .keys()
        .find(|k| !super::EVENT_COLUMNS.contains(&k.as_str()))
    {
        return Err(format!("\"{extra}\" is not a field of an event"));
    }
    let t_s = map.get("t_s").and_then(Value::as_f64);
    let tick = map.get("tick").and_then(Value::as_u64);
    let kind = map.get("kind").and_then(Value::as_str);
    let text = map.get("text").and_then(Value::as_str);
    match (t_s, tick, kind, text) {
        (Some(t_s), Some(tick), Some(kind), Some(text))
            if ["mode", "fault", "notice", "dropped"].contains(&kind) =>
        {
            Ok(ReceivedEvent {
                t_s,
                tick,
                kind: kind.to_string(),
                text: text.to_string(),
            })
        }
        _ => Err(
            "an event needs t_s (s), tick, kind (mode, fault, notice or dropped) and text"
                .to_string(),
        ),
    }
}

/// The files of an off-board record, written on the receiving thread (nothing here
/// waits on the robot).
pub(crate) struct BusRecord {
    /// None once a sink has failed.
    sinks: Vec<Option<Box<dyn Sink>>>,
    files: Vec<String>,
    last_flush: Instant,
    pub problems: Vec<String>,
}

impl BusRecord {
    /// New files in `[record] folder` in its formats, named by the time now. The robot's
    /// run began at `start_unix_ns`; it publishes every `every_n_ticks`th tick.
    pub fn create(
        settings: &RecordSettings,
        start_unix_ns: u64,
        every_n_ticks: u64,
        cross_track: CrossTrackMeaning,
    ) -> Result<BusRecord, RecordError> {
        let stamp = super::utc_stamp(SystemTime::now());
        // A header without the robot's settings (the bus does not carry them), for what
        // the record's readers need of it: where it came from, and its cross-track.
        let header = RunHeader::off_board(cross_track);
        let sinks = super::new_sinks(
            settings,
            &stamp,
            start_unix_ns,
            every_n_ticks,
            Some(&header),
        )?;
        let sinks: Vec<Option<Box<dyn Sink>>> = sinks.into_iter().map(Some).collect();
        let files = sinks.iter().flatten().flat_map(|s| s.files()).collect();
        Ok(BusRecord {
            sinks,
            files,
            last_flush: Instant::now(),
            problems: Vec::new(),
        })
    }

    pub fn files(&self) -> &[String] {
        &self.files
    }

    pub fn tick(&mut self, tick: &ReceivedTick) {
        self.each(|sink| sink.received_tick(tick));
        if self.last_flush.elapsed().as_secs_f64() >= 0.5 {
            self.flush();
        }
    }

    /// A fault is on the disk at once.
    pub fn event(&mut self, event: &ReceivedEvent) {
        self.each(|sink| sink.received_event(event));
        if event.kind == "fault" {
            self.flush();
        }
    }

    fn flush(&mut self) {
        self.each(|sink| sink.flush());
        self.last_flush = Instant::now();
    }

    /// Complete the files (MCAP's summary and footer).
    pub fn finish(mut self) -> Vec<String> {
        self.each(|sink| sink.finish());
        self.problems
    }

    /// Do `work` on every sink still working; a sink that fails is given up, once said.
    fn each(&mut self, mut work: impl FnMut(&mut dyn Sink) -> std::io::Result<()>) {
        for slot in &mut self.sinks {
            let Some(sink) = slot else { continue };
            if let Err(e) = work(sink.as_mut()) {
                let problem = format!("cannot write {}: {e}", sink.files().join(", "));
                eprintln!("{problem}; recording into it stopped");
                self.problems.push(problem);
                *slot = None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::tick_json;

    fn a_tick() -> String {
        let mut sample = TickSample::default();
        sample.status.tick = 40;
        sample.status.t_s = 0.4;
        let mut json = String::new();
        tick_json(&sample, &mut json);
        json
    }

    #[test]
    fn a_tick_as_the_robot_publishes_it_is_taken_whole() {
        let json = a_tick();
        let tick = parse_tick(json.as_bytes()).unwrap();
        assert_eq!((tick.tick, tick.t_s), (40, 0.4));
        assert_eq!(tick.cells.len(), COLUMNS.len());
        assert_eq!(tick.json, json);
    }

    #[test]
    fn a_tick_that_is_not_a_record_row_is_refused_with_the_reason() {
        let json = a_tick();
        let mut map: Map<String, Value> = serde_json::from_str(&json).unwrap();
        let refused = |map: &Map<String, Value>| {
            parse_tick(serde_json::to_string(map).unwrap().as_bytes()).unwrap_err()
        };
        let mut extra = map.clone();
        extra.insert("speed".into(), Value::from(1.0));
        assert_eq!(refused(&extra), "\"speed\" is not a column of a record");
        let mut wrong = map.clone();
        wrong.insert("tick".into(), Value::from("forty"));
        assert_eq!(refused(&wrong), "tick = \"forty\" is not a whole number");
        map.remove("mode");
        assert_eq!(refused(&map), "the column mode is missing");
        assert!(
            parse_tick(b"{\"t_s\": 1")
                .unwrap_err()
                .starts_with("not JSON")
        );
        assert_eq!(parse_tick(b"[1]").unwrap_err(), "JSON but not an object");
        assert_eq!(parse_tick(b"\xff").unwrap_err(), "not UTF-8 text");
    }

    #[test]
    fn events_need_their_four_fields_and_a_known_kind() {
        let good = br#"{"t_s": 0.7, "tick": 70, "kind": "fault", "text": "camera link lost"}"#;
        let event = parse_event(good).unwrap();
        assert_eq!((event.tick, event.kind.as_str()), (70, "fault"));
        assert!(parse_event(br#"{"t_s": 0.7, "tick": 70, "kind": "party", "text": ""}"#).is_err());
        assert!(parse_event(br#"{"t_s": 0.7, "tick": -1, "kind": "mode", "text": ""}"#).is_err());
        let extra = br#"{"t_s": 0.7, "tick": 70, "kind": "mode", "text": "", "who": 1}"#;
        assert_eq!(
            parse_event(extra).unwrap_err(),
            "\"who\" is not a field of an event"
        );
    }
}

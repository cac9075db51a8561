//! The bus in a process of its own. Everything that speaks Zenoh for the controller (the
//! session, TLS, the access rules, the publishers, the queryables, the row estimates)
//! runs in `mechweed bus-gateway`, a child of `mechweed run` started from the same
//! binary. A defect in the network library then ends that child, never the supervisor:
//! the controller sees it end at once (its end of the channel closes), says so, drives
//! on as a robot without a bus, and starts it again (supervise.rs).
//!
//! The two talk over a Unix socket pair, the child's stdin, one JSON message a line:
//! `Down` from the controller (its settings, then status, ticks, events and answers),
//! `Up` from the bus process (queries with who asked, row estimates, its figures). The
//! controller decides every query itself (the dead-man, remote power-up, the rate
//! limits): the bus process only sorts them by importance and carries the answers.
//! Each side reads the other as untrusted input: a line too long or not a message ends
//! the link.

pub mod child;
pub mod supervise;

use std::io::{self, BufRead, Write};

use serde::{Deserialize, Serialize};

use super::queries::{Answer, Port};

/// A line longer than this is not a message (the session's own limit on a message is
/// lower): the link is ended rather than the memory filled.
const MAX_LINE_BYTES: u64 = 1 << 20;

/// From the controller to its bus process.
#[derive(Debug, Serialize, Deserialize)]
#[serde(tag = "m", rename_all = "snake_case")]
pub enum Down {
    /// First, once: the run's settings as the controller read them.
    Hello {
        label: String,
        text: String,
        overrides: Vec<String>,
    },
    /// ROBOT/status, ROBOT/tick and ROBOT/event, as JSON text.
    Status {
        json: String,
    },
    Tick {
        json: String,
    },
    Event {
        json: String,
    },
    /// The controller's answer to the query `id`.
    Answer {
        id: u64,
        answer: Answer,
    },
}

/// From the bus process to the controller.
#[derive(Debug, Serialize, Deserialize)]
#[serde(tag = "m", rename_all = "snake_case")]
pub enum Up {
    /// The session is open and every flow declared.
    Ready,
    /// The session could not open: why, in the words the robot's console says.
    Failed {
        why: String,
    },
    Query(QueryIn),
    /// A row estimate on ROBOT/camera/row, with its arrival, s since 1970.
    Row {
        payload: Vec<u8>,
        arrived_s: f64,
    },
    Figures(ProcessFigures),
}

/// A query as the controller decides it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct QueryIn {
    pub id: u64,
    pub port: Port,
    pub key: String,
    pub payload: Option<Vec<u8>>,
    /// The Zenoh session its attachment names ("" for none).
    pub asker: String,
    /// Its identity by the roster, on a secured bus.
    pub asker_name: Option<String>,
    /// That name is its link's certificate (bus/asked_as.rs).
    pub from_link: bool,
}

/// What the bus process has done since it started, about ten times a second.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ProcessFigures {
    pub peers: u32,
    /// The programs' tokens it sees (`ROBOT/alive/NAME`): a tool linked to the robot
    /// sees only the robot's own, as the robot's session does not pass others' on.
    pub present: Vec<String>,
    pub status_receivers: bool,
    pub status_published: u64,
    pub ticks_published: u64,
    pub events_published: u64,
    /// Queries its queues had no room for, and those the controller did not answer.
    pub queries_dropped: u64,
    /// Who is linked, by the roster, in words.
    pub identities: String,
    /// Two programs with the camera's identity are linked: no row is taken.
    pub rivals: bool,
    /// What each receiver said it gets, newest first heard (bus/hearing.rs).
    pub receivers: Vec<ReceiverSeen>,
}

/// A receiver's report, with its name (`ROBOT/heard/NAME`) and its age.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReceiverSeen {
    pub name: String,
    pub report: super::hearing::HeardReport,
    pub reported_s_ago: f64,
}

/// Write one message as a line.
pub fn send<T: Serialize>(out: &mut impl Write, message: &T) -> io::Result<()> {
    let mut line = serde_json::to_vec(message).map_err(io::Error::other)?;
    line.push(b'\n');
    out.write_all(&line)?;
    out.flush()
}

/// Read one message; Ok(None) at the end of the stream. A line that is too long or not
/// a message is an error that names what came.
pub fn receive<T: for<'de> Deserialize<'de>>(input: &mut impl BufRead) -> io::Result<Option<T>> {
    let mut line = Vec::new();
    io::Read::take(input.by_ref(), MAX_LINE_BYTES).read_until(b'\n', &mut line)?;
    if line.is_empty() {
        return Ok(None);
    }
    if line.last() != Some(&b'\n') {
        let why = if line.len() as u64 >= MAX_LINE_BYTES {
            format!("a line longer than {MAX_LINE_BYTES} bytes")
        } else {
            "a line cut short by the end of the stream".to_string()
        };
        return Err(io::Error::new(io::ErrorKind::InvalidData, why));
    }
    serde_json::from_slice(&line).map(Some).map_err(|e| {
        let start = String::from_utf8_lossy(&line[..line.len().min(80)]).into_owned();
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not a message ({e}): {start:?}"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_cross_the_link_as_they_were_sent() {
        let query = QueryIn {
            id: 7,
            port: Port::Halt,
            key: "mechweed/request".into(),
            payload: Some(br#"{"request":"halt"}"#.to_vec()),
            asker: "ab12".into(),
            asker_name: Some("viewer-laptop".into()),
            from_link: true,
        };
        let mut wire = Vec::new();
        send(&mut wire, &Up::Query(query)).unwrap();
        send(&mut wire, &Up::Ready).unwrap();
        let mut input = io::Cursor::new(wire);
        let Some(Up::Query(back)) = receive::<Up>(&mut input).unwrap() else {
            panic!("not the query");
        };
        assert_eq!((back.id, back.port), (7, Port::Halt));
        assert_eq!(back.asker_name.as_deref(), Some("viewer-laptop"));
        assert!(back.from_link);
        assert!(matches!(
            receive::<Up>(&mut input).unwrap(),
            Some(Up::Ready)
        ));
        assert!(receive::<Up>(&mut input).unwrap().is_none());
    }

    #[test]
    fn what_is_not_a_message_is_refused_with_what_came() {
        let mut input = io::Cursor::new(b"{\"m\":\"launch\"}\n".to_vec());
        let why = receive::<Up>(&mut input).unwrap_err().to_string();
        assert!(
            why.contains("not a message") && why.contains("launch"),
            "{why}"
        );
        let mut cut = io::Cursor::new(b"{\"m\":\"ready\"".to_vec());
        let why = receive::<Up>(&mut cut).unwrap_err().to_string();
        assert!(why.contains("cut short"), "{why}");
        let mut long = io::Cursor::new(vec![b'x'; MAX_LINE_BYTES as usize + 10]);
        let why = receive::<Up>(&mut long).unwrap_err().to_string();
        assert!(why.contains("longer than"), "{why}");
    }
}

//! `mechweed bus-gateway`: the bus process. It reads the run's settings from its
//! controller, opens the robot's session, and then only carries: what the controller
//! sends goes out on the publishers, what other programs ask goes to the controller one
//! query at a time (HALT first, inbox.rs) and its answer back to the asker, and row
//! estimates go up as they come. It ends when the controller's end of the link closes,
//! however the controller ended, and at once if the controller dies (its parent-death
//! signal).

use std::io::BufReader;
use std::os::fd::AsFd;
use std::os::unix::net::UnixStream;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Select, Sender, TryRecvError, bounded};
use serde_json::json;
use zenoh::bytes::Encoding;
use zenoh::qos::CongestionControl;
use zenoh::query::Query;
use zenoh::{Session, Wait};

use super::{Down, ProcessFigures, QueryIn, ReceiverSeen, Up, receive, send};
use crate::bus::asked_as::asker;
use crate::bus::hearing::HeardReport;
use crate::bus::identities::{Identities, LinkChange, watch_links};
use crate::bus::inbox::{Inbox, requester};
use crate::bus::keys::{self, Roster};
use crate::bus::payload::wall_s;
use crate::bus::peers::Peers;
use crate::bus::queries::Answer;
use crate::bus::session::{Role, open};
use crate::config::{CameraPort, Settings};

/// Messages waiting to go up; a full queue drops a row estimate (as a busy camera link
/// would) rather than wait in Zenoh's callback.
const UP_QUEUE: usize = 64;
/// How often the figures go up.
const FIGURES_PERIOD: Duration = Duration::from_millis(100);
/// A query the controller has not answered in this long is dropped (its asker times out
/// as for a full queue), so that one lost answer does not stop every later query.
const ANSWER_WITHIN: Duration = Duration::from_secs(5);
/// Receivers kept at most (their names are theirs to choose), and how long a report
/// counts.
const MAX_RECEIVERS: usize = 32;
const REPORT_COUNTS: Duration = Duration::from_secs(10);

/// The program: exit 0 when the controller closed the link, 1 when it could not start.
pub fn program() -> ExitCode {
    // The controller gone, this process goes too, even before it reads the end of the
    // link.
    // SAFETY: prctl with PR_SET_PDEATHSIG takes a signal number and changes nothing else.
    unsafe { libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) };
    match serve() {
        Ok(()) => ExitCode::SUCCESS,
        Err(why) => {
            tracing::error!("bus process: {why}");
            ExitCode::FAILURE
        }
    }
}

fn serve() -> Result<(), String> {
    let link = std::io::stdin()
        .as_fd()
        .try_clone_to_owned()
        .map(UnixStream::from)
        .map_err(|e| format!("no link to the controller on stdin: {e}"))?;
    let mut input = BufReader::new(link.try_clone().map_err(|e| e.to_string())?);
    let mut output = link;
    let settings = match receive::<Down>(&mut input) {
        Ok(Some(Down::Hello {
            label,
            text,
            overrides,
        })) => Settings::parse(&label, &text, &overrides).map_err(|errors| {
            let lines: Vec<String> = errors.iter().map(ToString::to_string).collect();
            lines.join("; ")
        })?,
        other => return Err(format!("the controller did not say hello: {other:?}")),
    };
    let session = match open(Role::Robot(&settings.bus), settings.bus.tls.as_ref()) {
        Ok(session) => session,
        Err(e) => {
            // Said once, by the controller, in these words.
            if send(&mut output, &Up::Failed { why: e.to_string() }).is_ok() {
                std::process::exit(1);
            }
            return Err(e.to_string());
        }
    };
    let (to_controller, queued) = bounded(UP_QUEUE);
    let flows = Flows::declare(&session, &settings, to_controller.clone())
        .map_err(|e| format!("the bus could not declare its flows: {e}"))?;
    send(&mut output, &Up::Ready).map_err(|e| e.to_string())?;
    let ended = Arc::new(AtomicBool::new(false));
    std::thread::Builder::new()
        .name("to-controller".into())
        .spawn({
            let ended = ended.clone();
            move || {
                for message in queued {
                    if send(&mut output, &message).is_err() {
                        break;
                    }
                }
                ended.store(true, Ordering::Relaxed);
            }
        })
        .map_err(|e| e.to_string())?;
    let (down_tx, down) = bounded(256);
    std::thread::Builder::new()
        .name("from-controller".into())
        .spawn(move || read_controller(input, &down_tx))
        .map_err(|e| e.to_string())?;
    flows.carry(&down, &to_controller, &ended);
    Ok(())
}

/// Hand on each message from the controller until its end of the link closes (or sends
/// what is not a message: said, and the link ends).
fn read_controller(mut input: BufReader<UnixStream>, down: &Sender<Down>) {
    loop {
        match receive::<Down>(&mut input) {
            Ok(Some(message)) => {
                if down.send(message).is_err() {
                    return;
                }
            }
            Ok(None) => return,
            Err(e) => {
                tracing::error!("bus process: from the controller: {e}");
                return;
            }
        }
    }
}

/// The robot's flows on its session.
struct Flows {
    /// Held: the session closes when its last handle goes.
    _session: Session,
    status: zenoh::pubsub::Publisher<'static>,
    tick: zenoh::pubsub::Publisher<'static>,
    event: zenoh::pubsub::Publisher<'static>,
    inbox: Inbox,
    own_token: String,
    peers: Peers,
    identities: Option<Identities>,
    links: Receiver<LinkChange>,
    /// Receivers' reports as they come, and the newest of each.
    heard: Receiver<(String, Vec<u8>)>,
    receivers: std::collections::BTreeMap<String, (HeardReport, Instant)>,
    _keep: (
        zenoh::liveliness::LivelinessToken,
        zenoh::session::LinkEventsListener<()>,
        Option<zenoh::pubsub::Subscriber<()>>,
        zenoh::pubsub::Subscriber<()>,
    ),
    figures: ProcessFigures,
}

impl Flows {
    fn declare(session: &Session, settings: &Settings, up: Sender<Up>) -> zenoh::Result<Flows> {
        let bus = &settings.bus;
        let publisher = |what: &str| {
            session
                .declare_publisher(bus.key(what))
                .congestion_control(CongestionControl::Drop)
                .encoding(Encoding::APPLICATION_JSON)
                .wait()
        };
        let own_token = bus.key("alive/controller");
        let token = session.liveliness().declare_token(&own_token).wait()?;
        let rows = if settings.camera_port == CameraPort::Bus {
            let subscriber = session
                .declare_subscriber(bus.key("camera/row"))
                .callback(move |sample| {
                    let payload = sample.payload().to_bytes().into_owned();
                    let _ = up.try_send(Up::Row {
                        payload,
                        arrived_s: wall_s(),
                    });
                })
                .wait()?;
            Some(subscriber)
        } else {
            None
        };
        // The roster was read when the session opened: it is there.
        let roster = (bus.tls.as_ref()).and_then(|tls| Roster::read(&tls.roster()).ok());
        let operators = (roster.iter())
            .flat_map(|r| r.names(keys::Role::Operator).map(str::to_string))
            .collect();
        let (links, listener) = watch_links(session)?;
        let (heard_tx, heard) = bounded(64);
        let reports = session
            .declare_subscriber(bus.key("heard/*"))
            .callback(move |sample| {
                let name = sample.key_expr().as_str().rsplit('/').next().unwrap_or("");
                let bytes = sample.payload().to_bytes().into_owned();
                let _ = heard_tx.try_send((name.to_string(), bytes));
            })
            .wait()?;
        Ok(Flows {
            _session: session.clone(),
            status: publisher("status")?,
            tick: publisher("tick")?,
            event: publisher("event")?,
            inbox: Inbox::declare(session, bus, operators)?,
            peers: Peers::watch(session, &bus.key("alive/**"))?,
            own_token,
            identities: roster.map(Identities::new),
            links,
            heard,
            receivers: std::collections::BTreeMap::new(),
            _keep: (token, listener, rows, reports),
            figures: ProcessFigures::default(),
        })
    }

    /// Carry until the controller's end closes.
    fn carry(mut self, down: &Receiver<Down>, up: &Sender<Up>, ended: &AtomicBool) {
        let mut asked: Option<(u64, Query, Instant)> = None;
        let mut next_id = 0;
        let mut next_figures = Instant::now();
        while !ended.load(Ordering::Relaxed) {
            // One query at a time, the most important first: a HALT waits at most for
            // the one answer being given.
            if asked.is_none()
                && let Some((port, query)) = self.inbox.try_next()
            {
                // The asker's link may have come a moment ago: its name first.
                self.follow_links();
                next_id += 1;
                let (key, named) = self.inbox.asked_as(&query);
                let who = asker(named, requester(&query), self.identities.as_ref());
                let message = QueryIn {
                    id: next_id,
                    port,
                    key,
                    payload: query.payload().map(|p| p.to_bytes().into_owned()),
                    asker: who.asker,
                    asker_name: who.name,
                    from_link: who.from_link,
                };
                if up.send(Up::Query(message)).is_err() {
                    return;
                }
                asked = Some((next_id, query, Instant::now()));
                continue;
            }
            let mut select = Select::new();
            select.recv(down);
            // A link that comes or goes is told at once (who is linked, rival cameras).
            select.recv(&self.links);
            if asked.is_none() {
                self.inbox.queues().iter().for_each(|q| {
                    select.recv(q);
                });
            }
            let wait = next_figures.saturating_duration_since(Instant::now());
            match select.ready_timeout(wait) {
                Ok(0) => match down.try_recv() {
                    Ok(message) => self.take(message, &mut asked),
                    Err(TryRecvError::Disconnected) => return,
                    Err(TryRecvError::Empty) => {}
                },
                Ok(1) if self.follow_links() => {
                    let _ = up.try_send(Up::Figures(self.figures.clone()));
                }
                _ => {}
            }
            if asked
                .as_ref()
                .is_some_and(|(_, _, since)| since.elapsed() > ANSWER_WITHIN)
            {
                asked = None;
                self.figures.queries_dropped += 1;
            }
            if Instant::now() >= next_figures {
                next_figures = Instant::now() + FIGURES_PERIOD;
                self.look();
                let _ = up.try_send(Up::Figures(self.figures.clone()));
            }
        }
    }

    /// One message from the controller.
    fn take(&mut self, message: Down, asked: &mut Option<(u64, Query, Instant)>) {
        let f = &mut self.figures;
        match message {
            Down::Status { json } => f.status_published += u64::from(put(&self.status, json)),
            Down::Tick { json } => f.ticks_published += u64::from(put(&self.tick, json)),
            Down::Event { json } => f.events_published += u64::from(put(&self.event, json)),
            Down::Answer { id, answer } => match asked.take() {
                Some((asked_id, query, _)) if asked_id == id => reply(&query, answer),
                // An answer to a query given up on: the new one waits on.
                other => *asked = other,
            },
            Down::Hello { .. } => tracing::warn!("bus process: a second hello, ignored"),
        }
    }

    /// Who is there, what the receivers get, and who is linked.
    fn look(&mut self) {
        self.take_reports();
        let f = &mut self.figures;
        f.peers = self.peers.others(&self.own_token);
        f.present = self.peers.present();
        f.status_receivers = (self.status.matching_status().wait()).is_ok_and(|m| m.matching());
        f.queries_dropped = f.queries_dropped.max(self.inbox.dropped());
        self.follow_links();
    }

    /// Take the links that came and went: who is linked, and rival cameras said. Whether
    /// anything changed.
    fn follow_links(&mut self) -> bool {
        let f = &mut self.figures;
        let Some(ids) = &mut self.identities else {
            // Not secured: nobody's name is known; the changes are only taken.
            return self.links.try_iter().count() > 0;
        };
        let look = ids.take(self.links.try_iter());
        for name in &look.newly_refused {
            tracing::warn!(
                "bus: {name} linked with a certificate of this authority, but the roster gives it no rights (revoked, or never in it): it may do nothing"
            );
        }
        let rivals = !look.rival_cameras.is_empty();
        if rivals && !f.rivals {
            tracing::warn!(
                "bus: two programs send camera rows: {}; the rows of neither are taken",
                look.rival_cameras.join(" and ")
            );
        }
        let summary = ids.summary();
        let changed = f.rivals != rivals || f.identities != summary;
        (f.rivals, f.identities) = (rivals, summary);
        changed
    }
}

impl Flows {
    /// The receivers' newest reports; one that cannot be read is left out (said at debug
    /// level: its sender is not this program's to judge aloud).
    fn take_reports(&mut self) {
        while let Ok((name, bytes)) = self.heard.try_recv() {
            let printable = name.len() <= 64 && !name.chars().any(char::is_control);
            let full = self.receivers.len() >= MAX_RECEIVERS;
            if !printable || (full && !self.receivers.contains_key(&name)) {
                continue;
            }
            match HeardReport::read(&bytes) {
                Ok(report) => {
                    self.receivers.insert(name, (report, Instant::now()));
                }
                Err(why) => tracing::debug!("bus: a receiver's report from {name}: {why}"),
            }
        }
        self.receivers
            .retain(|_, (_, at)| at.elapsed() < REPORT_COUNTS);
        self.figures.receivers = (self.receivers.iter())
            .map(|(name, (report, at))| ReceiverSeen {
                name: name.clone(),
                report: report.clone(),
                reported_s_ago: at.elapsed().as_secs_f64(),
            })
            .collect();
    }
}

fn put(publisher: &zenoh::pubsub::Publisher<'_>, json: String) -> bool {
    publisher.put(json).wait().is_ok()
}

/// The controller's answer, to its asker: JSON, an error answer as `{"error": WHY}`.
fn reply(query: &Query, answer: Answer) {
    let sent = match answer {
        Ok(reply) => query
            .reply(query.key_expr().clone(), reply.to_string())
            .encoding(Encoding::APPLICATION_JSON)
            .wait(),
        Err(why) => query
            .reply_err(json!({ "error": why }).to_string())
            .encoding(Encoding::APPLICATION_JSON)
            .wait(),
    };
    if let Err(e) = sent {
        tracing::debug!("bus: the answer could not be sent: {e}");
    }
}

//! The robot's flows as a program on another computer hears them (watch, the off-board
//! recorder, the ROS 2 bridge), with a session that mends itself. After a link flap a
//! long-lived Zenoh session has been seen to stop receiving while its link was up, or to
//! hand one flow's messages to another's subscriber, while a new session worked at
//! once. So: a session that hears no status for `QUIET` while it is linked to someone,
//! or that gets a message under a key it did not ask for, or whose program could not
//! read a message, is closed and opened again, and the program says so. Messages under
//! the wrong key are counted and never handed on.
//!
//! The robot's status comes ten times a second whatever a program listens to, so it is
//! the heartbeat: every hearing subscribes to it, and hands it on only if asked.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Sender, bounded};
use parking_lot::Mutex;
use zenoh::{Session, Wait};

use super::session::{Role, open, plain_words};
use crate::config::TlsFiles;

/// No status for this long while linked: the session is opened again.
const QUIET: Duration = Duration::from_secs(3);
/// How often the session is looked at.
const LOOK_EVERY: Duration = Duration::from_millis(250);
/// A status this long after the one before it is said as coming again, ms.
const COMES_AGAIN_MS: u64 = 1500;
/// Messages under a wrong key said at most this many times (all are counted).
const SAY_WRONG: u64 = 3;

/// How often a hearing tells the robot what it gets.
const REPORT_EVERY: Duration = Duration::from_secs(1);

/// What a receiver gets, as it tells the robot on `ROBOT/heard/NAME` once a second;
/// the robot names its receivers in its status with this, and `cluster status` shows
/// them.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeardReport {
    pub program: String,
    /// How long ago its newest status came, s (None: none yet).
    pub status_age_s: Option<f64>,
    pub received: u64,
    pub dropped_here: u64,
    pub wrong_key: u64,
    pub reopened: u64,
}

impl HeardReport {
    /// A report as another program sent it, checked: a name that prints as itself, a
    /// finite age.
    pub fn read(bytes: &[u8]) -> Result<HeardReport, String> {
        let report: HeardReport =
            serde_json::from_slice(bytes).map_err(|e| format!("not a report ({e})"))?;
        if report.program.len() > 32 || report.program.chars().any(char::is_control) {
            return Err("a program's name longer than 32 or with control characters".into());
        }
        if report
            .status_age_s
            .is_some_and(|s| !s.is_finite() || s < 0.0)
        {
            return Err("status_age_s is not an age".into());
        }
        Ok(report)
    }
}

/// What a hearing counts, for the program's own lines and its closing summary.
#[derive(Debug, Default)]
pub struct HearCounts {
    /// Messages taken (the status heard as the heartbeat too).
    pub received: AtomicU64,
    /// Messages the program's queue had no room for (this computer fell behind).
    pub dropped_here: AtomicU64,
    /// Messages that came under a key their subscriber was not for.
    pub wrong_key: AtomicU64,
    /// Times the session was opened again.
    pub reopened: AtomicU64,
    /// The program could not read a message: open the session again.
    unreadable: AtomicBool,
    /// A message came under the wrong key since the last look: the same.
    wrong_key_seen: AtomicBool,
    /// The newest status, ms after the hearing began.
    status_ms: AtomicU64,
}

/// Where and what to hear.
#[derive(Clone)]
pub struct Ear<F> {
    pub endpoint: String,
    pub robot: String,
    pub tls: Option<TlsFiles>,
    /// This program's liveliness token, `alive/NAME` under the robot's keys.
    pub token: String,
    /// Each flow with its key under the robot's (`tick`, `status`, ...).
    pub flows: Vec<(F, &'static str)>,
    /// The program's name, at the start of what it says.
    pub program: &'static str,
    pub queue: usize,
}

/// The flows as they arrive: (flow, payload, arrival).
pub type Arrived<F> = (F, Vec<u8>, Instant);

pub struct Hearing<F> {
    pub rx: Receiver<Arrived<F>>,
    pub counts: Arc<HearCounts>,
    session: Arc<Mutex<Session>>,
    quit: Arc<AtomicBool>,
}

/// A session with its subscribers and token, held while it is the one in use.
struct Opened {
    session: Session,
    _subscribers: Vec<zenoh::pubsub::Subscriber<()>>,
    _token: zenoh::liveliness::LivelinessToken,
}

impl<F: Copy + Send + Sync + 'static> Hearing<F> {
    /// Open the session (it waits for the robot) and hear `ear`'s flows.
    pub fn start(ear: Ear<F>) -> Result<Hearing<F>, String> {
        super::session::check_robot(ear.tls.as_ref(), &ear.robot)?;
        let (tx, rx) = bounded(ear.queue);
        let counts = Arc::new(HearCounts::default());
        let began = Instant::now();
        let opened = hear(&ear, &tx, &counts, began)?;
        let session = Arc::new(Mutex::new(opened.session.clone()));
        let quit = Arc::new(AtomicBool::new(false));
        let mender = Mender {
            ear,
            tx,
            counts: counts.clone(),
            began,
            session: session.clone(),
            quit: quit.clone(),
        };
        std::thread::Builder::new()
            .name("bus-hearing".into())
            .spawn(move || mender.run(opened))
            .map_err(|e| format!("cannot start a thread: {e}"))?;
        Ok(Hearing {
            rx,
            counts,
            session,
            quit,
        })
    }
}

impl<F> Hearing<F> {
    /// The session in use now, for queries (it changes when it is opened again).
    pub fn session(&self) -> Session {
        self.session.lock().clone()
    }

    /// Where the session in use is kept, for a thread that asks on it from time to time.
    pub fn sessions(&self) -> Arc<Mutex<Session>> {
        self.session.clone()
    }

    /// The program could not read a message: the session is opened again.
    pub fn unreadable(&self) {
        self.counts.unreadable.store(true, Ordering::Relaxed);
    }

    /// "; N under the wrong key; session opened again N times", for the summaries
    /// ("" when neither happened).
    pub fn line(&self) -> String {
        let wrong = self.counts.wrong_key.load(Ordering::Relaxed);
        let reopened = self.counts.reopened.load(Ordering::Relaxed);
        let mut line = String::new();
        if wrong > 0 {
            line += &format!("; {wrong} messages under the wrong key, not taken");
        }
        if reopened > 0 {
            line += &format!("; the session was opened again {reopened} times");
        }
        line
    }
}

impl<F> Drop for Hearing<F> {
    fn drop(&mut self) {
        self.quit.store(true, Ordering::Relaxed);
    }
}

/// The thread that watches the session and opens it again.
struct Mender<F> {
    ear: Ear<F>,
    tx: Sender<Arrived<F>>,
    counts: Arc<HearCounts>,
    began: Instant,
    session: Arc<Mutex<Session>>,
    quit: Arc<AtomicBool>,
}

impl<F: Copy + Send + Sync + 'static> Mender<F> {
    fn run(self, mut opened: Opened) {
        let mut since = Instant::now();
        let mut status_ms = 0;
        let mut next_report = Instant::now();
        while !self.quit.load(Ordering::Relaxed) {
            std::thread::sleep(LOOK_EVERY);
            if Instant::now() >= next_report {
                next_report += REPORT_EVERY;
                self.report(&opened.session);
            }
            // A status after a silence: said, so that a person (and a test) sees the
            // flows come back after a cut.
            let newest_ms = self.counts.status_ms.load(Ordering::Relaxed);
            if status_ms > 0 && newest_ms >= status_ms + COMES_AGAIN_MS {
                eprintln!(
                    "{}: the robot's status comes again after {:.1} s",
                    self.ear.program,
                    (newest_ms - status_ms) as f64 / 1000.0
                );
            }
            status_ms = newest_ms;
            let why = self.why_mend(&opened.session, since);
            let Some(why) = why else {
                continue;
            };
            eprintln!("{}: {why}: its session is opened again", self.ear.program);
            let _ = opened.session.close().wait();
            match hear(&self.ear, &self.tx, &self.counts, self.began) {
                Ok(new) => {
                    *self.session.lock() = new.session.clone();
                    opened = new;
                    self.counts.reopened.fetch_add(1, Ordering::Relaxed);
                }
                Err(e) => eprintln!("{}: the session could not open: {e}", self.ear.program),
            }
            since = Instant::now();
        }
    }

    /// Tell the robot what this program gets (dropped if it cannot be sent).
    fn report(&self, session: &Session) {
        let c = &self.counts;
        let status_ms = c.status_ms.load(Ordering::Relaxed);
        let report = HeardReport {
            program: self.ear.program.to_string(),
            status_age_s: (status_ms > 0).then(|| {
                let at = self.began + Duration::from_millis(status_ms);
                at.elapsed().as_secs_f64()
            }),
            received: c.received.load(Ordering::Relaxed),
            dropped_here: c.dropped_here.load(Ordering::Relaxed),
            wrong_key: c.wrong_key.load(Ordering::Relaxed),
            reopened: c.reopened.load(Ordering::Relaxed),
        };
        let name = self.ear.token.trim_start_matches("alive/");
        let key = format!("{}/heard/{name}", self.ear.robot);
        if let Ok(json) = serde_json::to_string(&report) {
            let _ = session.put(key, json).wait();
        }
    }

    /// Why the session must be opened again, if it must.
    fn why_mend(&self, session: &Session, since: Instant) -> Option<String> {
        if self.counts.unreadable.swap(false, Ordering::Relaxed) {
            return Some("a message that cannot be read".into());
        }
        if self.counts.wrong_key_seen.swap(false, Ordering::Relaxed) {
            return Some("a message under the wrong key".into());
        }
        let status_at =
            self.began + Duration::from_millis(self.counts.status_ms.load(Ordering::Relaxed));
        let quiet = status_at.max(since).elapsed();
        let linked = session.info().peers_zid().wait().next().is_some();
        (linked && quiet >= QUIET).then(|| {
            format!(
                "no status from {} for {:.0} s although linked to it",
                self.ear.robot,
                quiet.as_secs_f64()
            )
        })
    }
}

/// Open a session and subscribe: each flow's messages to `tx` (those under another key
/// counted, not handed on), the status noted as the heartbeat.
fn hear<F: Copy + Send + Sync + 'static>(
    ear: &Ear<F>,
    tx: &Sender<Arrived<F>>,
    counts: &Arc<HearCounts>,
    began: Instant,
) -> Result<Opened, String> {
    let role = Role::Tool {
        connect: vec![ear.endpoint.clone()],
        wait: true,
    };
    let session = open(role, ear.tls.as_ref()).map_err(|e| plain_words(&e))?;
    let key = |what: &str| format!("{}/{what}", ear.robot);
    let mut wanted: Vec<(Option<F>, String)> = ear
        .flows
        .iter()
        .map(|&(flow, what)| (Some(flow), key(what)))
        .collect();
    if !ear.flows.iter().any(|(_, what)| *what == "status") {
        wanted.push((None, key("status")));
    }
    let mut subscribers = Vec::new();
    for (flow, key) in wanted {
        let (tx, counts, program) = (tx.clone(), counts.clone(), ear.program);
        let is_status = key.ends_with("/status");
        let subscriber = session
            .declare_subscriber(key.clone())
            .callback(move |sample| {
                let came = sample.key_expr().as_str();
                if came != key {
                    counts.wrong_key_seen.store(true, Ordering::Relaxed);
                    let n = counts.wrong_key.fetch_add(1, Ordering::Relaxed) + 1;
                    if n <= SAY_WRONG {
                        eprintln!("{program}: a message under {came} came to the subscriber of {key}: not taken");
                    }
                    return;
                }
                counts.received.fetch_add(1, Ordering::Relaxed);
                if is_status {
                    let ms = began.elapsed().as_millis() as u64;
                    counts.status_ms.store(ms, Ordering::Relaxed);
                }
                let Some(flow) = flow else {
                    return;
                };
                let bytes = sample.payload().to_bytes().into_owned();
                if tx.try_send((flow, bytes, Instant::now())).is_err() {
                    counts.dropped_here.fetch_add(1, Ordering::Relaxed);
                }
            })
            .wait()
            .map_err(|e| plain_words(&e))?;
        subscribers.push(subscriber);
    }
    let token = session
        .liveliness()
        .declare_token(key(&ear.token))
        .wait()
        .map_err(|e| plain_words(&e))?;
    Ok(Opened {
        session,
        _subscribers: subscribers,
        _token: token,
    })
}

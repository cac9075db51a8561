//! The camera-link thread: opens the transport, feeds every byte that arrives to the
//! decoder, publishes the link's state, wakes the steer thread on each usable row
//! estimate, and sends the command bytes the link asks for. A transport that fails is
//! opened again with back-off; whether the robot faults is the supervisor's decision
//! (only when it relies on the camera, in autonomous mode). The thread beats at least
//! every 10 ms, also while the port is being opened (opener.rs).

use std::io::{self, ErrorKind, Read, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Sender};

use super::opener::{Heard, Opening};
use super::transport::{ByteStream, Resolver};
use super::{LinkCore, LinkProblem, LinkStatus, OpenStep};
use crate::config::CameraPort;
use crate::rt;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::rt::inject::Injection;
use crate::state::status::Status;
use crate::state::{Reader, Writer};

/// A read waits at most this long for a byte, so commands go out without delay.
pub const READ_TIMEOUT: Duration = Duration::from_millis(10);
/// Opening again after a failure waits this long at first, doubling up to the maximum.
const BACKOFF_MIN: Duration = Duration::from_millis(100);
const BACKOFF_MAX: Duration = Duration::from_secs(2);

/// What the camera-link thread meets the other threads through.
pub struct LinkWires {
    /// Wakes the steer thread on each usable row.
    pub new_estimate: Sender<()>,
    /// Link tests asked for (the GUI's "Test link" button).
    pub ping_requests: Receiver<()>,
    pub status: Writer<LinkStatus>,
    /// The supervisor's status: the link streams rows while the robot drives, so that
    /// switching from joystick to autonomous finds a fresh estimate at hand.
    pub robot: Reader<Status>,
    pub panics: Arc<PanicFlag>,
    pub stop: Arc<AtomicBool>,
}

pub struct LinkThread {
    core: LinkCore,
    port: CameraPort,
    /// How a host name in the port is looked up (`transport::system_resolver`).
    resolve: Resolver,
    clock: Instant,
    new_estimate: Sender<()>,
    ping_requests: Receiver<()>,
    status: Writer<LinkStatus>,
    robot: Reader<Status>,
    panics: Arc<PanicFlag>,
    /// SCHED_FIFO priority (0 = normal).
    priority: u8,
    /// For tests: fail on purpose.
    inject: Option<Injection>,
    /// A stream made before the thread started (the bus's row estimates), used first.
    ready: Option<Box<dyn ByteStream>>,
    /// Set while two programs send rows on the bus (bus/identities.rs): said in the
    /// status, for the supervisor's fault.
    rivals: Option<Arc<AtomicBool>>,
    stop: Arc<AtomicBool>,
}

impl LinkThread {
    /// The link to the camera computer at `port`, at normal priority, looking names up
    /// with the system's resolver; `clock` is the run's.
    pub fn new(core: LinkCore, port: CameraPort, clock: Instant, wires: LinkWires) -> LinkThread {
        LinkThread {
            core,
            port,
            resolve: super::transport::system_resolver,
            clock,
            new_estimate: wires.new_estimate,
            ping_requests: wires.ping_requests,
            status: wires.status,
            robot: wires.robot,
            panics: wires.panics,
            priority: 0,
            inject: None,
            ready: None,
            rivals: None,
            stop: wires.stop,
        }
    }

    /// Run at this SCHED_FIFO priority (0 = normal).
    pub fn with_priority(self, priority: u8) -> LinkThread {
        LinkThread { priority, ..self }
    }

    /// Look host names up with `resolve` (tests put in one that hangs).
    pub fn with_resolver(self, resolve: Resolver) -> LinkThread {
        LinkThread { resolve, ..self }
    }

    /// Fail on purpose as `inject` says, if it names this thread.
    pub fn with_injection(self, inject: Option<Injection>) -> LinkThread {
        LinkThread { inject, ..self }
    }

    /// Read from `stream`, already open (row estimates from the bus), instead of opening
    /// the port; `rivals` is set while two programs send them.
    pub fn with_stream(self, stream: Box<dyn ByteStream>, rivals: Arc<AtomicBool>) -> LinkThread {
        LinkThread {
            ready: Some(stream),
            rivals: Some(rivals),
            ..self
        }
    }

    /// Publish the link's state, with whether rows have rival sources now.
    fn publish_status(&mut self) {
        if let Some(rivals) = &self.rivals {
            self.core.rival_sources(rivals.load(Ordering::Relaxed));
        }
        self.status.publish(self.core.status());
    }

    fn now_s(&self) -> f64 {
        self.clock.elapsed().as_secs_f64()
    }

    pub fn run(mut self) {
        health::watch_this_thread(&self.panics, ThreadName::CameraLink);
        if let Some(warning) = rt::set_this_thread(self.priority, -1) {
            tracing::warn!("camera link thread: {warning}");
        }
        self.core.beat(self.now_s());
        self.publish_status();
        let mut backoff = BACKOFF_MIN;
        let mut last_problem = None;
        while !self.stop.load(Ordering::Relaxed) {
            let opened = match self.ready.take() {
                Some(stream) => Ok(stream),
                None => self.open_beating(),
            };
            if self.stop.load(Ordering::Relaxed) {
                break;
            }
            match opened {
                Ok(stream) => {
                    tracing::info!("camera link open on {}", self.port.describe());
                    self.core.connected();
                    backoff = BACKOFF_MIN;
                    last_problem = None;
                    if let Some(problem) = self.serve(stream) {
                        if self.stop.load(Ordering::Relaxed) {
                            break; // the cable went down because the program is stopping
                        }
                        tracing::warn!(
                            "camera link on {}: {problem}; opening it again",
                            self.port.describe()
                        );
                        self.core.disconnected(problem);
                        last_problem = Some(problem);
                    }
                }
                Err(e) => {
                    let problem = LinkProblem::OpenFailed(e.kind());
                    if last_problem != Some(problem) {
                        tracing::warn!(
                            "camera link: cannot open {}: {e}; trying again every {} s at most",
                            self.port.describe(),
                            BACKOFF_MAX.as_secs()
                        );
                    }
                    last_problem = Some(problem);
                    self.core.disconnected(problem);
                }
            }
            self.publish_status();
            self.sleep(backoff);
            backoff = (backoff * 2).min(BACKOFF_MAX);
        }
    }

    /// Open the port on a helper thread, beating and publishing what it waits for
    /// meanwhile; gives up at once when the program stops.
    fn open_beating(&mut self) -> io::Result<Box<dyn ByteStream>> {
        let opening = Opening::start(&self.port, self.resolve, READ_TIMEOUT)?;
        while !self.stop.load(Ordering::Relaxed) {
            match opening.poll(READ_TIMEOUT) {
                Heard::Done(result) => return result,
                Heard::Step(step) => {
                    if step == OpenStep::LookingUp {
                        tracing::debug!("camera link: looking up {}", self.port.describe());
                    }
                    self.core.opening(step);
                }
                Heard::Nothing => {}
            }
            self.core.beat(self.now_s());
            self.publish_status();
        }
        Err(io::Error::new(
            ErrorKind::Interrupted,
            "the program is stopping",
        ))
    }

    /// Sleep, beating, and wake at once when the program stops.
    fn sleep(&mut self, total: Duration) {
        let end = Instant::now() + total;
        while !self.stop.load(Ordering::Relaxed) && Instant::now() < end {
            std::thread::sleep(Duration::from_millis(10));
            self.core.beat(self.now_s());
            self.publish_status();
        }
    }

    /// Carry bytes until the transport fails (returns why) or the program stops.
    fn serve(&mut self, mut stream: Box<dyn ByteStream>) -> Option<LinkProblem> {
        let mut buf = [0u8; 256];
        // A link test at every connection: the round trip shows in the status.
        let mut ping_due = true;
        while !self.stop.load(Ordering::Relaxed) {
            // Commands first, so each goes out the moment it is stamped.
            let now_s = self.now_s();
            if let Some(injection) = self.inject
                && injection.thread == ThreadName::CameraLink
                && now_s >= injection.at_s
            {
                injection.strike(&self.stop);
            }
            ping_due |= self.ping_requests.try_recv().is_ok() || self.core.keepalive_due(now_s);
            let ping = ping_due.then(|| self.core.ping(now_s));
            ping_due = false;
            let command = self
                .core
                .command(self.robot.snapshot().mode.drives(), now_s);
            for byte in [ping, command].into_iter().flatten() {
                if let Err(e) = stream.write_all(&[byte]) {
                    return Some(LinkProblem::Vanished(e.kind()));
                }
            }
            let n = match stream.read(&mut buf) {
                Ok(0) => return Some(LinkProblem::PeerClosed),
                Ok(n) => n,
                Err(e)
                    if matches!(
                        e.kind(),
                        ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted
                    ) =>
                {
                    0
                }
                Err(e) => return Some(LinkProblem::Vanished(e.kind())),
            };
            let now_s = self.now_s();
            let usable = self.core.receive(&buf[..n], now_s);
            self.core.beat(now_s);
            // Published before the steer thread is woken: it runs at a higher priority
            // and reads the estimate from this status at once.
            self.publish_status();
            if usable {
                let _ = self.new_estimate.try_send(());
            }
        }
        None
    }
}

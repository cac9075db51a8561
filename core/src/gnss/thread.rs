//! The GNSS link thread: opens the receiver's port (serial or TCP, as the camera link
//! does, through camlink's opener so that a slow network never stalls it), feeds every
//! byte to the decoder, and publishes the status after each read. A receiver streams by
//! itself: nothing is ever written to it. A port that fails is opened again with
//! back-off; whether GNSS still steers is the steer thread's decision (no trusted fix
//! for [gnss] timeout_s is GNSS lost).

use std::io::{ErrorKind, Read};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::{GnssCore, GnssStatus};
use crate::camlink::opener::{Heard, Opening};
use crate::camlink::transport::{ByteStream, system_resolver};
use crate::config::CameraPort;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::state::Writer;

/// A read waits at most this long, so the thread beats and sees a stop in time.
const READ_TIMEOUT: Duration = Duration::from_millis(20);
const BACKOFF_MIN: Duration = Duration::from_millis(100);
const BACKOFF_MAX: Duration = Duration::from_secs(2);

pub(crate) struct GnssThread {
    core: GnssCore,
    port: CameraPort,
    clock: Instant,
    status: Writer<GnssStatus>,
    panics: Arc<PanicFlag>,
    stop: Arc<AtomicBool>,
}

impl GnssThread {
    pub fn new(
        port: CameraPort,
        clock: Instant,
        status: Writer<GnssStatus>,
        panics: Arc<PanicFlag>,
        stop: Arc<AtomicBool>,
    ) -> GnssThread {
        GnssThread {
            core: GnssCore::new(),
            port,
            clock,
            status,
            panics,
            stop,
        }
    }

    fn now_s(&self) -> f64 {
        self.clock.elapsed().as_secs_f64()
    }

    fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    pub fn run(mut self) {
        health::watch_this_thread(&self.panics, ThreadName::Gnss);
        let mut backoff = BACKOFF_MIN;
        let mut said_why = None;
        while !self.stopping() {
            match self.open() {
                Some(Ok(stream)) => {
                    tracing::info!("GNSS receiver open on {}", self.port.describe());
                    backoff = BACKOFF_MIN;
                    said_why = None;
                    self.core.reconnected();
                    if let Some(why) = self.serve(stream)
                        && !self.stopping()
                    {
                        tracing::warn!(
                            "GNSS receiver on {}: {why}; opening it again",
                            self.port.describe()
                        );
                    }
                }
                Some(Err(e)) => {
                    if said_why != Some(e.kind()) {
                        tracing::warn!(
                            "GNSS receiver: cannot open {}: {e}; trying again every {} s at most",
                            self.port.describe(),
                            BACKOFF_MAX.as_secs()
                        );
                    }
                    said_why = Some(e.kind());
                }
                None => break,
            }
            self.sleep(backoff);
            backoff = (backoff * 2).min(BACKOFF_MAX);
        }
    }

    /// Open the port on a helper thread, beating meanwhile; None when the program stops.
    fn open(&mut self) -> Option<std::io::Result<Box<dyn ByteStream>>> {
        let opening = match Opening::start(&self.port, system_resolver, READ_TIMEOUT) {
            Ok(opening) => opening,
            Err(e) => return Some(Err(e)),
        };
        while !self.stopping() {
            if let Heard::Done(result) = opening.poll(READ_TIMEOUT) {
                return Some(result);
            }
            self.beat();
        }
        None
    }

    fn beat(&mut self) {
        self.core.beat(self.now_s());
        self.status.publish(self.core.status());
    }

    fn sleep(&mut self, total: Duration) {
        let end = Instant::now() + total;
        while !self.stopping() && Instant::now() < end {
            std::thread::sleep(READ_TIMEOUT);
            self.beat();
        }
    }

    /// Read until the port fails (returns why) or the program stops.
    fn serve(&mut self, mut stream: Box<dyn ByteStream>) -> Option<String> {
        let mut buf = [0u8; 512];
        while !self.stopping() {
            let n = match stream.read(&mut buf) {
                Ok(0) => return Some("the receiver closed the connection".to_string()),
                Ok(n) => n,
                Err(e)
                    if matches!(
                        e.kind(),
                        ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted
                    ) =>
                {
                    0
                }
                Err(e) => return Some(e.to_string()),
            };
            let now_s = self.now_s();
            self.core.receive(&buf[..n], now_s);
            self.core.beat(now_s);
            self.status.publish(self.core.status());
        }
        None
    }
}

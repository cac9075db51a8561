//! The controller's side of its bus process: start it (`mechweed bus-gateway`, the same
//! binary), talk to it through two threads at normal priority, see it end, and say how it
//! ended. The controller's real-time threads never touch any of this: the bus thread
//! reads them through protected objects and a queue that drops (bus/thread.rs).

use std::io::BufReader;
use std::os::fd::OwnedFd;
use std::os::unix::net::UnixStream;
use std::os::unix::process::ExitStatusExt;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, Sender, TrySendError, bounded};

use super::{Down, Up, receive, send};
use crate::config::Settings;

/// How long a bus process may take to open its session (TLS, the roster, the ports).
const READY_WITHIN: Duration = Duration::from_secs(20);
/// Messages waiting to go down: about a second of status, ticks and events. A full
/// queue drops (the bus's rule: a slow receiver gets the latest, not a backlog).
const DOWN_QUEUE: usize = 128;
/// Messages waiting to be read by the bus thread.
const UP_QUEUE: usize = 256;
/// A bus process asked to end (its link closed) that has not ended in this long is
/// killed.
const END_WITHIN: Duration = Duration::from_secs(2);

/// A running bus process.
pub struct Gateway {
    child: Child,
    to: Option<Sender<Down>>,
    pub from: Receiver<Up>,
}

impl Gateway {
    /// Start a bus process for the run `settings` and wait until its session is open;
    /// the error says why it could not (the bus's own words where it said them).
    pub fn start(settings: &Settings) -> Result<Gateway, String> {
        let program = std::env::current_exe()
            .map_err(|e| format!("cannot find this program to start the bus process: {e}"))?;
        let (ours, theirs) =
            UnixStream::pair().map_err(|e| format!("cannot make the bus process's link: {e}"))?;
        let child = Command::new(&program)
            .arg("bus-gateway")
            .stdin(Stdio::from(OwnedFd::from(theirs)))
            .spawn()
            .map_err(|e| format!("cannot start {} bus-gateway: {e}", program.display()))?;
        let (to, queued) = bounded::<Down>(DOWN_QUEUE);
        let (up, from) = bounded::<Up>(UP_QUEUE);
        let writer = ours.try_clone().map_err(|e| e.to_string())?;
        spawn("bus-to-process", move || write_process(writer, &queued));
        spawn("bus-from-process", move || read_process(ours, &up));
        let mut gateway = Gateway {
            child,
            to: Some(to),
            from,
        };
        let s = &settings.source;
        gateway.send(Down::Hello {
            label: s.label.clone(),
            text: s.text.clone(),
            overrides: s.overrides.clone(),
        });
        match gateway.from.recv_timeout(READY_WITHIN) {
            Ok(Up::Ready) => Ok(gateway),
            Ok(Up::Failed { why }) => Err(why),
            Ok(other) => Err(format!("the bus process began with {other:?}, not ready")),
            Err(RecvTimeoutError::Timeout) => Err(format!(
                "the bus process did not open its session within {} s",
                READY_WITHIN.as_secs()
            )),
            Err(RecvTimeoutError::Disconnected) => Err(format!(
                "the bus process ended before its session was open ({})",
                gateway.end()
            )),
        }
    }

    /// Hand `message` to the bus process; false when its queue is full or it has ended
    /// (the message is dropped).
    pub fn send(&self, message: Down) -> bool {
        let to = self.to.as_ref().map(|to| to.try_send(message));
        matches!(to, Some(Ok(())))
    }

    /// Hand on an answer, waiting a little for room: a dropped answer leaves its asker
    /// waiting until it gives up.
    pub fn answer(&self, message: Down) {
        if let Some(to) = &self.to
            && let Err(e) = to.send_timeout(message, Duration::from_millis(200))
        {
            tracing::debug!("bus: an answer not handed to the bus process: {e}");
        }
    }

    /// The process id, for the words of a restart.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// End the bus process (close its link, then kill it if it stays) and say how it
    /// ended, in words: "exit status 0", "signal 9 (killed)".
    pub fn end(&mut self) -> String {
        self.to = None;
        let deadline = Instant::now() + END_WITHIN;
        let status = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                Ok(None) | Err(_) => {
                    let _ = self.child.kill();
                    break self.child.wait().ok();
                }
            }
        };
        match status {
            Some(s) => match (s.code(), s.signal()) {
                (Some(code), _) => format!("exit status {code}"),
                (None, Some(signal)) => format!("signal {signal} ({})", signal_name(signal)),
                _ => s.to_string(),
            },
            None => "how is not known".to_string(),
        }
    }
}

/// However the run ends, its bus process ends with it.
impl Drop for Gateway {
    fn drop(&mut self) {
        self.to = None;
        if matches!(self.child.try_wait(), Ok(None)) {
            self.end();
        }
    }
}

fn signal_name(signal: i32) -> &'static str {
    match signal {
        libc::SIGKILL => "killed",
        libc::SIGSEGV => "a memory fault",
        libc::SIGABRT => "aborted",
        libc::SIGTERM => "asked to end",
        libc::SIGBUS => "a bus error",
        _ => "a signal",
    }
}

fn spawn(name: &str, f: impl FnOnce() + Send + 'static) {
    if let Err(e) = std::thread::Builder::new().name(name.to_string()).spawn(f) {
        tracing::error!("cannot start the {name} thread: {e}");
    }
}

/// Every message handed down, until the bus thread lets go of its sender; then the
/// link's write side closes and the bus process reads its end.
fn write_process(mut link: UnixStream, queued: &Receiver<Down>) {
    for message in queued {
        if send(&mut link, &message).is_err() {
            break;
        }
    }
    let _ = link.shutdown(std::net::Shutdown::Write);
}

/// Every message from the bus process, until its end closes. What is not a message
/// ends the link (said): a bus process that sends it is not to be believed further.
fn read_process(link: UnixStream, up: &Sender<Up>) {
    let mut input = BufReader::new(link);
    loop {
        match receive::<Up>(&mut input) {
            Ok(Some(message)) => match up.try_send(message) {
                Ok(()) | Err(TrySendError::Full(_)) => {}
                Err(TrySendError::Disconnected(_)) => return,
            },
            Ok(None) => return,
            Err(e) => {
                tracing::error!("bus: from the bus process: {e}");
                return;
            }
        }
    }
}

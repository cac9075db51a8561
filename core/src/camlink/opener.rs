//! Opening the camera port without stalling the link thread. A camera computer named
//! by host name needs a name look-up, which blocks for seconds when there is no
//! network, and a connect to an address that does not answer waits for its time-out;
//! meanwhile the link thread must go on beating, or the supervisor faults "the camera
//! link thread stopped" in every mode. So the opening runs on a short-lived helper
//! thread, and the link thread polls it. There is never more than one: the link thread
//! waits for its answer, however long it takes, before it tries again.

use std::io;
use std::time::Duration;

use crossbeam_channel::{Receiver, RecvTimeoutError, unbounded};

use super::OpenStep;
use super::transport::{ByteStream, Resolver, open};
use crate::config::CameraPort;

/// What the helper thread says.
enum Message {
    Step(OpenStep),
    Done(io::Result<Box<dyn ByteStream>>),
}

/// What a poll heard.
pub enum Heard {
    /// Nothing yet: still waiting.
    Nothing,
    /// The opening has moved on to this step.
    Step(OpenStep),
    /// The port is open, or why not.
    Done(io::Result<Box<dyn ByteStream>>),
}

/// One opening of the port, under way on its helper thread.
pub struct Opening {
    messages: Receiver<Message>,
}

impl Opening {
    /// Start opening `port` (reads will wait at most `read_timeout` for a byte).
    pub fn start(
        port: &CameraPort,
        resolve: Resolver,
        read_timeout: Duration,
    ) -> io::Result<Opening> {
        let (tx, messages) = unbounded();
        let port = port.clone();
        // Not watched by the panic flag: a failure here is a port that does not open,
        // which the link thread reports and retries (the helper has no outputs).
        std::thread::Builder::new()
            .name("camlink-open".into())
            .spawn(move || {
                let step = |s| {
                    let _ = tx.send(Message::Step(s));
                };
                let result = open(&port, resolve, read_timeout, &step);
                // If the link thread has stopped meanwhile, the port closes here.
                let _ = tx.send(Message::Done(result));
            })?;
        Ok(Opening { messages })
    }

    /// Wait at most `wait` for news.
    pub fn poll(&self, wait: Duration) -> Heard {
        match self.messages.recv_timeout(wait) {
            Ok(Message::Step(step)) => Heard::Step(step),
            Ok(Message::Done(result)) => Heard::Done(result),
            Err(RecvTimeoutError::Timeout) => Heard::Nothing,
            Err(RecvTimeoutError::Disconnected) => Heard::Done(Err(io::Error::other(
                "opening the camera port failed (its helper thread ended without an answer)",
            ))),
        }
    }
}

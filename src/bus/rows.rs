//! Row estimates from the bus (`[camera] port = bus`): a vision program on any machine
//! publishes `ROBOT/camera/row`, and the camera link thread reads them as it reads a
//! camera computer's bytes. Each estimate that passes the checks of payload.rs becomes
//! the ROW frame the camera computer would have sent, so the link's decoder, counters
//! (sequence gaps, duplicates), quality rule and freshness time-out are the very same:
//! a vision program that stops publishing stops the robot with the link's fault.

use std::io::{self, Read, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use crossbeam_channel::{Receiver, bounded};
use mechweed_hw::camproto::{FRAME_LEN, encode_row};
use zenoh::{Session, Wait};

use super::payload::parse_row;

/// Counts of what came in on `ROBOT/camera/row`.
#[derive(Debug, Default)]
pub struct RowCounts {
    pub received: AtomicU64,
    pub rejected: AtomicU64,
}

/// The camera link's byte stream when the rows come from the bus.
pub struct BusRows {
    frames: Receiver<[u8; FRAME_LEN]>,
    read_timeout: Duration,
    _subscriber: zenoh::pubsub::Subscriber<()>,
}

/// Frames waiting for the link thread; it reads every 10 ms, so a few are plenty, and a
/// full queue drops the newest estimate rather than wait in zenoh's callback.
const QUEUE_FRAMES: usize = 8;

impl BusRows {
    /// Subscribe to `key`; bad estimates are counted in `counts` and logged with why.
    pub fn subscribe(
        session: &Session,
        key: &str,
        read_timeout: Duration,
        counts: Arc<RowCounts>,
    ) -> zenoh::Result<BusRows> {
        let (tx, frames) = bounded(QUEUE_FRAMES);
        let key_text = key.to_string();
        let subscriber = session
            .declare_subscriber(key)
            .callback(move |sample| {
                counts.received.fetch_add(1, Ordering::Relaxed);
                match parse_row(&sample.payload().to_bytes()) {
                    Ok(estimate) => {
                        let _ = tx.try_send(encode_row(&estimate));
                    }
                    Err(why) => {
                        let n = counts.rejected.fetch_add(1, Ordering::Relaxed) + 1;
                        // The first few name the problem; a flood is only counted.
                        if n <= 5 {
                            tracing::warn!("{key_text}: row estimate refused: {why}");
                        }
                    }
                }
            })
            .wait()?;
        Ok(BusRows {
            frames,
            read_timeout,
            _subscriber: subscriber,
        })
    }
}

impl Read for BusRows {
    /// The frames that came, or a time-out after `read_timeout` as a serial port gives.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.len() < FRAME_LEN {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "read a whole frame at a time",
            ));
        }
        let first = self
            .frames
            .recv_timeout(self.read_timeout)
            .map_err(|_| io::Error::new(io::ErrorKind::TimedOut, "no row estimate"))?;
        buf[..FRAME_LEN].copy_from_slice(&first);
        let mut n = FRAME_LEN;
        // Take more only while there is room: a frame taken is never cut.
        while buf.len() - n >= FRAME_LEN {
            let Ok(frame) = self.frames.try_recv() else {
                break;
            };
            buf[n..n + FRAME_LEN].copy_from_slice(&frame);
            n += FRAME_LEN;
        }
        Ok(n)
    }
}

impl Write for BusRows {
    /// START, STOP and PING mean nothing to a vision program on the bus, which
    /// publishes as long as it runs: they are taken and dropped.
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

//! Row estimates from the bus (`[camera] port = bus`): a vision program on any machine
//! publishes `ROBOT/camera/row`, the bus process hands each on, and the camera link
//! thread reads them as it reads a camera computer's bytes. Each estimate that passes the checks of payload.rs becomes
//! the ROW frame the camera computer would have sent, so the link's decoder, counters
//! (sequence gaps, duplicates), quality rule and freshness time-out are the very same:
//! a vision program that stops publishing stops the robot with the link's fault.

use std::io::{self, Read, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Sender, bounded};
use mechweed_hw::camproto::{FRAME_LEN, encode_row};

use super::payload::parse_row;
use super::row_clock::{RowClock, Verdict};

/// Counts of what came in on `ROBOT/camera/row`.
#[derive(Debug, Default)]
pub struct RowCounts {
    pub received: AtomicU64,
    pub rejected: AtomicU64,
    /// Set by the bus thread while two programs with the camera's identity are linked:
    /// no row is taken then (identities.rs).
    pub rivals: Arc<AtomicBool>,
}

/// The camera link's byte stream when the rows come from the bus.
pub(crate) struct BusRows {
    /// Each payload with its arrival, s since 1970.
    payloads: Receiver<(Vec<u8>, f64)>,
    clock: RowClock,
    read_timeout: Duration,
    counts: Arc<RowCounts>,
    key: String,
}

/// Estimates waiting for the link thread; it reads every 10 ms, so a few are plenty, and
/// a full queue drops the newest rather than wait in the bus thread.
const QUEUE_ROWS: usize = 8;

impl BusRows {
    /// The rows that come in under `key`, and where the bus thread puts them.
    /// `max_age_s`: a row older than this by its capture time is stale (row_clock.rs).
    pub(crate) fn new(
        key: &str,
        read_timeout: Duration,
        max_age_s: f64,
        counts: Arc<RowCounts>,
    ) -> (BusRows, Sender<(Vec<u8>, f64)>) {
        let (tx, payloads) = bounded(QUEUE_ROWS);
        let rows = BusRows {
            payloads,
            clock: RowClock::new(max_age_s),
            read_timeout,
            counts,
            key: key.to_string(),
        };
        (rows, tx)
    }

    /// The frame for one payload, or None for one refused (counted, and the first few
    /// logged with why).
    fn frame(&mut self, payload: &[u8], arrived_s: f64) -> Option<[u8; FRAME_LEN]> {
        self.counts.received.fetch_add(1, Ordering::Relaxed);
        if self.counts.rivals.load(Ordering::Relaxed) {
            // Whose row this is cannot be told: none is taken.
            self.counts.rejected.fetch_add(1, Ordering::Relaxed);
            return None;
        }
        let refused = match parse_row(payload) {
            Ok((estimate, t_s)) => {
                let (verdict, said) = self.clock.row(t_s, arrived_s);
                if let Some(line) = said {
                    tracing::info!("{line}");
                }
                match verdict {
                    Verdict::Take => return Some(encode_row(&estimate)),
                    Verdict::Stale(why) => format!("stale: {why}"),
                }
            }
            Err(why) => why,
        };
        let n = self.counts.rejected.fetch_add(1, Ordering::Relaxed) + 1;
        // The first few name the problem; a flood is only counted.
        if n <= 5 {
            tracing::warn!("{}: row estimate refused: {refused}", self.key);
        }
        None
    }
}

impl Read for BusRows {
    /// The frames of the estimates that came, or a time-out after `read_timeout` as a
    /// serial port gives.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.len() < FRAME_LEN {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "read a whole frame at a time",
            ));
        }
        let deadline = Instant::now() + self.read_timeout;
        let mut n = 0;
        // Wait for the first payload; then take what is there while a frame fits.
        while buf.len() - n >= FRAME_LEN {
            let payload = if n == 0 {
                self.payloads.recv_deadline(deadline).ok()
            } else {
                self.payloads.try_recv().ok()
            };
            let Some((payload, arrived_s)) = payload else {
                break;
            };
            if let Some(frame) = self.frame(&payload, arrived_s) {
                buf[n..n + FRAME_LEN].copy_from_slice(&frame);
                n += FRAME_LEN;
            }
        }
        if n == 0 {
            return Err(io::Error::new(io::ErrorKind::TimedOut, "no row estimate"));
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

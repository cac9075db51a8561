//! The camera link, program side: bytes from the camera computer in, decoded row
//! estimates out, and the commands (START / STOP / PING) that keep it streaming while
//! the steer side wants rows. `LinkCore` is transport-free: the link thread
//! (thread.rs, over a serial port or TCP) and the lockstep simulation feed it bytes
//! and send the command bytes it asks for.

pub mod opener;
pub mod simwire;
pub mod thread;
pub mod transport;

use std::fmt;

use mechweed_hw::camproto::{
    CMD_PING, CMD_START, CMD_STOP, Decoder, Frame, LinkCounters, RowEstimate,
};

use crate::config::CameraSettings;

/// What went wrong with the transport, kept for the status (the thread logs details).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkProblem {
    /// The device or address could not be opened (missing, no permission, refused).
    OpenFailed(std::io::ErrorKind),
    /// Reading or writing failed: the device vanished (USB adapter unplugged?).
    Vanished(std::io::ErrorKind),
    /// The TCP peer closed the connection.
    PeerClosed,
}

impl fmt::Display for LinkProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinkProblem::OpenFailed(kind) => write!(f, "cannot open the camera port ({kind})"),
            LinkProblem::Vanished(kind) => {
                write!(f, "the camera port stopped working ({kind}): unplugged?")
            }
            LinkProblem::PeerClosed => write!(f, "the camera computer closed the connection"),
        }
    }
}

/// What the link thread waits for while the camera port is being opened (on a helper
/// thread, so that the link thread keeps beating: opener.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenStep {
    /// Looking up the camera computer's host name (tcp://HOST:PORT): without a network
    /// this can take seconds.
    LookingUp,
    /// Opening the serial device, or connecting to the camera computer's address.
    Opening,
}

impl fmt::Display for OpenStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OpenStep::LookingUp => write!(f, "looking up the camera computer's name"),
            OpenStep::Opening => write!(f, "opening the camera port"),
        }
    }
}

/// The link as the other threads see it. Times are s since start; -inf = never.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkStatus {
    pub counters: LinkCounters,
    /// Last valid ROW frame (whatever its quality) and when it arrived.
    pub last_row: RowEstimate,
    pub last_row_s: f64,
    /// Last ROW frame good enough to steer by, and when it arrived.
    pub last_usable: RowEstimate,
    pub last_usable_s: f64,
    /// START has been sent and not yet taken back by STOP.
    pub streaming: bool,
    /// When START was first sent for this spell of streaming, s.
    pub streaming_since_s: f64,
    /// When the camera computer last sent a valid frame, a row or a PONG, s: standing,
    /// it answers the link's keep-alive PINGs, so a computer switched off shows.
    pub heard_s: f64,
    pub starts_sent: u64,
    pub stops_sent: u64,
    /// The transport is open.
    pub connected: bool,
    /// Times the transport was opened again after a problem.
    pub reconnects: u64,
    /// The latest transport problem, if the link is not connected.
    pub problem: Option<LinkProblem>,
    /// What the link thread waits for while it opens the port (None: not opening).
    pub opening: Option<OpenStep>,
    pub pings_sent: u64,
    /// Round trip of the last PING, ms (NaN until a PONG has come back).
    pub ping_rtt_ms: f64,
    /// When the link thread last showed a sign of life, s (its heartbeat).
    pub beat_s: f64,
    /// Rows from the bus: two programs with the camera's identity send them at once,
    /// and the rows of neither are taken.
    pub rival_sources: bool,
}

impl Default for LinkStatus {
    fn default() -> Self {
        LinkStatus {
            counters: LinkCounters::default(),
            last_row: RowEstimate::default(),
            last_row_s: f64::NEG_INFINITY,
            last_usable: RowEstimate::default(),
            last_usable_s: f64::NEG_INFINITY,
            streaming: false,
            streaming_since_s: f64::NEG_INFINITY,
            heard_s: f64::NEG_INFINITY,
            starts_sent: 0,
            stops_sent: 0,
            connected: false,
            reconnects: 0,
            problem: None,
            opening: None,
            pings_sent: 0,
            ping_rtt_ms: f64::NAN,
            beat_s: 0.0,
            rival_sources: false,
        }
    }
}

pub struct LinkCore {
    settings: CameraSettings,
    decoder: Decoder,
    status: LinkStatus,
    last_start_s: f64,
    ping_sent_s: Option<f64>,
    last_ping_s: f64,
}

/// While not streaming, the link PINGs the camera computer this often, s: the robot
/// standing in Halt still knows whether its camera answers (the supervisor refuses
/// Autonomous when it has not for a while: supervisor/sensors.rs).
pub const KEEPALIVE_S: f64 = 1.0;

impl LinkCore {
    pub fn new(settings: &CameraSettings) -> LinkCore {
        LinkCore {
            settings: *settings,
            decoder: Decoder::new(),
            status: LinkStatus::default(),
            last_start_s: f64::NEG_INFINITY,
            ping_sent_s: None,
            last_ping_s: f64::NEG_INFINITY,
        }
    }

    pub fn status(&self) -> &LinkStatus {
        &self.status
    }

    /// Decode bytes that arrived at `now_s`. Returns true if a usable row estimate came.
    pub fn receive(&mut self, bytes: &[u8], now_s: f64) -> bool {
        let mut usable = false;
        for &byte in bytes {
            match self.decoder.push(byte) {
                Some(Frame::Row(estimate)) => {
                    self.status.heard_s = now_s;
                    self.status.last_row = estimate;
                    self.status.last_row_s = now_s;
                    if estimate.quality >= self.settings.min_quality {
                        self.status.last_usable = estimate;
                        self.status.last_usable_s = now_s;
                        usable = true;
                    }
                }
                Some(Frame::Pong { .. }) => {
                    self.status.heard_s = now_s;
                    if let Some(sent_s) = self.ping_sent_s.take() {
                        self.status.ping_rtt_ms = (now_s - sent_s) * 1e3;
                    }
                }
                None => {}
            }
        }
        self.status.counters = self.decoder.counters;
        usable
    }

    /// The link thread is alive at `now_s` (the supervisor watches this).
    pub fn beat(&mut self, now_s: f64) {
        self.status.beat_s = now_s;
    }

    /// Whether two programs send rows on the bus now.
    pub(crate) fn rival_sources(&mut self, rivals: bool) {
        self.status.rival_sources = rivals;
    }

    /// The link thread is opening the port and waits for `step`.
    pub fn opening(&mut self, step: OpenStep) {
        self.status.opening = Some(step);
    }

    /// The transport opened (again): the camera computer has not heard START on it.
    pub fn connected(&mut self) {
        if self.status.problem.is_some() {
            self.status.reconnects += 1;
        }
        self.status.connected = true;
        self.status.problem = None;
        self.status.opening = None;
        self.status.streaming = false;
    }

    /// The transport failed; the link thread will try to open it again.
    pub(crate) fn disconnected(&mut self, problem: LinkProblem) {
        self.status.connected = false;
        self.status.problem = Some(problem);
        self.status.opening = None;
        self.status.streaming = false;
        self.ping_sent_s = None;
    }

    /// A link test: the PING byte to send; the round trip shows in the status.
    pub fn ping(&mut self, now_s: f64) -> u8 {
        self.ping_sent_s = Some(now_s);
        self.last_ping_s = now_s;
        self.status.pings_sent += 1;
        CMD_PING
    }

    /// A keep-alive PING is due at `now_s`: not streaming (rows show that the camera
    /// computer is there), and no PING for KEEPALIVE_S.
    pub fn keepalive_due(&self, now_s: f64) -> bool {
        !self.status.streaming && now_s - self.last_ping_s >= KEEPALIVE_S
    }

    /// The command byte to send now, if any: START when rows are wanted (again after
    /// `restart_after_s` without a frame: the camera computer may have rebooted), STOP
    /// when they are no longer wanted.
    pub fn command(&mut self, wants_rows: bool, now_s: f64) -> Option<u8> {
        let st = &mut self.status;
        if wants_rows {
            let quiet_s = now_s - st.last_row_s.max(self.last_start_s);
            if !st.streaming || quiet_s > self.settings.restart_after_s {
                if !st.streaming {
                    st.streaming_since_s = now_s;
                }
                st.streaming = true;
                st.starts_sent += 1;
                self.last_start_s = now_s;
                return Some(CMD_START);
            }
        } else if st.streaming {
            st.streaming = false;
            st.stops_sent += 1;
            return Some(CMD_STOP);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;
    use mechweed_hw::camproto::encode_row;

    #[test]
    fn start_stop_and_restart_after_silence() {
        let mut link = LinkCore::new(&Settings::shipped().camera);
        assert_eq!(link.command(true, 0.0), Some(CMD_START));
        assert_eq!(link.command(true, 0.1), None);
        let frame = encode_row(&RowEstimate {
            seq: 0,
            angle_rad: 0.0,
            offset_m: 0.0,
            quality: 90,
        });
        assert!(link.receive(&frame, 0.2));
        assert_eq!(link.command(true, 0.4), None);
        // Silent for longer than restart_after_s: START again.
        assert_eq!(link.command(true, 0.2 + 0.31), Some(CMD_START));
        assert_eq!(link.command(false, 0.6), Some(CMD_STOP));
        assert_eq!(link.command(false, 0.7), None);
    }

    #[test]
    fn ping_round_trip_and_restart_after_reconnect() {
        let mut link = LinkCore::new(&Settings::shipped().camera);
        link.connected();
        assert_eq!(link.ping(1.0), CMD_PING);
        assert!(link.status().ping_rtt_ms.is_nan());
        link.receive(&mechweed_hw::camproto::encode_pong(0), 1.004);
        assert!((link.status().ping_rtt_ms - 4.0).abs() < 1e-9);
        assert_eq!(link.command(true, 2.0), Some(CMD_START));
        link.disconnected(LinkProblem::PeerClosed);
        link.connected();
        assert_eq!(link.status().reconnects, 1);
        // A new connection has not heard START.
        assert_eq!(link.command(true, 2.1), Some(CMD_START));
    }

    #[test]
    fn low_quality_frames_count_but_are_not_usable() {
        let mut link = LinkCore::new(&Settings::shipped().camera);
        let frame = encode_row(&RowEstimate {
            seq: 0,
            angle_rad: 0.0,
            offset_m: 0.0,
            quality: 0,
        });
        assert!(!link.receive(&frame, 1.0));
        assert_eq!(link.status().last_row_s, 1.0);
        assert_eq!(link.status().last_usable_s, f64::NEG_INFINITY);
    }

    #[test]
    fn a_duplicated_frame_does_not_make_the_link_look_fresh() {
        let mut link = LinkCore::new(&Settings::shipped().camera);
        let frame = encode_row(&RowEstimate {
            seq: 4,
            angle_rad: 0.0,
            offset_m: 0.0,
            quality: 90,
        });
        assert!(link.receive(&frame, 1.0));
        // The same frame again, later: not news, not steered by.
        assert!(!link.receive(&frame, 1.4));
        let st = link.status();
        assert_eq!((st.last_row_s, st.last_usable_s), (1.0, 1.0));
        assert_eq!(st.counters.duplicates, 1);
        assert_eq!(st.counters.seq_gaps, 0);
    }
}

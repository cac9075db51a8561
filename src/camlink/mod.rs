//! The camera link, program side: bytes from the camera computer in, decoded row
//! estimates out, and the commands (START / STOP) that keep it streaming while the
//! steer side wants rows. Transport-free: the link thread (run.rs) and the lockstep
//! simulation feed it bytes and send the command bytes it asks for.

use mechweed_hw::camproto::{CMD_START, CMD_STOP, Decoder, Frame, LinkCounters, RowEstimate};

use crate::config::CameraSettings;

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
    pub starts_sent: u64,
    pub stops_sent: u64,
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
            starts_sent: 0,
            stops_sent: 0,
        }
    }
}

pub struct LinkCore {
    settings: CameraSettings,
    decoder: Decoder,
    status: LinkStatus,
    last_start_s: f64,
}

impl LinkCore {
    pub fn new(settings: &CameraSettings) -> LinkCore {
        LinkCore {
            settings: *settings,
            decoder: Decoder::new(),
            status: LinkStatus::default(),
            last_start_s: f64::NEG_INFINITY,
        }
    }

    pub fn status(&self) -> &LinkStatus {
        &self.status
    }

    /// Decode bytes that arrived at `now_s`. Returns true if a usable row estimate came.
    pub fn receive(&mut self, bytes: &[u8], now_s: f64) -> bool {
        let mut usable = false;
        for &byte in bytes {
            if let Some(Frame::Row(estimate)) = self.decoder.push(byte) {
                self.status.last_row = estimate;
                self.status.last_row_s = now_s;
                if estimate.quality >= self.settings.min_quality {
                    self.status.last_usable = estimate;
                    self.status.last_usable_s = now_s;
                    usable = true;
                }
            }
        }
        self.status.counters = self.decoder.counters;
        usable
    }

    /// The command byte to send now, if any: START when rows are wanted (again after
    /// `restart_after_s` without a frame: the camera computer may have rebooted), STOP
    /// when they are no longer wanted.
    pub fn command(&mut self, wants_rows: bool, now_s: f64) -> Option<u8> {
        let st = &mut self.status;
        if wants_rows {
            let quiet_s = now_s - st.last_row_s.max(self.last_start_s);
            if !st.streaming || quiet_s > self.settings.restart_after_s {
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
}

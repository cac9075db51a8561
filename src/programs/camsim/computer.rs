//! `mechweed camsim`: a stand-alone simulated camera computer, for bench-testing a robot
//! computer or a link without the camera. It speaks docs/function_spec.md section 7: after START
//! it sends a ROW frame about every 0.1 s, STOP stops them, PING gets one PONG; any
//! other byte is ignored. Frames can be dropped or damaged on purpose.

use std::io::{self, ErrorKind};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use mechweed_hw::camproto::{CMD_PING, CMD_START, CMD_STOP, RowEstimate, encode_pong, encode_row};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::camlink::transport::ByteStream;

/// What the simulated row looks like.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Pattern {
    /// The robot on a straight row: offset and angle near zero, with camera noise.
    Straight,
    /// The row sways from side to side: 5 cm, every 4 s.
    Sway,
    /// No row in sight: quality 0.
    Lost,
}

#[derive(Debug, Clone, Copy)]
pub struct CamSimOptions {
    pub pattern: Pattern,
    pub seed: u64,
    /// Share of frames not sent (their sequence numbers are used up).
    pub drop: f64,
    /// Probability that a byte is damaged.
    pub corrupt: f64,
}

/// Frame interval and camera noise (the [sim] settings in config/robot.ini).
const FRAME_INTERVAL_S: f64 = 0.1;
const NOISE_OFFSET_M: f64 = 0.01;
const NOISE_ANGLE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// What a camsim has sent and heard since it started, for its once-a-second line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Sent {
    pub row_frames: u64,
    /// ROW frames left out on purpose (--drop).
    pub dropped: u64,
    pub pongs: u64,
    pub commands_received: u64,
}

impl Sent {
    /// What happened since `before`.
    pub fn since(&self, before: &Sent) -> Sent {
        Sent {
            row_frames: self.row_frames - before.row_frames,
            dropped: self.dropped - before.dropped,
            pongs: self.pongs - before.pongs,
            commands_received: self.commands_received - before.commands_received,
        }
    }
}

pub struct CamSim {
    opts: CamSimOptions,
    pub sent: Sent,
    rng: ChaCha8Rng,
    streaming: bool,
    seq: u8,
    next_frame_s: f64,
    pongs_due: u32,
}

impl CamSim {
    pub fn new(opts: CamSimOptions) -> CamSim {
        CamSim {
            opts,
            rng: ChaCha8Rng::seed_from_u64(opts.seed),
            streaming: false,
            seq: 0,
            next_frame_s: 0.0,
            pongs_due: 0,
            sent: Sent::default(),
        }
    }

    pub(crate) fn is_streaming(&self) -> bool {
        self.streaming
    }

    /// A byte from the robot computer; returns the command's name if it was one.
    pub fn receive(&mut self, byte: u8, now_s: f64) -> Option<&'static str> {
        let name = self.command(byte, now_s);
        self.sent.commands_received += u64::from(name.is_some());
        name
    }

    fn command(&mut self, byte: u8, now_s: f64) -> Option<&'static str> {
        match byte {
            CMD_START => {
                if !self.streaming {
                    self.streaming = true;
                    self.next_frame_s = now_s + FRAME_INTERVAL_S;
                }
                Some("START")
            }
            CMD_STOP => {
                self.streaming = false;
                Some("STOP")
            }
            CMD_PING => {
                self.pongs_due += 1;
                Some("PING")
            }
            _ => None,
        }
    }

    /// Come back from a reboot: silent, not streaming, numbering from 0.
    pub fn reboot(&mut self) {
        self.streaming = false;
        self.seq = 0;
        self.pongs_due = 0;
    }

    fn estimate(&mut self, now_s: f64) -> RowEstimate {
        let mut noise = |sd: f64| sd * self.rng.sample::<f64, _>(StandardNormal);
        let (offset_m, angle_rad, quality) = match self.opts.pattern {
            Pattern::Straight => (noise(NOISE_OFFSET_M), noise(NOISE_ANGLE_RAD), 90),
            Pattern::Sway => {
                let phase = std::f64::consts::TAU * now_s / 4.0;
                (
                    0.05 * phase.sin() + noise(NOISE_OFFSET_M),
                    0.03 * phase.cos() + noise(NOISE_ANGLE_RAD),
                    90,
                )
            }
            Pattern::Lost => (0.0, 0.0, 0),
        };
        let seq = self.seq;
        self.seq = self.seq.wrapping_add(1);
        RowEstimate {
            seq,
            angle_rad,
            offset_m,
            quality,
        }
    }

    fn damage(&mut self, frame: &mut [u8]) {
        for byte in frame {
            if self.rng.random::<f64>() < self.opts.corrupt {
                *byte ^= self.rng.random_range(1..=255u8);
            }
        }
    }

    /// Append what is due at `now_s` to `out`: PONGs, and a ROW frame every 0.1 s.
    pub fn poll(&mut self, now_s: f64, out: &mut Vec<u8>) {
        while self.pongs_due > 0 {
            self.pongs_due -= 1;
            let mut frame = encode_pong(self.seq);
            self.seq = self.seq.wrapping_add(1);
            self.damage(&mut frame);
            out.extend_from_slice(&frame);
            self.sent.pongs += 1;
        }
        while let Some(estimate) = self.next_row(now_s) {
            let mut frame = encode_row(&estimate);
            self.damage(&mut frame);
            out.extend_from_slice(&frame);
        }
    }

    /// The next row estimate due at `now_s` while streaming (one every 0.1 s); those
    /// --drop leaves out are counted and skipped.
    pub(crate) fn next_row(&mut self, now_s: f64) -> Option<RowEstimate> {
        while self.streaming && now_s >= self.next_frame_s {
            self.next_frame_s += FRAME_INTERVAL_S;
            let estimate = self.estimate(now_s);
            if self.rng.random::<f64>() < self.opts.drop {
                self.sent.dropped += 1;
                continue;
            }
            self.sent.row_frames += 1;
            return Some(estimate);
        }
        None
    }
}

/// Serve one robot computer on `stream` until it closes or `stop` is set.
/// `on_command(t_s, name)` hears every command received; `each_second(t_s, sim)` is
/// called once a second, so that a bench test can see the camera is alive.
pub fn serve(
    sim: &mut CamSim,
    stream: &mut dyn ByteStream,
    clock: Instant,
    stop: &AtomicBool,
    on_command: &mut dyn FnMut(f64, &'static str),
    each_second: &mut dyn FnMut(f64, &CamSim),
) -> io::Result<()> {
    let mut buf = [0u8; 64];
    let mut out = Vec::with_capacity(64);
    let mut next_second_s = clock.elapsed().as_secs_f64() + 1.0;
    while !stop.load(Ordering::Relaxed) {
        let now_s = clock.elapsed().as_secs_f64();
        if now_s >= next_second_s {
            each_second(now_s, sim);
            next_second_s += 1.0;
        }
        match stream.read(&mut buf) {
            Ok(0) => return Ok(()),
            Ok(n) => {
                for &byte in &buf[..n] {
                    if let Some(name) = sim.receive(byte, now_s) {
                        on_command(now_s, name);
                    }
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted
                ) => {}
            Err(e) => return Err(e),
        }
        out.clear();
        sim.poll(clock.elapsed().as_secs_f64(), &mut out);
        stream.write_all(&out)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::camproto::{Decoder, Frame};

    fn options(pattern: Pattern) -> CamSimOptions {
        CamSimOptions {
            pattern,
            seed: 1,
            drop: 0.0,
            corrupt: 0.0,
        }
    }

    fn frames(bytes: &[u8]) -> Vec<Frame> {
        let mut dec = Decoder::new();
        bytes.iter().filter_map(|&b| dec.push(b)).collect()
    }

    #[test]
    fn streams_after_start_only_and_answers_ping() {
        let mut sim = CamSim::new(options(Pattern::Straight));
        let mut out = Vec::new();
        sim.poll(1.0, &mut out);
        assert!(out.is_empty(), "frames before START");
        assert_eq!(sim.receive(CMD_START, 1.0), Some("START"));
        sim.poll(2.05, &mut out);
        assert_eq!(
            frames(&out).len(),
            10,
            "one frame every 0.1 s from 1.1 s to 2.0 s"
        );
        sim.receive(CMD_PING, 2.0);
        sim.receive(CMD_STOP, 2.0);
        out.clear();
        sim.poll(3.0, &mut out);
        assert!(matches!(frames(&out)[..], [Frame::Pong { .. }]));
        assert_eq!(sim.receive(0x42, 3.0), None);
    }

    #[test]
    fn lost_pattern_has_quality_zero_and_reboot_needs_start() {
        let mut sim = CamSim::new(options(Pattern::Lost));
        sim.receive(CMD_START, 0.0);
        let mut out = Vec::new();
        sim.poll(0.35, &mut out);
        assert!(
            frames(&out)
                .iter()
                .all(|f| matches!(f, Frame::Row(e) if e.quality == 0))
        );
        sim.reboot();
        out.clear();
        sim.poll(1.0, &mut out);
        assert!(out.is_empty());
    }
}

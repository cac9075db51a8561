//! The simulated row camera computer: speaks docs/function_spec.md section 7 on its end of a pipe.
//!
//! After START it captures every 1/rate s: the row's offset and angle at the look-ahead
//! line (sight.rs) plus Gaussian noise. Each frame goes out after the latency (uniform
//! in latency +- jitter), in capture order; the sequence number is given when the frame
//! is due, so a PONG between two ROW frames keeps the numbers counting up. A dropped
//! frame uses its number and writes nothing; a silent link swallows frames (numbers
//! still used) but still hears commands. A reboot forgets everything, ignores the line
//! for `camera_reboot_s`, and then waits for START. Frames waiting for their send time
//! sit in a fixed ring, so running the camera never allocates.
//!
//! In the realistic field (field_tier.rs) the offset also carries an error correlated
//! over distance, a weed patch pulls it aside, and in a gap of the row the camera
//! repeats its last estimate at the tier's low quality, as vision systems that hold the
//! row through a gap do.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::body::Pose;
use super::field::Field;
use super::field_tier::FieldTier;
use super::gauss_markov::GaussMarkov;
use super::params::{FieldKind, SimParams};
use super::pipe::PipeEnd;
use super::sight::row_at_lookahead;
use crate::camproto::{CMD_PING, CMD_START, CMD_STOP, RowEstimate, encode_pong, encode_row};

/// Frames that can wait for their send time at once (0.1 s latency at 10 Hz needs 2).
const RING: usize = 8;
/// Quality of a normal estimate.
const QUALITY_SEEN: u8 = 90;

/// What the camera computer has done, for tests and the GUI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CameraCounters {
    pub captures: u64,
    /// ROW and PONG frames written into the pipe.
    pub frames_written: u64,
    /// Frames not sent on purpose (camera_drop).
    pub frames_dropped: u64,
    /// Frames swallowed by a silent link.
    pub frames_silenced: u64,
    /// Captures lost because the ring of waiting frames was full.
    pub ring_full: u64,
    pub pongs: u64,
}

/// A ROW frame waiting for its send time.
#[derive(Debug, Clone, Copy, Default)]
struct Pending {
    send_t_s: f64,
    angle_rad: f64,
    offset_m: f64,
    quality: u8,
    dropped: bool,
}

pub struct CameraComputer {
    pipe: PipeEnd,
    lookahead_m: f64,
    /// Capture period, s; infinite for a camera that never captures.
    period_s: f64,
    latency_s: f64,
    jitter_s: f64,
    noise_offset_m: f64,
    noise_angle_rad: f64,
    drop_probability: f64,
    corrupt_probability: f64,
    reboot_s: f64,

    streaming: bool,
    next_capture_t_s: f64,
    seq: u8,
    silent_until_t_s: f64,
    booting_until_t_s: f64,
    pong_due: bool,
    pending: [Pending; RING],
    /// Index of the oldest waiting frame, and how many wait.
    head: usize,
    waiting: usize,
    /// Point index on the row near the look-ahead line, for the search.
    hint: usize,
    /// Separate streams, so that turning one effect on does not change another's draws.
    noise_rng: ChaCha8Rng,
    timing_rng: ChaCha8Rng,
    corrupt_rng: ChaCha8Rng,
    counters: CameraCounters,
    /// The realistic field's correlated offset error over distance, from a stream of
    /// its own, and the distance it was last stepped to, m.
    bias: GaussMarkov,
    bias_at_m: f64,
    bias_rng: ChaCha8Rng,
    gap_quality: u8,
    /// The last estimate of a row seen, repeated in a gap: offset m, angle rad.
    last_seen: Option<(f64, f64)>,
}

impl CameraComputer {
    /// `params` must be sanitized.
    pub(crate) fn new(params: &SimParams, pipe: PipeEnd) -> CameraComputer {
        let seed = params.seed;
        let mut bias_rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(super::SEED_CAMERA_BIAS));
        let bias_sd_m = match params.field {
            FieldKind::Clean => 0.0,
            FieldKind::Realistic => params.tier.camera_bias_sd_m,
        };
        let unit: f64 = bias_rng.sample(StandardNormal);
        let bias = GaussMarkov::new(bias_sd_m, params.tier.camera_bias_length_m, unit);
        CameraComputer {
            pipe,
            lookahead_m: params.camera_lookahead_m,
            period_s: 1.0 / params.camera_rate_hz,
            latency_s: params.camera_latency_s,
            jitter_s: params.camera_jitter_s,
            noise_offset_m: params.camera_noise_offset_m,
            noise_angle_rad: params.camera_noise_angle_deg.to_radians(),
            drop_probability: params.camera_drop,
            corrupt_probability: params.camera_corrupt,
            reboot_s: params.camera_reboot_s,
            streaming: false,
            next_capture_t_s: 0.0,
            seq: 0,
            silent_until_t_s: f64::NEG_INFINITY,
            booting_until_t_s: f64::NEG_INFINITY,
            pong_due: false,
            pending: [Pending::default(); RING],
            head: 0,
            waiting: 0,
            hint: 0,
            noise_rng: ChaCha8Rng::seed_from_u64(seed.wrapping_add(super::SEED_CAMERA_NOISE)),
            timing_rng: ChaCha8Rng::seed_from_u64(seed.wrapping_add(super::SEED_CAMERA_TIMING)),
            corrupt_rng: ChaCha8Rng::seed_from_u64(seed.wrapping_add(super::SEED_CAMERA_CORRUPT)),
            counters: CameraCounters::default(),
            bias,
            bias_at_m: 0.0,
            bias_rng,
            gap_quality: params.tier.gap_quality,
            last_seen: None,
        }
    }

    pub fn is_streaming(&self) -> bool {
        self.streaming
    }

    pub fn counters(&self) -> CameraCounters {
        self.counters
    }

    /// One integration step at time t, the robot having driven `distance_m`: hear
    /// commands, capture if due, send what is due.
    pub(crate) fn tick(
        &mut self,
        t_s: f64,
        pose: &Pose,
        field: &Field,
        tier: &FieldTier,
        distance_m: f64,
    ) {
        self.read_commands(t_s);
        if self.streaming && t_s >= self.next_capture_t_s {
            self.capture(t_s, pose, field, tier, distance_m);
            self.next_capture_t_s += self.period_s;
            if self.next_capture_t_s <= t_s {
                // Fell behind (a long step): skip, never burst.
                self.next_capture_t_s = t_s + self.period_s;
            }
        }
        self.send_due(t_s);
        if self.pong_due {
            self.pong_due = false;
            let seq = self.take_seq();
            self.counters.pongs += 1;
            self.write_frame(t_s, encode_pong(seq));
        }
    }

    /// The link falls silent for `duration_s` from now.
    pub(crate) fn silence(&mut self, t_s: f64, duration_s: f64) {
        if duration_s.is_finite() {
            self.silent_until_t_s = self.silent_until_t_s.max(t_s + duration_s);
        }
    }

    /// Reboot now: forget streaming, waiting frames and the sequence number.
    pub(crate) fn reboot(&mut self, t_s: f64) {
        self.streaming = false;
        self.waiting = 0;
        self.seq = 0;
        self.pong_due = false;
        self.last_seen = None;
        self.booting_until_t_s = t_s + self.reboot_s;
    }

    fn read_commands(&mut self, t_s: f64) {
        let mut buf = [0u8; 32];
        loop {
            let n = self.pipe.try_read(&mut buf);
            if n == 0 {
                return;
            }
            if t_s < self.booting_until_t_s {
                continue; // still booting: the bytes fall on deaf ears
            }
            for &byte in &buf[..n] {
                match byte {
                    CMD_START if !self.streaming => {
                        self.streaming = true;
                        self.next_capture_t_s = t_s;
                    }
                    CMD_STOP => self.streaming = false,
                    CMD_PING => self.pong_due = true,
                    _ => {} // anything else is ignored, as the protocol says
                }
            }
        }
    }

    fn capture(&mut self, t_s: f64, pose: &Pose, field: &Field, tier: &FieldTier, distance_m: f64) {
        self.counters.captures += 1;
        // Draw every number every time, so that what the camera sees does not shift the
        // noise of later frames.
        let offset_noise: f64 = self.noise_rng.sample(StandardNormal);
        let angle_noise: f64 = self.noise_rng.sample(StandardNormal);
        let latency_s =
            self.latency_s + self.jitter_s * (2.0 * self.timing_rng.random::<f64>() - 1.0);
        let dropped = self.timing_rng.random::<f64>() < self.drop_probability;
        let unit: f64 = self.bias_rng.sample(StandardNormal);
        let bias_m = self.bias.step(distance_m - self.bias_at_m, unit);
        self.bias_at_m = self.bias_at_m.max(distance_m);

        let (offset_m, angle_rad, quality) =
            match row_at_lookahead(field, pose, self.lookahead_m, &mut self.hint) {
                Some(view) if view.s_m <= field.planted_length_m() => {
                    let at = tier.row_at(view.s_m);
                    match self.last_seen {
                        Some((offset_m, angle_rad)) if at.gap => {
                            (offset_m, angle_rad, self.gap_quality)
                        }
                        None if at.gap => (0.0, 0.0, 0), // no row seen yet
                        _ => {
                            let offset_m = view.offset_m
                                + offset_noise * self.noise_offset_m
                                + bias_m
                                + at.weed_offset_m;
                            let angle_rad = view.angle_rad + angle_noise * self.noise_angle_rad;
                            self.last_seen = Some((offset_m, angle_rad));
                            (offset_m, angle_rad, QUALITY_SEEN)
                        }
                    }
                }
                _ => (0.0, 0.0, 0), // past the row's end: no row in the image
            };
        if self.waiting == RING {
            self.counters.ring_full += 1;
            return;
        }
        // Frames leave in capture order, as from one serial port.
        let newest_send_t_s = match self.waiting {
            0 => f64::NEG_INFINITY,
            n => self.pending[(self.head + n - 1) % RING].send_t_s,
        };
        self.pending[(self.head + self.waiting) % RING] = Pending {
            send_t_s: (t_s + latency_s.max(0.0)).max(newest_send_t_s),
            angle_rad,
            offset_m,
            quality,
            dropped,
        };
        self.waiting += 1;
    }

    fn send_due(&mut self, t_s: f64) {
        while self.waiting > 0 && self.pending[self.head].send_t_s <= t_s {
            let frame = self.pending[self.head];
            self.head = (self.head + 1) % RING;
            self.waiting -= 1;
            let seq = self.take_seq();
            if frame.dropped {
                self.counters.frames_dropped += 1;
                continue;
            }
            let bytes = encode_row(&RowEstimate {
                seq,
                angle_rad: frame.angle_rad,
                offset_m: frame.offset_m,
                quality: frame.quality,
            });
            self.write_frame(t_s, bytes);
        }
    }

    fn take_seq(&mut self) -> u8 {
        let seq = self.seq;
        self.seq = self.seq.wrapping_add(1);
        seq
    }

    fn write_frame(&mut self, t_s: f64, mut bytes: [u8; crate::camproto::FRAME_LEN]) {
        if t_s < self.silent_until_t_s || t_s < self.booting_until_t_s {
            self.counters.frames_silenced += 1;
            return;
        }
        if self.corrupt_probability > 0.0 {
            for byte in &mut bytes {
                if self.corrupt_rng.random::<f64>() < self.corrupt_probability {
                    *byte ^= self.corrupt_rng.random_range(1..=255u8);
                }
            }
        }
        self.pipe.send(&bytes);
        self.counters.frames_written += 1;
    }
}

#[cfg(test)]
#[path = "camera_tests.rs"]
mod tests;

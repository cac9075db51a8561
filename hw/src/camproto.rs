//! The camera link's bytes (docs/function_spec.md, section 7): frames, CRC, and a streaming
//! decoder that resynchronises on garbage.
//!
//! It lives in the hardware crate because both sides speak it: the program decodes
//! what the camera computer sends, and the simulated camera computer encodes it.
//! Everything that arrives is untrusted: the decoder never panics, never allocates,
//! and keeps at most one frame's bytes whatever arrives.

/// First byte of every frame.
pub const SYNC: u8 = 0xA5;
/// Every frame is this long, CRC included.
pub const FRAME_LEN: usize = 10;
/// Frame kind: a row estimate.
pub(crate) const KIND_ROW: u8 = 0x01;
/// Frame kind: the answer to PING.
pub(crate) const KIND_PONG: u8 = 0x02;
/// Command: begin sending ROW frames.
pub const CMD_START: u8 = 0x10;
/// Command: stop sending ROW frames.
pub const CMD_STOP: u8 = 0x11;
/// Command: answer with one PONG frame.
pub const CMD_PING: u8 = 0x12;

/// Units on the wire: 0.1 mrad for the angle, 0.1 mm for the offset (dividing by
/// 1e4 rather than multiplying by 1e-4 gives the exact decimal: 300 -> 0.03).
const ANGLE_UNITS_PER_RAD: f64 = 1e4;
const OFFSET_UNITS_PER_M: f64 = 1e4;
/// Estimates beyond these are not physical for this camera (function_spec.md, section 7).
pub const MAX_ANGLE_RAD: f64 = 0.8;
pub const MAX_OFFSET_M: f64 = 0.5;

/// CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no final xor.
pub(crate) fn crc16(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &byte in bytes {
        crc ^= (byte as u16) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// One row estimate as the camera computer sent it, in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RowEstimate {
    pub seq: u8,
    /// Heading of the row relative to the robot, rad (positive: row turns left).
    pub angle_rad: f64,
    /// Row centre line relative to the robot at the camera's reference point, m
    /// (positive: row lies to the left).
    pub offset_m: f64,
    /// Camera's confidence, 0..=100; 0 = no row seen.
    pub quality: u8,
}

/// A frame that passed its CRC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Frame {
    Row(RowEstimate),
    Pong { seq: u8 },
}

fn encode(kind: u8, seq: u8, angle_units: i16, offset_units: i16, quality: u8) -> [u8; FRAME_LEN] {
    let mut f = [0u8; FRAME_LEN];
    f[0] = SYNC;
    f[1] = kind;
    f[2] = seq;
    f[3..5].copy_from_slice(&angle_units.to_le_bytes());
    f[5..7].copy_from_slice(&offset_units.to_le_bytes());
    f[7] = quality;
    let crc = crc16(&f[..8]);
    f[8..10].copy_from_slice(&crc.to_le_bytes());
    f
}

fn to_units(value: f64, units_per: f64) -> i16 {
    // `as` saturates at the i16 range, which is what a camera computer's encoder does.
    (value * units_per).round() as i16
}

/// Encode a ROW frame.
pub fn encode_row(est: &RowEstimate) -> [u8; FRAME_LEN] {
    encode(
        KIND_ROW,
        est.seq,
        to_units(est.angle_rad, ANGLE_UNITS_PER_RAD),
        to_units(est.offset_m, OFFSET_UNITS_PER_M),
        est.quality,
    )
}

/// Encode a PONG frame (angle, offset and quality are zero).
pub fn encode_pong(seq: u8) -> [u8; FRAME_LEN] {
    encode(KIND_PONG, seq, 0, 0, 0)
}

/// What the decoder has seen, for the link's status and the run report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct LinkCounters {
    /// Frames that passed the CRC and carried a usable row estimate or a pong.
    pub frames_ok: u64,
    /// Ten bytes that began with 0xA5 but failed the CRC.
    pub crc_errors: u64,
    /// Times the decoder had to hunt for the next 0xA5 after a bad or useless frame.
    pub resyncs: u64,
    /// Gaps in the sequence numbers: frames lost on the way.
    pub seq_gaps: u64,
    /// Bytes thrown away while hunting for a frame start.
    pub bytes_skipped: u64,
    /// PONG frames received.
    pub pongs: u64,
    /// Frames with a good CRC but physically impossible values (a bad estimate).
    pub bad_values: u64,
    /// Frames with a good CRC but a kind this program does not know (skipped).
    pub unknown_kinds: u64,
    /// Frames whose sequence number repeats the previous one: the same frame twice on
    /// a noisy line, ignored (it is no news, so it must not look like a fresh one).
    pub duplicates: u64,
}

/// What ten bytes with a good CRC turned out to be.
enum Verdict {
    /// A new frame to pass on.
    Use(Frame),
    /// A frame already seen: consumed, not passed on.
    Repeat,
    /// No use (unknown kind, impossible values): perhaps a false sync in noise.
    Useless,
}

/// Streaming decoder: feed it bytes one at a time as they arrive.
#[derive(Debug, Clone, Default)]
pub struct Decoder {
    buf: [u8; FRAME_LEN],
    len: usize,
    last_seq: Option<u8>,
    pub counters: LinkCounters,
}

impl Decoder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Feed one byte; returns a frame when this byte completed a valid one.
    pub fn push(&mut self, byte: u8) -> Option<Frame> {
        if self.len == 0 && byte != SYNC {
            self.counters.bytes_skipped += 1;
            return None;
        }
        self.buf[self.len] = byte;
        self.len += 1;
        if self.len < FRAME_LEN {
            return None;
        }
        let crc = u16::from_le_bytes([self.buf[8], self.buf[9]]);
        if crc16(&self.buf[..8]) != crc {
            self.counters.crc_errors += 1;
            self.resync();
            return None;
        }
        match self.interpret() {
            Verdict::Use(frame) => {
                self.len = 0;
                Some(frame)
            }
            Verdict::Repeat => {
                self.len = 0;
                None
            }
            Verdict::Useless => {
                // A good CRC on a frame that is no use: a ROW with impossible values
                // (its seq was counted as sent) or, rarely, a false sync in noise.
                // Look inside it too, so that a real frame is never swallowed.
                self.resync();
                None
            }
        }
    }

    /// The 0xA5 we started from was not a frame start (or the frame was damaged):
    /// drop it and start again from the next 0xA5 among the bytes already held.
    fn resync(&mut self) {
        self.counters.resyncs += 1;
        let next_sync = self.buf[1..].iter().position(|&b| b == SYNC).map(|i| i + 1);
        let start = next_sync.unwrap_or(FRAME_LEN);
        self.counters.bytes_skipped += start as u64;
        self.buf.copy_within(start.., 0);
        self.len = FRAME_LEN - start;
    }

    /// Count a sequence gap against the last frame the camera computer sent.
    fn follow_seq(&mut self, seq: u8) {
        if let Some(last) = self.last_seq
            && seq != last.wrapping_add(1)
        {
            self.counters.seq_gaps += 1;
        }
        self.last_seq = Some(seq);
    }

    fn interpret(&mut self) -> Verdict {
        let b = self.buf;
        let (kind, seq) = (b[1], b[2]);
        if kind != KIND_ROW && kind != KIND_PONG {
            // The camera computer sends only these two kinds: this is noise, and its
            // sequence number means nothing.
            self.counters.unknown_kinds += 1;
            return Verdict::Useless;
        }
        // The seq counts up by one per frame sent (wrapping 255 -> 0): a frame with the
        // previous one's seq is that frame again, duplicated on the way.
        if self.last_seq == Some(seq) {
            self.counters.duplicates += 1;
            return Verdict::Repeat;
        }
        // A frame the camera computer sent, usable or not: the next one follows it.
        self.follow_seq(seq);
        if kind == KIND_PONG {
            self.counters.frames_ok += 1;
            self.counters.pongs += 1;
            return Verdict::Use(Frame::Pong { seq });
        }
        let est = RowEstimate {
            seq,
            angle_rad: i16::from_le_bytes([b[3], b[4]]) as f64 / ANGLE_UNITS_PER_RAD,
            offset_m: i16::from_le_bytes([b[5], b[6]]) as f64 / OFFSET_UNITS_PER_M,
            quality: b[7],
        };
        if est.angle_rad.abs() > MAX_ANGLE_RAD
            || est.offset_m.abs() > MAX_OFFSET_M
            || est.quality > 100
        {
            self.counters.bad_values += 1;
            return Verdict::Useless;
        }
        self.counters.frames_ok += 1;
        Verdict::Use(Frame::Row(est))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_check_value() {
        assert_eq!(crc16(b"123456789"), 0x29B1);
    }

    #[test]
    fn worked_example_encodes_and_decodes() {
        let est = RowEstimate {
            seq: 7,
            angle_rad: 0.0125,
            offset_m: -0.03,
            quality: 87,
        };
        let bytes = encode_row(&est);
        assert_eq!(
            bytes,
            [0xA5, 0x01, 0x07, 0x7D, 0x00, 0xD4, 0xFE, 0x57, 0x3D, 0x10]
        );
        let mut dec = Decoder::new();
        let frames: Vec<_> = bytes.iter().filter_map(|&b| dec.push(b)).collect();
        assert_eq!(frames, vec![Frame::Row(est)]);
    }

    #[test]
    fn resyncs_from_the_byte_after_a_false_sync() {
        let good = encode_row(&RowEstimate {
            seq: 1,
            angle_rad: 0.01,
            offset_m: 0.02,
            quality: 90,
        });
        // A stray 0xA5 followed by three bytes, then a good frame: the good frame starts
        // inside the ten bytes taken for the false one, and must still be found.
        let mut stream = vec![0xA5, 0x00, 0x11, 0x22];
        stream.extend_from_slice(&good);
        let mut dec = Decoder::new();
        let frames: Vec<_> = stream.iter().filter_map(|&b| dec.push(b)).collect();
        assert_eq!(frames.len(), 1);
        assert_eq!(dec.counters.crc_errors, 1);
        assert_eq!(dec.counters.resyncs, 1);
        assert_eq!(dec.counters.bytes_skipped, 4);
    }

    #[test]
    fn a_false_frame_with_a_good_crc_does_not_swallow_a_real_one() {
        // Found by the property test: noise "A5 22 99 85" and the start of a real frame
        // form ten bytes whose CRC happens to pass, with an unknown kind.
        let stream = [
            0xA5, 0x22, 0x99, 0x85, 0xA5, 0x01, 0xA3, 0x88, 0x13, 0x4F, 0x03, 0x00, 0x89, 0xAC,
        ];
        let mut dec = Decoder::new();
        let frames: Vec<_> = stream.iter().filter_map(|&b| dec.push(b)).collect();
        assert_eq!(dec.counters.unknown_kinds, 1);
        let real = RowEstimate {
            seq: 0xA3,
            angle_rad: 0.5,
            offset_m: 0.0847,
            quality: 0,
        };
        assert_eq!(frames, vec![Frame::Row(real)]);
    }

    #[test]
    fn counts_gaps_and_rejects_impossible_values() {
        let mut dec = Decoder::new();
        let mut feed =
            |est: RowEstimate| encode_row(&est).iter().filter_map(|&b| dec.push(b)).count();
        let ok = RowEstimate {
            seq: 1,
            angle_rad: 0.0,
            offset_m: 0.0,
            quality: 50,
        };
        assert_eq!(feed(ok), 1);
        assert_eq!(feed(RowEstimate { seq: 3, ..ok }), 1);
        assert_eq!(
            feed(RowEstimate {
                seq: 4,
                offset_m: 0.9,
                ..ok
            }),
            0
        );
        assert_eq!(
            feed(RowEstimate {
                seq: 5,
                quality: 101,
                ..ok
            }),
            0
        );
        assert_eq!(dec.counters.seq_gaps, 1);
        assert_eq!(dec.counters.bad_values, 2);
        assert_eq!(dec.counters.frames_ok, 2);
    }

    fn row(seq: u8) -> RowEstimate {
        RowEstimate {
            seq,
            angle_rad: 0.01,
            offset_m: -0.02,
            quality: 80,
        }
    }

    /// Decode `frames` one after the other; returns the frames passed on.
    fn decode(dec: &mut Decoder, frames: &[RowEstimate]) -> Vec<Frame> {
        let bytes: Vec<u8> = frames.iter().flat_map(encode_row).collect();
        bytes.iter().filter_map(|&b| dec.push(b)).collect()
    }

    #[test]
    fn a_frame_with_impossible_values_still_counts_in_the_sequence() {
        let mut dec = Decoder::new();
        let bad = RowEstimate {
            offset_m: 0.9,
            ..row(8)
        };
        let passed = decode(&mut dec, &[row(7), bad, row(9)]);
        assert_eq!(passed, vec![Frame::Row(row(7)), Frame::Row(row(9))]);
        assert_eq!(dec.counters.bad_values, 1);
        assert_eq!(dec.counters.seq_gaps, 0, "{:?}", dec.counters);
    }

    #[test]
    fn a_duplicated_frame_is_counted_and_not_passed_on() {
        let mut dec = Decoder::new();
        let passed = decode(&mut dec, &[row(255), row(255), row(0)]);
        assert_eq!(passed, vec![Frame::Row(row(255)), Frame::Row(row(0))]);
        assert_eq!(dec.counters.duplicates, 1);
        assert_eq!(dec.counters.seq_gaps, 0, "{:?}", dec.counters);
        assert_eq!(dec.counters.frames_ok, 2);
        assert_eq!(dec.counters.crc_errors + dec.counters.resyncs, 0);
        // A PONG sent twice is a duplicate too.
        let pongs: Vec<u8> = [encode_pong(1), encode_pong(1)].concat();
        let passed: Vec<_> = pongs.iter().filter_map(|&b| dec.push(b)).collect();
        assert_eq!(passed, vec![Frame::Pong { seq: 1 }]);
        assert_eq!(dec.counters.duplicates, 2);
    }

    #[test]
    fn lost_frames_still_count_as_a_gap_also_across_the_wrap() {
        let mut dec = Decoder::new();
        let passed = decode(&mut dec, &[row(254), row(1), row(2), row(4)]);
        assert_eq!(passed.len(), 4);
        assert_eq!(dec.counters.seq_gaps, 2);
        assert_eq!(dec.counters.duplicates, 0);
    }
}

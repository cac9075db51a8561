//! Property tests of the camera-link decoder: whatever arrives, it never panics and
//! keeps its memory bounded, every valid frame between garbage is found, and lost,
//! duplicated and bad frames are each counted as what they are.

use mechweed_hw::camproto::{Decoder, Frame, RowEstimate, SYNC, encode_row};
use proptest::prelude::*;

/// What happened to one frame the camera computer sent.
#[derive(Debug, Clone, Copy)]
enum Fate {
    Lost,
    /// Arrived `copies` times (1, or 2: duplicated on the line); `bad`: with an impossible
    /// offset (a bad estimate, good CRC).
    Arrived {
        copies: usize,
        bad: bool,
    },
}

fn fate() -> impl Strategy<Value = Fate> {
    prop_oneof![
        6 => Just(Fate::Arrived { copies: 1, bad: false }),
        1 => Just(Fate::Lost),
        1 => Just(Fate::Arrived { copies: 2, bad: false }),
        1 => Just(Fate::Arrived { copies: 1, bad: true }),
        1 => Just(Fate::Arrived { copies: 2, bad: true }),
    ]
}

fn estimate() -> impl Strategy<Value = RowEstimate> {
    (any::<u8>(), -8000i16..=8000, -5000i16..=5000, 0u8..=100).prop_map(|(seq, a, o, q)| {
        RowEstimate {
            seq,
            angle_rad: a as f64 / 1e4,
            offset_m: o as f64 / 1e4,
            quality: q,
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..4000)) {
        let mut dec = Decoder::new();
        for b in bytes {
            let _ = dec.push(b);
        }
        let c = dec.counters;
        prop_assert!(c.frames_ok + c.crc_errors <= 4000);
    }

    #[test]
    fn damaged_frames_never_panic(
        frames in proptest::collection::vec(estimate(), 1..30),
        flips in proptest::collection::vec((any::<usize>(), 1u8..=255), 0..40),
    ) {
        let mut stream: Vec<u8> = frames.iter().flat_map(encode_row).collect();
        for (at, mask) in flips {
            let i = at % stream.len();
            stream[i] ^= mask;
        }
        let mut dec = Decoder::new();
        let found = stream.iter().filter_map(|&b| dec.push(b)).count();
        prop_assert!(found <= frames.len() + 1);
    }

    #[test]
    fn lost_duplicated_and_bad_frames_are_counted_as_such(
        first_seq in any::<u8>(),
        fates in proptest::collection::vec(fate(), 1..200),
    ) {
        let mut stream = Vec::new();
        for (k, fate) in fates.iter().enumerate() {
            if let Fate::Arrived { copies, bad } = *fate {
                let est = RowEstimate {
                    // Counts up by one per frame sent, wrapping 255 -> 0.
                    seq: first_seq.wrapping_add(k as u8),
                    angle_rad: 0.01,
                    offset_m: if bad { 0.9 } else { -0.02 },
                    quality: 80,
                };
                for _ in 0..copies {
                    stream.extend_from_slice(&encode_row(&est));
                }
            }
        }
        let mut dec = Decoder::new();
        let passed = stream.iter().filter_map(|&b| dec.push(b)).count() as u64;
        let arrived: Vec<(usize, bool)> = fates
            .iter()
            .filter_map(|f| match *f {
                Fate::Arrived { copies, bad } => Some((copies, bad)),
                Fate::Lost => None,
            })
            .collect();
        let good = arrived.iter().filter(|(_, bad)| !bad).count() as u64;
        let bad = arrived.len() as u64 - good;
        let copies = arrived.iter().map(|(c, _)| *c as u64 - 1).sum::<u64>();
        // A gap: a frame that arrived after one or more lost ones, with one before them.
        let first = fates.iter().position(|f| !matches!(f, Fate::Lost));
        let gaps = first.map_or(0, |first| {
            fates[first..]
                .windows(2)
                .filter(|w| matches!(w[0], Fate::Lost) && !matches!(w[1], Fate::Lost))
                .count() as u64
        });
        let c = dec.counters;
        prop_assert_eq!(passed, good);
        prop_assert_eq!(c.frames_ok, good);
        prop_assert_eq!(c.bad_values, bad);
        prop_assert_eq!(c.duplicates, copies);
        prop_assert_eq!(c.seq_gaps, gaps, "{:?}", c);
    }

    #[test]
    fn every_valid_frame_surrounded_by_garbage_is_recovered(
        first_seq in any::<u8>(),
        frames in proptest::collection::vec(estimate(), 1..20),
        garbage in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..25), 20),
    ) {
        // Numbered as the camera computer numbers them: a repeated number is a duplicate.
        let frames: Vec<RowEstimate> = frames
            .iter()
            .enumerate()
            .map(|(k, est)| RowEstimate { seq: first_seq.wrapping_add(k as u8), ..*est })
            .collect();
        let mut stream = Vec::new();
        for (k, est) in frames.iter().enumerate() {
            stream.extend_from_slice(&garbage[k]);
            stream.extend_from_slice(&encode_row(est));
        }
        let mut dec = Decoder::new();
        let rows: Vec<RowEstimate> = stream
            .iter()
            .filter_map(|&b| match dec.push(b) {
                Some(Frame::Row(e)) => Some(e),
                _ => None,
            })
            .collect();
        // Garbage can, rarely, contain a valid frame of its own (2^-16 per try after a
        // 0xA5): every real frame must be there, in order.
        let mut it = rows.iter();
        for est in &frames {
            prop_assert!(it.any(|r| r == est), "lost {est:?} in {stream:02X?}");
        }
    }
}

#[test]
fn a_flood_of_sync_bytes_stays_bounded() {
    let mut dec = Decoder::new();
    for _ in 0..1_000_000 {
        assert_eq!(dec.push(SYNC), None);
    }
    assert!(dec.counters.crc_errors > 0);
}

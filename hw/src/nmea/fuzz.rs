//! One fuzz case: arbitrary bytes through the decoder and the fix assembler, checked
//! against every promise they make. For the program's cargo-fuzz target and for the
//! property tests, which share it so that both check the same things.
//!
//! `check_stream` returns what it found as a value; `fuzz_one` panics with it, which
//! is how a fuzzer learns of a finding. That is the only panic in this module, and it
//! fires only when the decoder breaks a promise, never because of what the bytes are.

use super::decode::{NmeaCounters, NmeaDecoder};
use super::fix::{Epoch, FixAssembler};
use super::sentence::{LatLon, Sentence};

/// UTC seconds of day run up to 86 400 inclusive of a leap second.
const MAX_UTC_S: f64 = 86_401.0;

/// A broken promise, with enough to reproduce it from the logged input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FuzzFinding {
    #[error("{lines} lines counted (+{open} open) but {dollars} `$` in the input")]
    Accounting { lines: u64, open: u64, dollars: u64 },
    #[error("decoding in chunks of {chunk} bytes gave other results than whole")]
    Chunking { chunk: usize },
    #[error("{passed} sentences passed on but {counted} counted as good")]
    GoodCount { passed: usize, counted: u64 },
    #[error("a sentence with an impossible {field} was passed on: {sentence:?}")]
    Impossible {
        field: &'static str,
        sentence: Box<Sentence>,
    },
    #[error("the assembler made a fix without a position quality: {epoch:?}")]
    FixWithoutPosition { epoch: Box<Epoch> },
    #[error("{fixes} fixes from {ggas} GGA sentences")]
    TooManyFixes { fixes: usize, ggas: u64 },
}

/// Decode `bytes` in chunks of `chunk` bytes (0: all at once).
fn decode(bytes: &[u8], chunk: usize) -> (Vec<Sentence>, NmeaCounters, bool) {
    let mut decoder = NmeaDecoder::new();
    let mut sentences = Vec::new();
    for piece in bytes.chunks(if chunk == 0 {
        bytes.len().max(1)
    } else {
        chunk
    }) {
        decoder.push(piece, |s| sentences.push(s));
    }
    (sentences, decoder.counters(), decoder.in_line())
}

fn in_range(value: Option<f64>, lo: f64, hi: f64) -> bool {
    value.is_none_or(|v| v.is_finite() && (lo..=hi).contains(&v))
}

fn position_ok(position: Option<LatLon>) -> bool {
    position.is_none_or(|p| {
        in_range(Some(p.lat_deg), -90.0, 90.0) && in_range(Some(p.lon_deg), -180.0, 180.0)
    })
}

/// The first impossible field of a sentence the decoder passed on, if any.
pub fn impossible_field(sentence: &Sentence) -> Option<&'static str> {
    let time_ok = in_range(sentence.utc_s_of_day(), 0.0, MAX_UTC_S);
    let checks: [(bool, &'static str); 4] = match sentence {
        Sentence::Gga(g) => [
            (
                position_ok(g.position) && (g.position.is_some() || !g.quality.carries_position()),
                "position",
            ),
            (in_range(g.altitude_m, -1e5, 1e5), "altitude"),
            (
                in_range(g.hdop.map(f64::from), 0.0, 100.0) && g.satellites.is_none_or(|n| n <= 99),
                "hdop or satellites",
            ),
            (
                in_range(g.correction_age_s.map(f64::from), 0.0, 86_400.0),
                "correction age",
            ),
        ],
        Sentence::Rmc(r) => [
            (
                position_ok(r.position) && (r.position.is_some() || !r.valid),
                "position",
            ),
            (in_range(r.speed_mps, 0.0, 1e3), "speed"),
            (in_range(r.course_deg, 0.0, 360.0), "course"),
            (true, ""),
        ],
        Sentence::Vtg(v) => [
            (in_range(v.speed_mps, 0.0, 1e3), "speed"),
            (in_range(v.course_deg, 0.0, 360.0), "course"),
            (true, ""),
            (true, ""),
        ],
        Sentence::Gst(s) => [
            (in_range(s.sd_lat_m, 0.0, 1e6), "latitude s.d."),
            (in_range(s.sd_lon_m, 0.0, 1e6), "longitude s.d."),
            (in_range(s.sd_alt_m, 0.0, 1e6), "altitude s.d."),
            (true, ""),
        ],
    };
    if !time_ok {
        return Some("time");
    }
    checks.iter().find(|(ok, _)| !ok).map(|&(_, field)| field)
}

/// Run one input through everything and check every promise.
pub fn check_stream(bytes: &[u8]) -> Result<(), FuzzFinding> {
    let whole = decode(bytes, 0);
    let (sentences, counters, open) = &whole;
    let dollars = bytes.iter().filter(|&&b| b == b'$').count() as u64;
    if counters.lines() + u64::from(*open) != dollars {
        let (lines, open) = (counters.lines(), u64::from(*open));
        return Err(FuzzFinding::Accounting {
            lines,
            open,
            dollars,
        });
    }
    if sentences.len() as u64 != counters.good() {
        return Err(FuzzFinding::GoodCount {
            passed: sentences.len(),
            counted: counters.good(),
        });
    }
    for &sentence in sentences {
        if let Some(field) = impossible_field(&sentence) {
            return Err(FuzzFinding::Impossible {
                field,
                sentence: Box::new(sentence),
            });
        }
    }
    // After the range check: the comparison needs numbers that equal themselves.
    // A split point from the input itself, so the fuzzer can steer it.
    let split = usize::from(bytes.first().copied().unwrap_or(0)) % 7 + 2;
    for chunk in [1, split] {
        if decode(bytes, chunk) != whole {
            return Err(FuzzFinding::Chunking { chunk });
        }
    }
    let mut assembler = FixAssembler::new();
    let mut epochs = Vec::new();
    for &sentence in sentences {
        assembler.push(sentence, |e| epochs.push(e));
    }
    assembler.finish(|e| epochs.push(e));
    if let Some(&epoch) = epochs
        .iter()
        .find(|e| matches!(e, Epoch::Fix(f) if !f.quality.carries_position()))
    {
        return Err(FuzzFinding::FixWithoutPosition {
            epoch: Box::new(epoch),
        });
    }
    let fixes = epochs.iter().filter(|e| matches!(e, Epoch::Fix(_))).count();
    if fixes as u64 > counters.gga {
        return Err(FuzzFinding::TooManyFixes {
            fixes,
            ggas: counters.gga,
        });
    }
    Ok(())
}

/// For a cargo-fuzz target: `fuzz_target!(|data: &[u8]| mechweed_hw::nmea::fuzz::fuzz_one(data));`
#[allow(clippy::panic)]
pub fn fuzz_one(bytes: &[u8]) {
    if let Err(finding) = check_stream(bytes) {
        panic!("{finding}");
    }
}

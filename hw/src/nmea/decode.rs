//! The GNSS receiver's byte stream to sentences: a streaming decoder that splits NMEA
//! 0183 lines, checks them, parses them with the `nmea` crate and passes on our own
//! small `Copy` sentences, counting every line it skips and why.
//!
//! Everything that arrives is untrusted: the decoder never panics, keeps at most one
//! line's bytes in a fixed buffer, and allocates nothing. A `$` always starts a new
//! line, because NMEA reserves it for that: a line cut short by a lost byte never
//! swallows the good line after it.

use ::nmea::{Error as NmeaError, ParseResult, SENTENCE_MAX_LEN, SentenceType};

use super::convert;
use super::error::{LineError, LineFault, SentenceKind};
use super::sentence::Sentence;

/// The longest line taken, `$` to checksum: NMEA's 82 characters allow 79 here, but
/// real receivers exceed that (a Trimble BX-960 GGA has 91), so the `nmea` crate's
/// own limit, which it would enforce anyway.
pub(crate) const MAX_LINE_LEN: usize = SENTENCE_MAX_LEN;
/// Room for the `\r` before the `\n`.
const BUF_LEN: usize = MAX_LINE_LEN + 1;

/// What the decoder has seen. Every line (a `$` up to the next `\n` or `$`) lands in
/// exactly one of the fields from `gga` to `non_ascii`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct NmeaCounters {
    pub gga: u64,
    pub rmc: u64,
    pub vtg: u64,
    pub gst: u64,
    /// Lines whose checksum was wrong: noise on the line.
    pub checksum_errors: u64,
    /// Good lines of kinds this program does not use (GSA, GSV, proprietary ...).
    pub unknown_kinds: u64,
    /// Cut short, or with a needed field empty, unreadable or out of range.
    pub malformed: u64,
    /// Longer than `MAX_LINE_LEN`: skipped to their end.
    pub overlong: u64,
    /// Lines holding a byte above 0x7F.
    pub non_ascii: u64,
    /// Bytes outside any line (before the first `$`, after a line's end), not counting
    /// `\r` and `\n`.
    pub stray_bytes: u64,
}

impl NmeaCounters {
    /// Sentences passed on.
    pub fn good(&self) -> u64 {
        self.gga + self.rmc + self.vtg + self.gst
    }

    /// Lines skipped, for any reason.
    pub fn skipped(&self) -> u64 {
        self.checksum_errors + self.unknown_kinds + self.malformed + self.overlong + self.non_ascii
    }

    /// Every line ended so far.
    pub fn lines(&self) -> u64 {
        self.good() + self.skipped()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Framing {
    /// Waiting for a `$`.
    Hunting,
    /// Inside a line: its bytes are in the buffer.
    InLine,
    /// Inside a line already counted as overlong: skipping to its end.
    Skipping,
}

/// Streaming NMEA decoder: feed it bytes as they arrive, in chunks of any size.
#[derive(Debug, Clone)]
pub struct NmeaDecoder {
    buf: [u8; BUF_LEN],
    len: usize,
    framing: Framing,
    counters: NmeaCounters,
    last_error: Option<LineError>,
}

impl Default for NmeaDecoder {
    fn default() -> Self {
        NmeaDecoder {
            buf: [0; BUF_LEN],
            len: 0,
            framing: Framing::Hunting,
            counters: NmeaCounters::default(),
            last_error: None,
        }
    }
}

impl NmeaDecoder {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn counters(&self) -> NmeaCounters {
        self.counters
    }

    /// Why the most recent skipped line was skipped.
    pub fn last_error(&self) -> Option<LineError> {
        self.last_error
    }

    /// True while a line has begun and not yet ended (it is not counted yet).
    pub(crate) fn in_line(&self) -> bool {
        self.framing == Framing::InLine
    }

    /// Feed bytes; `out` gets each good sentence as its line ends.
    pub fn push(&mut self, bytes: &[u8], mut out: impl FnMut(Sentence)) {
        for &byte in bytes {
            self.push_byte(byte, &mut out);
        }
    }

    fn push_byte(&mut self, byte: u8, out: &mut impl FnMut(Sentence)) {
        match (byte, self.framing) {
            (b'$', framing) => {
                if framing == Framing::InLine {
                    // The line had no end: decode what it has (it may lack only its
                    // `\r\n`); if it was cut short, framing says so.
                    self.end_line(out);
                }
                self.buf[0] = b'$';
                self.len = 1;
                self.framing = Framing::InLine;
            }
            (b'\n', Framing::InLine) => {
                self.end_line(out);
                self.framing = Framing::Hunting;
            }
            (b'\n', _) => self.framing = Framing::Hunting,
            (b'\r', Framing::Hunting) => {}
            (_, Framing::Hunting) => self.counters.stray_bytes += 1,
            (_, Framing::Skipping) => {}
            (_, Framing::InLine) => {
                if let Some(slot) = self.buf.get_mut(self.len) {
                    *slot = byte;
                    self.len += 1;
                } else {
                    let kind = kind_of(&self.buf);
                    self.skip(LineFault::Overlong, kind);
                    self.framing = Framing::Skipping;
                }
            }
        }
    }

    fn skip(&mut self, fault: LineFault, kind: Option<SentenceKind>) {
        let counter = match fault {
            LineFault::Checksum => &mut self.counters.checksum_errors,
            LineFault::UnknownKind => &mut self.counters.unknown_kinds,
            LineFault::Truncated | LineFault::Malformed(_) => &mut self.counters.malformed,
            LineFault::Overlong => &mut self.counters.overlong,
            LineFault::NonAscii => &mut self.counters.non_ascii,
        };
        *counter += 1;
        self.last_error = Some(LineError { fault, kind });
    }

    /// Decode the line in the buffer and count it, exactly once.
    fn end_line(&mut self, out: &mut impl FnMut(Sentence)) {
        let held = self.buf.get(..self.len).unwrap_or(&[]);
        let line = held.strip_suffix(b"\r").unwrap_or(held);
        let kind = kind_of(line);
        match decode_line(line) {
            Ok(sentence) => {
                let counter = match sentence {
                    Sentence::Gga(_) => &mut self.counters.gga,
                    Sentence::Rmc(_) => &mut self.counters.rmc,
                    Sentence::Vtg(_) => &mut self.counters.vtg,
                    Sentence::Gst(_) => &mut self.counters.gst,
                };
                *counter += 1;
                out(sentence);
            }
            Err(fault) => self.skip(fault, kind),
        }
        self.len = 0;
    }
}

/// The sentence kind a line claims, if it is long enough to claim one.
fn kind_of(line: &[u8]) -> Option<SentenceKind> {
    let letters: [u8; 3] = line.get(3..6)?.try_into().ok()?;
    Some(SentenceKind::from_letters(letters))
}

fn hex_digit(byte: u8) -> Option<u8> {
    char::from(byte)
        .to_digit(16)
        .and_then(|d| u8::try_from(d).ok())
}

/// Check the framing and the checksum ourselves before the crate sees the line: the
/// crate looks up the sentence kind before the checksum, so a damaged kind would be
/// counted as an unknown sentence instead of as noise.
fn check_frame(line: &[u8]) -> Result<(), LineFault> {
    if !line.is_ascii() {
        return Err(LineFault::NonAscii);
    }
    if line.len() > MAX_LINE_LEN {
        return Err(LineFault::Overlong);
    }
    let Some(star) = line.iter().rposition(|&b| b == b'*') else {
        return Err(LineFault::Truncated);
    };
    let body = line.get(1..star).unwrap_or(&[]);
    let sent = match line.get(star + 1..) {
        Some(&[high, low]) => (hex_digit(high), hex_digit(low)),
        Some(tail) if tail.len() < 2 => return Err(LineFault::Truncated),
        _ => return Err(LineFault::Malformed("text after the checksum")),
    };
    let (Some(high), Some(low)) = sent else {
        return Err(LineFault::Checksum);
    };
    let computed = body.iter().fold(0u8, |acc, &b| acc ^ b);
    if computed != (high << 4 | low) {
        return Err(LineFault::Checksum);
    }
    Ok(())
}

/// One line, without its `\r\n`, to a sentence or the reason it is no use.
fn decode_line(line: &[u8]) -> Result<Sentence, LineFault> {
    check_frame(line)?;
    // Cannot fail after the ASCII check; mapped anyway, so no input can panic here.
    let text = core::str::from_utf8(line).map_err(|_| LineFault::NonAscii)?;
    let parsed = match ::nmea::parse_str(text) {
        Ok(parsed) => parsed,
        Err(error) => return Err(fault_of(&error, text)),
    };
    let converted = match &parsed {
        ParseResult::GGA(data) => convert::gga(data, text).map(Sentence::Gga),
        ParseResult::RMC(data) => convert::rmc(data, text).map(Sentence::Rmc),
        ParseResult::VTG(data) => convert::vtg(data).map(Sentence::Vtg),
        ParseResult::GST(data) => convert::gst(data).map(Sentence::Gst),
        _ => return Err(LineFault::UnknownKind),
    };
    converted.map_err(LineFault::Malformed)
}

/// What the crate's error means for a line whose frame and checksum are good.
fn fault_of(error: &NmeaError<'_>, text: &str) -> LineFault {
    match error {
        NmeaError::ChecksumMismatch { .. } => LineFault::Checksum,
        NmeaError::SentenceLength(_) => LineFault::Overlong,
        NmeaError::ASCII | NmeaError::Utf8Decoding => LineFault::NonAscii,
        NmeaError::DisabledSentence | NmeaError::Unsupported(_) | NmeaError::Unknown(_) => {
            LineFault::UnknownKind
        }
        // The crate reports a kind it has never heard of as a parse error of the whole
        // line; tell it apart from a known kind with a bad field.
        NmeaError::ParsingError(_) => match text.get(3..6).map(SentenceType::try_from) {
            Some(Ok(_)) => LineFault::Malformed("a field the parser could not read"),
            Some(Err(_)) => LineFault::UnknownKind,
            None => LineFault::Malformed("too short to be a sentence"),
        },
        _ => LineFault::Malformed("rejected by the nmea parser"),
    }
}

#[cfg(test)]
#[path = "decode_tests.rs"]
mod tests;

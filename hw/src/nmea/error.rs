//! Why the GNSS decoder skipped a line, as a small `Copy` value the program can keep
//! and show: "GNSS: checksum error in a GGA line".

use core::fmt;

/// The three letters after the talker id, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SentenceKind {
    Gga,
    Rmc,
    Vtg,
    Gst,
    /// Anything else, as it appeared (proprietary `$P...` lines show letters 4 to 6).
    Other([u8; 3]),
}

impl SentenceKind {
    pub(crate) fn from_letters(letters: [u8; 3]) -> SentenceKind {
        match &letters {
            b"GGA" => SentenceKind::Gga,
            b"RMC" => SentenceKind::Rmc,
            b"VTG" => SentenceKind::Vtg,
            b"GST" => SentenceKind::Gst,
            _ => SentenceKind::Other(letters),
        }
    }
}

impl fmt::Display for SentenceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let letters = match self {
            SentenceKind::Gga => *b"GGA",
            SentenceKind::Rmc => *b"RMC",
            SentenceKind::Vtg => *b"VTG",
            SentenceKind::Gst => *b"GST",
            SentenceKind::Other(letters) => *letters,
        };
        for byte in letters {
            // Line noise can put anything here; a log line must stay readable.
            let shown = if byte.is_ascii_alphanumeric() {
                byte as char
            } else {
                '?'
            };
            write!(f, "{shown}")?;
        }
        Ok(())
    }
}

/// What was wrong with a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineFault {
    /// The XOR checksum did not match, or its two digits were not hex: line noise.
    Checksum,
    /// A well-formed sentence this program does not use (or does not know).
    UnknownKind,
    /// No `*HH` at the end: the line was cut short.
    Truncated,
    /// A needed field is empty, unreadable or out of range; says which.
    Malformed(&'static str),
    /// Longer than any NMEA sentence: two lines run together, or garbage.
    Overlong,
    /// A byte above 0x7F: wrong baud rate or a noisy line.
    NonAscii,
}

/// The last line the decoder skipped, and the sentence kind it claimed to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineError {
    pub fault: LineFault,
    /// Empty when the line was too short or too damaged to say.
    pub kind: Option<SentenceKind>,
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.fault, self.kind) {
            (LineFault::Checksum, Some(kind)) => write!(f, "checksum error in a {kind} line"),
            (LineFault::Checksum, None) => write!(f, "checksum error"),
            (LineFault::UnknownKind, Some(kind)) => write!(f, "unknown sentence kind {kind}"),
            (LineFault::UnknownKind, None) => write!(f, "unknown sentence kind"),
            (LineFault::Truncated, Some(kind)) => write!(f, "{kind} line cut short"),
            (LineFault::Truncated, None) => write!(f, "line cut short"),
            (LineFault::Malformed(why), Some(kind)) => write!(f, "bad {kind} line: {why}"),
            (LineFault::Malformed(why), None) => write!(f, "bad line: {why}"),
            (LineFault::Overlong, Some(kind)) => write!(f, "overlong {kind} line"),
            (LineFault::Overlong, None) => write!(f, "overlong line"),
            (LineFault::NonAscii, Some(kind)) => write!(f, "non-ascii byte in a {kind} line"),
            (LineFault::NonAscii, None) => write!(f, "non-ascii byte in a line"),
        }
    }
}

impl std::error::Error for LineError {}

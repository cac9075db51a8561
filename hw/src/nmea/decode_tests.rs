//! Tests of the NMEA decoder: published example sentences, every way a line can be
//! skipped, and resynchronisation after damage.

use super::*;
use crate::nmea::sentence::{FixQuality, RmcMode};

// Classic examples with their published checksums (GGA, RMC, VTG: the NMEA notes of
// gpsinformation.org; GST: Trimble's NMEA-0183 message reference; GNRMC: u-blox).
const GGA: &str = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n";
const RMC: &str = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n";
const VTG: &str = "$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n";
const GST: &str = "$GPGST,172814.0,0.006,0.023,0.020,273.6,0.023,0.020,0.031*6A\r\n";
const GNRMC: &str = "$GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A*7B\r\n";

/// `$body*HH\r\n` with the right checksum, for lines made up by the tests.
fn line(body: &str) -> String {
    let sum = body.bytes().fold(0u8, |acc, b| acc ^ b);
    format!("${body}*{sum:02X}\r\n")
}

fn decode(bytes: &[u8]) -> (Vec<Sentence>, NmeaDecoder) {
    let mut decoder = NmeaDecoder::new();
    let mut sentences = Vec::new();
    decoder.push(bytes, |s| sentences.push(s));
    (sentences, decoder)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn published_examples_decode_to_si_units() {
    let stream = [GGA, RMC, VTG, GST, GNRMC].concat();
    let (sentences, decoder) = decode(stream.as_bytes());
    assert_eq!(decoder.counters().good(), 5, "{:?}", decoder.counters());
    let [
        Sentence::Gga(gga),
        Sentence::Rmc(rmc),
        Sentence::Vtg(vtg),
        Sentence::Gst(gst),
        _,
    ] = sentences[..]
    else {
        panic!("wrong kinds: {sentences:?}");
    };
    assert_eq!(gga.utc_s_of_day, Some(12.0 * 3600.0 + 35.0 * 60.0 + 19.0));
    let pos = gga.position.expect("position");
    assert!(close(pos.lat_deg, 48.0 + 7.038 / 60.0, 1e-12));
    assert!(close(pos.lon_deg, 11.0 + 31.0 / 60.0, 1e-12));
    assert_eq!(gga.quality, FixQuality::Gps);
    assert_eq!(gga.satellites, Some(8));
    assert_eq!(gga.hdop, Some(0.9));
    assert!(close(gga.altitude_m.expect("altitude"), 545.4, 1e-4));
    assert_eq!(gga.correction_age_s, None);
    assert!(rmc.valid);
    assert!(close(
        rmc.speed_mps.expect("speed"),
        22.4 * 1852.0 / 3600.0,
        1e-5
    ));
    assert!(close(rmc.course_deg.expect("course"), 84.4, 1e-5));
    assert!(close(
        vtg.speed_mps.expect("speed"),
        5.5 * 1852.0 / 3600.0,
        1e-5
    ));
    assert!(close(vtg.course_deg.expect("course"), 54.7, 1e-5));
    assert_eq!(gst.utc_s_of_day, 17.0 * 3600.0 + 28.0 * 60.0 + 14.0);
    assert!(close(gst.sd_lat_m.expect("sd lat"), 0.023, 1e-7));
    assert!(close(gst.sd_lon_m.expect("sd lon"), 0.020, 1e-7));
    assert!(close(gst.sd_alt_m.expect("sd alt"), 0.031, 1e-7));
}

#[test]
fn every_talker_id_is_accepted() {
    let body = "GGA,123519,4807.038,N,01131.000,E,4,08,0.9,545.4,M,46.9,M,,";
    for talker in ["GP", "GN", "GL", "GA", "GB", "GQ", "BD"] {
        let (sentences, decoder) = decode(line(&format!("{talker}{body}")).as_bytes());
        assert_eq!(
            sentences.len(),
            1,
            "talker {talker}: {:?}",
            decoder.last_error()
        );
    }
}

#[test]
fn chunking_does_not_change_the_result() {
    let stream = [GGA, "junk", RMC, "$GPGGA,12", VTG, GST].concat();
    let (whole, whole_decoder) = decode(stream.as_bytes());
    let mut decoder = NmeaDecoder::new();
    let mut bytewise = Vec::new();
    for byte in stream.as_bytes() {
        decoder.push(std::slice::from_ref(byte), |s| bytewise.push(s));
    }
    assert_eq!(whole.len(), 4);
    assert_eq!(bytewise, whole);
    assert_eq!(decoder.counters(), whole_decoder.counters());
}

#[test]
fn a_bad_checksum_is_counted_and_named_and_the_next_line_decodes() {
    let damaged = GGA.replace("545.4", "545.5");
    let (sentences, decoder) = decode([damaged.as_str(), RMC].concat().as_bytes());
    assert!(matches!(sentences[..], [Sentence::Rmc(_)]));
    assert_eq!(decoder.counters().checksum_errors, 1);
    let error = decoder.last_error().expect("an error");
    assert_eq!(error.to_string(), "checksum error in a GGA line");
    // Damage in the kind letters is noise too, not an unknown sentence.
    let (_, decoder) = decode(GGA.replace("GPGGA", "GPGGB").as_bytes());
    assert_eq!(decoder.counters().checksum_errors, 1);
    assert_eq!(decoder.counters().unknown_kinds, 0);
}

#[test]
fn a_line_cut_short_does_not_swallow_the_next() {
    // The receiver's buffer overflowed mid-line: no `\r\n` before the next `$`.
    let stream = ["$GPGGA,123519,4807.0", RMC, "$GPVTG,054.7,T,03\r\n"].concat();
    let (sentences, decoder) = decode(stream.as_bytes());
    assert!(matches!(sentences[..], [Sentence::Rmc(_)]));
    assert_eq!(decoder.counters().malformed, 2);
    assert_eq!(
        decoder.last_error().map(|e| e.to_string()),
        Some("VTG line cut short".into())
    );
    // A line that lost only its `\r\n` is whole, and decodes.
    let (sentences, _) = decode([GGA.trim_end(), RMC].concat().as_bytes());
    assert_eq!(sentences.len(), 2);
}

#[test]
fn sentences_of_other_kinds_are_counted_as_unknown() {
    let stream = [
        // Known to the crate but not enabled here.
        "$GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1*39\r\n".to_string(),
        line("GPXYZ,1,2,3"),
        line("PUBX,00,081350.00"),
        GGA.to_string(),
    ]
    .concat();
    let (sentences, decoder) = decode(stream.as_bytes());
    assert_eq!(sentences.len(), 1);
    assert_eq!(
        decoder.counters().unknown_kinds,
        3,
        "{:?}",
        decoder.counters()
    );
    let (_, decoder) = decode(line("GPXYZ,1").as_bytes());
    assert_eq!(
        decoder.last_error().map(|e| e.to_string()),
        Some("unknown sentence kind XYZ".into())
    );
}

#[test]
fn a_gga_without_a_fix_is_a_sentence_not_an_error() {
    // What a u-blox receiver sends before its first fix.
    let (sentences, decoder) = decode(line("GPGGA,,,,,,0,00,99.99,,,,,,").as_bytes());
    assert_eq!(
        decoder.counters().skipped(),
        0,
        "{:?}",
        decoder.last_error()
    );
    let [Sentence::Gga(gga)] = sentences[..] else {
        panic!("{sentences:?}")
    };
    assert_eq!(gga.quality, FixQuality::None);
    assert!(!gga.quality.carries_position());
    assert_eq!((gga.position, gga.utc_s_of_day), (None, None));
}

#[test]
fn rtk_quality_and_correction_age_are_read() {
    let body = "GNGGA,101010.20,4807.0380000,N,01131.0000000,E,4,21,0.6,545.400,M,,,1.4,0031";
    let (sentences, _) = decode(line(body).as_bytes());
    let [Sentence::Gga(gga)] = sentences[..] else {
        panic!("{sentences:?}")
    };
    assert_eq!(gga.quality, FixQuality::RtkFixed);
    assert!(gga.quality.is_rtk());
    assert_eq!(gga.correction_age_s, Some(1.4));
    assert!(close(gga.utc_s_of_day.expect("time"), 36610.2, 1e-9));
    let (sentences, _) = decode(GNRMC.as_bytes());
    let [Sentence::Rmc(rmc)] = sentences[..] else {
        panic!("{sentences:?}")
    };
    assert_eq!(rmc.mode, Some(RmcMode::Autonomous));
    let pos = rmc.position.expect("position");
    assert!(pos.lon_deg < 0.0, "west is negative: {pos:?}");
}

#[test]
fn impossible_numbers_are_malformed_with_a_reason() {
    let gga = |fields: &str| line(&format!("GPGGA,123519,{fields},M,46.9,M,,"));
    let cases = [
        (
            gga("9100.000,N,01131.000,E,4,08,0.9,545.4"),
            "latitude beyond 90 degrees",
        ),
        (
            gga("4807.038,N,18100.000,E,4,08,0.9,545.4"),
            "longitude beyond 180 degrees",
        ),
        (
            gga("4807.038,N,01131.000,E,4,08,0.9,1e300"),
            "altitude out of range",
        ),
        (
            gga("4807.038,N,01131.000,E,4,08,nan,545.4"),
            "hdop out of range",
        ),
        (
            gga("4807.038,N,01131.000,E,4,150,0.9,545.4"),
            "satellite count above 99",
        ),
        (gga(",,,,4,08,0.9,545.4"), "fix without a position"),
        (
            gga("5275.000,N,01131.000,E,4,08,0.9,545.4"),
            "minutes of a latitude or longitude not between 0 and 60",
        ),
        (
            gga("4807.038,N,01199.000,E,4,08,0.9,545.4"),
            "minutes of a latitude or longitude not between 0 and 60",
        ),
        (
            line("GPRMC,123519,A,4807.038,N,01160.000,E,022.4,084.4,230394,003.1,W"),
            "minutes of a latitude or longitude not between 0 and 60",
        ),
        (line("GPVTG,054.7,T,,M,-5.5,N,,K"), "speed out of range"),
        (
            line("GPGST,,0.006,0.023,0.020,273.6,0.023,0.020,0.031"),
            "empty time",
        ),
        (
            line("GPGST,172814.0,,,,,inf,0.020,0.031"),
            "standard deviation out of range",
        ),
    ];
    for (text, why) in cases {
        let (sentences, decoder) = decode(text.as_bytes());
        assert!(sentences.is_empty(), "{text} gave {sentences:?}");
        assert_eq!(decoder.counters().malformed, 1, "{text}");
        assert_eq!(
            decoder.last_error().map(|e| e.fault),
            Some(LineFault::Malformed(why)),
            "{text}"
        );
    }
}

#[test]
fn an_overlong_line_is_skipped_to_its_end() {
    let long = format!("$GPGGA,{}*00\r\n", "9".repeat(999));
    let stream = [long.as_str(), GGA, &long, "junk", RMC].concat();
    let (sentences, decoder) = decode(stream.as_bytes());
    assert_eq!(sentences.len(), 2);
    assert_eq!(decoder.counters().overlong, 2);
    assert_eq!(decoder.counters().stray_bytes, 4);
    assert_eq!(decoder.counters().lines(), 4);
    // The longest line taken is taken whole.
    let base = "GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,";
    // `$`, the body, `*HH`: the station id field is padded to fill the line.
    let longest = line(&format!(
        "{base}{}",
        "0".repeat(MAX_LINE_LEN - 4 - base.len())
    ));
    assert_eq!(longest.trim_end().len(), MAX_LINE_LEN);
    let (sentences, decoder) = decode(longest.as_bytes());
    assert_eq!(sentences.len(), 1, "{:?}", decoder.last_error());
}

#[test]
fn non_ascii_bytes_and_bare_newlines() {
    let mut stream = GGA.as_bytes().to_vec();
    stream.splice(10..10, [0xC3, 0xA9]);
    stream.extend_from_slice(&[0xFF, 0xFE]);
    stream.extend_from_slice(RMC.replace("\r\n", "\n").as_bytes());
    let (sentences, decoder) = decode(&stream);
    assert!(matches!(sentences[..], [Sentence::Rmc(_)]));
    assert_eq!(decoder.counters().non_ascii, 1);
    assert_eq!(decoder.counters().stray_bytes, 2);
}

#[test]
fn error_messages_read_as_sentences() {
    let shown = |fault, kind| LineError { fault, kind }.to_string();
    assert_eq!(shown(LineFault::Overlong, None), "overlong line");
    assert_eq!(
        shown(LineFault::NonAscii, Some(SentenceKind::Rmc)),
        "non-ascii byte in a RMC line"
    );
    assert_eq!(
        shown(LineFault::Malformed("empty time"), Some(SentenceKind::Gst)),
        "bad GST line: empty time"
    );
    // Line noise in the kind letters stays printable.
    assert_eq!(
        shown(
            LineFault::UnknownKind,
            Some(SentenceKind::Other(*b"X\n\xff"))
        ),
        "unknown sentence kind X??"
    );
}

//! Tests of the NMEA encoder, through the decoder and the fix assembler: what the
//! simulated receiver writes is what the program reads.

use super::*;
use crate::nmea::decode::NmeaDecoder;
use crate::nmea::fix::{Epoch, Fix, FixAssembler};
use crate::nmea::sentence::Sentence;

fn epoch(lat_deg: f64, lon_deg: f64, utc_s_of_day: f64) -> ReceiverEpoch {
    ReceiverEpoch {
        utc_s_of_day,
        lat_deg,
        lon_deg,
        altitude_m: 512.3456,
        quality: FixQuality::RtkFixed,
        satellites: 23,
        hdop: 0.64,
        correction_age_s: Some(1.26),
        sd_lat_m: 0.01234,
        sd_lon_m: 0.0456,
        sd_alt_m: 0.0211,
        speed_mps: 0.83,
        course_deg: 271.456,
    }
}

/// Encode one epoch, decode it, and assemble it.
fn round_trip(encoder: &NmeaEncoder, e: &ReceiverEpoch) -> (Vec<Sentence>, Vec<Epoch>) {
    let mut decoder = NmeaDecoder::new();
    let mut assembler = FixAssembler::new();
    let (mut sentences, mut epochs) = (Vec::new(), Vec::new());
    for line in encoder.epoch(e).expect("encodes") {
        decoder.push(line.as_bytes(), |s| sentences.push(s));
    }
    assert_eq!(
        decoder.counters().skipped(),
        0,
        "{:?}",
        decoder.last_error()
    );
    for &s in &sentences {
        assembler.push(s, |ep| epochs.push(ep));
    }
    assembler.finish(|ep| epochs.push(ep));
    (sentences, epochs)
}

fn the_fix(epochs: &[Epoch]) -> Fix {
    match epochs {
        [Epoch::Fix(fix)] => *fix,
        other => panic!("expected one fix, got {other:?}"),
    }
}

/// Printed to the millimetre: what comes back is exactly the rounded value.
fn printed_mm(value: f64) -> f64 {
    (value * 1000.0).round() / 1000.0
}

#[test]
fn positions_come_back_within_a_millimetre_everywhere() {
    let encoder = NmeaEncoder::new();
    let places = [
        (48.117_300_123_4, 11.516_666_987_6),
        (-33.856_784_333_3, 151.215_297_444_4),
        (0.000_000_7, -0.000_000_4),
        (-89.999_999_99, 179.999_999_99),
        (52.520_008_333_33, -179.999_999_999),
        (59.999_999_999_9, 0.999_999_999_99),
    ];
    for (lat_deg, lon_deg) in places {
        let fix = the_fix(&round_trip(&encoder, &epoch(lat_deg, lon_deg, 45_319.37)).1);
        let north_error_m = (fix.lat_deg - lat_deg) * 111_320.0;
        let east_error_m = (fix.lon_deg - lon_deg) * 111_320.0 * lat_deg.to_radians().cos();
        assert!(north_error_m.abs() < 1e-3, "{lat_deg}: {north_error_m} m");
        assert!(east_error_m.abs() < 1e-3, "{lon_deg}: {east_error_m} m");
    }
}

#[test]
fn the_other_fields_come_back_to_their_printed_precision() {
    let e = epoch(48.1, 11.5, 86_399.996);
    let fix = the_fix(&round_trip(&NmeaEncoder::new(), &e).1);
    assert_eq!(fix.quality, FixQuality::RtkFixed);
    assert_eq!(fix.satellites, Some(23));
    // 86399.996 s rounds to the next midnight.
    assert_eq!(fix.utc_s_of_day, 0.0);
    assert_eq!(
        fix.sd_north_m.map(|v| v as f32),
        Some(printed_mm(e.sd_lat_m) as f32)
    );
    assert_eq!(
        fix.sd_east_m.map(|v| v as f32),
        Some(printed_mm(e.sd_lon_m) as f32)
    );
    assert!((fix.altitude_m.expect("altitude") - printed_mm(e.altitude_m)).abs() < 1e-4);
    assert_eq!(fix.hdop, Some(0.6));
    assert_eq!(fix.correction_age_s, Some(1.3));
    assert!((fix.speed_mps.expect("speed") - e.speed_mps).abs() < 1e-3);
    assert!((fix.course_deg.expect("course") - 271.46).abs() < 1e-4);
}

#[test]
fn every_quality_survives_and_no_fix_writes_no_position() {
    for quality in [
        FixQuality::Gps,
        FixQuality::Dgps,
        FixQuality::RtkFloat,
        FixQuality::Other(6),
    ] {
        let e = ReceiverEpoch {
            quality,
            ..epoch(10.0, 20.0, 100.0)
        };
        assert_eq!(
            the_fix(&round_trip(&NmeaEncoder::new(), &e).1).quality,
            quality
        );
    }
    let lost = ReceiverEpoch {
        quality: FixQuality::None,
        lat_deg: f64::NAN,
        ..epoch(0.0, 0.0, 100.0)
    };
    let (_, epochs) = round_trip(&NmeaEncoder::new(), &lost);
    assert_eq!(
        epochs,
        [Epoch::NoFix {
            utc_s_of_day: Some(100.0),
            satellites: Some(23)
        }]
    );
}

#[test]
fn lines_have_the_talker_and_a_crlf() {
    let encoder = NmeaEncoder::with_talker(*b"GP").expect("a good talker");
    let line = encoder.gga(&epoch(48.1, 11.5, 1.0)).expect("encodes");
    let text = String::from_utf8(line.as_bytes().to_vec()).expect("ascii");
    assert!(
        text.starts_with("$GPGGA,000001.00,4806.0000000,N,01130.0000000,E,4,23,"),
        "{text}"
    );
    assert!(
        text.ends_with("\r\n") && text.matches('\n').count() == 1,
        "{text:?}"
    );
    assert_eq!(
        NmeaEncoder::new()
            .gga(&epoch(1.0, 1.0, 1.0))
            .expect("encodes")
            .as_bytes()[..6],
        *b"$GNGGA"
    );
    assert_eq!(
        NmeaEncoder::with_talker(*b"g$").err(),
        Some(EncodeError::BadTalker)
    );
}

#[test]
fn impossible_input_is_refused_with_the_field_named() {
    let encoder = NmeaEncoder::new();
    let refuse = |e: ReceiverEpoch| encoder.epoch(&e).err().map(|err| err.to_string());
    let good = epoch(1.0, 1.0, 1.0);
    assert_eq!(
        refuse(ReceiverEpoch {
            lat_deg: 90.5,
            ..good
        }),
        Some("latitude is out of range".into())
    );
    assert_eq!(
        refuse(ReceiverEpoch {
            utc_s_of_day: f64::NAN,
            ..good
        }),
        Some("time is not a finite number".into())
    );
    assert_eq!(
        refuse(ReceiverEpoch {
            altitude_m: f64::INFINITY,
            ..good
        }),
        Some("altitude is not a finite number".into())
    );
    assert_eq!(
        refuse(ReceiverEpoch {
            speed_mps: -0.1,
            ..good
        }),
        Some("speed is out of range".into())
    );
    assert_eq!(
        refuse(ReceiverEpoch {
            correction_age_s: Some(f64::NAN),
            ..good
        }),
        Some("correction age is not a finite number".into())
    );
    // Without a fix the position is not written, so it need not be a number.
    let lost = ReceiverEpoch {
        quality: FixQuality::None,
        lat_deg: f64::NAN,
        ..good
    };
    assert!(encoder.epoch(&lost).is_ok());
    // A course is any angle; on the wire it is 0..360.
    let vtg = encoder
        .vtg(&ReceiverEpoch {
            course_deg: -90.0,
            ..good
        })
        .expect("encodes");
    assert!(String::from_utf8_lossy(vtg.as_bytes()).starts_with("$GNVTG,270.00,T,"));
    // A number too long to print in a line is refused, not cut.
    assert_eq!(
        refuse(ReceiverEpoch {
            altitude_m: 1e300,
            ..good
        }),
        Some(EncodeError::TooLong.to_string())
    );
}

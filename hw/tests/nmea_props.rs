//! Property tests of the NMEA decoder: whatever arrives, it never panics, counts every
//! line exactly once, and damage to one line never costs the lines around it.

use mechweed_hw::nmea::encode::{NmeaEncoder, ReceiverEpoch};
use mechweed_hw::nmea::fuzz::{check_stream, impossible_field};
use mechweed_hw::nmea::{FixQuality, NmeaDecoder, Sentence};
use proptest::prelude::*;

fn epoch() -> impl Strategy<Value = ReceiverEpoch> {
    let quality = prop::sample::select(vec![0u8, 1, 2, 4, 5, 6]).prop_map(FixQuality::from_code);
    (
        (
            0.0..86_399.0f64,
            -90.0..=90.0f64,
            -180.0..=180.0f64,
            -400.0..9_000.0f64,
        ),
        (
            quality,
            0u8..=99,
            0.0..50.0f64,
            prop::option::of(0.0..100.0f64),
        ),
        (
            0.0..10.0f64,
            0.0..10.0f64,
            0.0..10.0f64,
            0.0..50.0f64,
            0.0..360.0f64,
        ),
    )
        .prop_map(
            |((t, lat, lon, alt), (quality, sats, hdop, age), (sdn, sde, sdu, v, c))| {
                ReceiverEpoch {
                    utc_s_of_day: t,
                    lat_deg: lat,
                    lon_deg: lon,
                    altitude_m: alt,
                    quality,
                    satellites: sats,
                    hdop,
                    correction_age_s: age,
                    sd_lat_m: sdn,
                    sd_lon_m: sde,
                    sd_alt_m: sdu,
                    speed_mps: v,
                    course_deg: c,
                }
            },
        )
}

/// Valid lines, four per epoch.
fn lines() -> impl Strategy<Value = Vec<Vec<u8>>> {
    prop::collection::vec(epoch(), 1..4).prop_map(|epochs| {
        let encoder = NmeaEncoder::new();
        epochs
            .iter()
            .flat_map(|e| encoder.epoch(e).expect("generated epochs are valid"))
            .map(|line| line.as_bytes().to_vec())
            .collect()
    })
}

fn decode(bytes: &[u8]) -> Vec<Sentence> {
    let mut decoder = NmeaDecoder::new();
    let mut sentences = Vec::new();
    decoder.push(bytes, |s| sentences.push(s));
    sentences
}

/// What each line gives alone: one sentence per valid line.
fn each(lines: &[Vec<u8>]) -> Vec<Sentence> {
    lines.iter().flat_map(|l| decode(l)).collect()
}

/// Bytes that look like NMEA more often than uniform bytes would.
fn nmea_ish_bytes() -> impl Strategy<Value = Vec<u8>> {
    let byte = prop_oneof![
        any::<u8>(),
        prop::sample::select(b"$*,.\r\n0123456789ABCDEFGNPRMCVTSWK-e".to_vec()),
    ];
    prop::collection::vec(byte, 0..400)
}

fn with_checksum(body: &str) -> Vec<u8> {
    let sum = body.bytes().fold(0u8, |acc, b| acc ^ b);
    format!("${body}*{sum:02X}\r\n").into_bytes()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn arbitrary_bytes_keep_every_promise(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        prop_assert_eq!(check_stream(&bytes), Ok(()));
    }

    #[test]
    fn nmea_like_noise_between_valid_lines_keeps_every_promise(
        noise in nmea_ish_bytes(),
        lines in lines(),
        at in any::<prop::sample::Index>(),
    ) {
        let mut stream = lines.concat();
        let at = at.index(stream.len() + 1);
        stream.splice(at..at, noise);
        prop_assert_eq!(check_stream(&stream), Ok(()));
    }

    #[test]
    fn a_line_cut_anywhere_costs_only_itself(
        lines in lines(),
        which in any::<prop::sample::Index>(),
        cut in any::<prop::sample::Index>(),
    ) {
        let which = which.index(lines.len());
        let len = lines[which].len();
        let cut = cut.index(len + 1);
        let mut damaged = lines.clone();
        damaged[which].truncate(cut);
        let stream = damaged.concat();
        prop_assert_eq!(check_stream(&stream), Ok(()));
        // Cut only in its `\r\n` the line is still whole if a next `$` ends it; the last
        // line stays open, waiting for its end.
        let ended = which + 1 < lines.len();
        let mut expected = lines.clone();
        if cut < len && !(cut >= len - 2 && ended) {
            expected.remove(which);
        }
        prop_assert_eq!(decode(&stream), each(&expected));
    }

    #[test]
    fn a_changed_byte_never_gives_a_different_sentence(
        lines in lines(),
        which in any::<prop::sample::Index>(),
        at in any::<prop::sample::Index>(),
        byte in any::<u8>(),
    ) {
        let which = which.index(lines.len());
        let at = at.index(lines[which].len());
        prop_assume!(lines[which][at] != byte);
        let mut damaged = lines.clone();
        damaged[which][at] = byte;
        let stream = damaged.concat();
        prop_assert_eq!(check_stream(&stream), Ok(()));
        // The XOR checksum catches any one changed byte: the line is lost or, if the
        // change was harmless (a hex digit's case, `\r` to `\n`), decodes as before.
        let all = each(&lines);
        let mut without = lines.clone();
        without.remove(which);
        let got = decode(&stream);
        prop_assert!(got == all || got == each(&without), "{:?}", String::from_utf8_lossy(&stream));
    }
}

const TEMPLATES: [&str; 4] = [
    "GNGGA,123519.00,4807.038,N,01131.000,E,4,08,0.9,545.4,M,46.9,M,1.0,0000",
    "GNRMC,123519.00,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W,R",
    "GNVTG,054.7,T,034.4,M,005.5,N,010.2,K,R",
    "GNGST,172814.0,0.006,0.023,0.020,273.6,0.023,0.020,0.031",
];

fn absurd_values() -> Vec<String> {
    let mut values: Vec<String> = [
        "1e300",
        "-1e300",
        "nan",
        "NaN",
        "inf",
        "-inf",
        "infinity",
        "-5",
        "1e-400",
        "+7",
        "-0",
        "",
        "0x1F",
        "9999.999",
        "18100.0",
        "99",
        "9999999999",
        "-0.001",
        "1e38",
        "3.4e39",
    ]
    .map(String::from)
    .to_vec();
    values.extend([
        "9".repeat(999),
        "9".repeat(40),
        format!("0.{}", "9".repeat(60)),
    ]);
    values
}

/// Every sentence kind, every field, every absurd value: too few cases to leave to chance.
fn absurd_lines() -> Vec<Vec<u8>> {
    let values = absurd_values();
    let mut lines = Vec::new();
    for template in TEMPLATES {
        let fields: Vec<&str> = template.split(',').collect();
        for field in 1..fields.len() {
            for value in &values {
                let mut changed = fields.clone();
                changed[field] = value;
                lines.push(with_checksum(&changed.join(",")));
            }
        }
    }
    lines
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    #[test]
    fn absurd_numbers_are_never_passed_on_and_cost_only_their_line(lines in lines()) {
        let expected = each(&lines);
        for nasty in absurd_lines() {
            let stream = [lines[0].clone(), nasty.clone(), lines[1..].concat()].concat();
            prop_assert_eq!(check_stream(&stream), Ok(()));
            let from_nasty = decode(&nasty);
            for sentence in &from_nasty {
                prop_assert_eq!(impossible_field(sentence), None, "{}", String::from_utf8_lossy(&nasty));
            }
            // The lines around it decode as if it were not there.
            let mut got = decode(&stream);
            got.drain(1..1 + from_nasty.len());
            prop_assert_eq!(&got, &expected);
        }
    }
}

//! Tests of epoch assembly, with the sentence orders of real receivers.

use super::*;
use crate::nmea::sentence::{Gst, LatLon, Rmc, Vtg};

fn gga(t: f64, quality: FixQuality) -> Sentence {
    Sentence::Gga(Gga {
        utc_s_of_day: Some(t),
        position: Some(LatLon {
            lat_deg: 48.1,
            lon_deg: 11.5 + t * 1e-6,
        }),
        quality,
        satellites: Some(20),
        hdop: Some(0.7),
        altitude_m: Some(500.0),
        correction_age_s: Some(1.0),
    })
}

fn rmc(t: f64) -> Sentence {
    Sentence::Rmc(Rmc {
        utc_s_of_day: Some(t),
        valid: true,
        position: Some(LatLon {
            lat_deg: 48.1,
            lon_deg: 11.5,
        }),
        speed_mps: Some(1.0),
        course_deg: Some(90.0),
        mode: None,
    })
}

fn vtg() -> Sentence {
    Sentence::Vtg(Vtg {
        course_deg: Some(91.0),
        speed_mps: Some(1.1),
    })
}

fn gst(t: f64) -> Sentence {
    Sentence::Gst(Gst {
        utc_s_of_day: t,
        sd_lat_m: Some(0.012),
        sd_lon_m: Some(0.034),
        sd_alt_m: Some(0.05),
    })
}

/// Feed the sentences; for each, the epochs it made the assembler pass on.
fn run(assembler: &mut FixAssembler, sentences: &[Sentence]) -> Vec<Vec<Epoch>> {
    sentences
        .iter()
        .map(|&s| {
            let mut epochs = Vec::new();
            assembler.push(s, |e| epochs.push(e));
            epochs
        })
        .collect()
}

fn fix(epoch: &Epoch) -> Fix {
    match epoch {
        Epoch::Fix(fix) => *fix,
        other => panic!("expected a fix, got {other:?}"),
    }
}

#[test]
fn gga_first_order_gives_one_complete_fix_per_epoch_without_waiting() {
    let mut assembler = FixAssembler::new();
    let quality = FixQuality::RtkFixed;
    let epoch = |t| [gga(t, quality), rmc(t), vtg(), gst(t)];
    // The first epoch teaches the assembler what this receiver sends: it goes out
    // when the second begins, with its GST.
    assert!(run(&mut assembler, &epoch(10.0)).iter().all(Vec::is_empty));
    let out = run(&mut assembler, &[gga(10.2, quality)]);
    let [ref first] = out[0][..] else {
        panic!("{out:?}")
    };
    assert_eq!(
        (fix(first).utc_s_of_day, fix(first).sd_east_m),
        (10.0, Some(0.034))
    );
    run(&mut assembler, &epoch(10.2)[1..]);
    for t in [10.4, 10.6] {
        let out = run(&mut assembler, &epoch(t));
        // Nothing before the GST, which completes the epoch: the fix goes out with it,
        // not one epoch later.
        assert!(out[..3].iter().all(Vec::is_empty), "{out:?}");
        let [ref made] = out[3][..] else {
            panic!("{out:?}")
        };
        let fix = fix(made);
        assert_eq!(fix.utc_s_of_day, t);
        assert_eq!(fix.quality, quality);
        assert_eq!((fix.sd_north_m, fix.sd_east_m), (Some(0.012), Some(0.034)));
        // VTG is preferred for motion when both are sent.
        assert_eq!((fix.speed_mps, fix.course_deg), (Some(1.1), Some(91.0)));
    }
    assert_eq!(assembler.counters().fixes, 4);
    assert_eq!(assembler.counters().late, 0);
}

#[test]
fn gga_after_rmc_as_u_blox_sends_it() {
    let mut assembler = FixAssembler::new();
    let epoch = |t| [rmc(t), vtg(), gga(t, FixQuality::RtkFloat), gst(t)];
    let mut fixes = Vec::new();
    for t in [1.0, 1.1, 1.2] {
        for out in run(&mut assembler, &epoch(t)) {
            fixes.extend(out.iter().map(fix));
        }
    }
    assert_eq!(
        fixes.iter().map(|f| f.utc_s_of_day).collect::<Vec<_>>(),
        [1.0, 1.1, 1.2]
    );
    assert!(
        fixes.iter().all(|f| f.sd_east_m == Some(0.034)),
        "{fixes:?}"
    );
}

#[test]
fn a_gst_of_another_time_is_not_used() {
    let mut assembler = FixAssembler::new();
    run(&mut assembler, &[gga(5.0, FixQuality::RtkFixed), gst(5.0)]);
    // A stale GST (from 5.9, say a 1 Hz GST lagging) must not give 6.0 its numbers.
    let out = run(
        &mut assembler,
        &[
            gga(6.0, FixQuality::RtkFixed),
            gst(5.9),
            gga(6.1, FixQuality::RtkFixed),
        ],
    );
    let fixes: Vec<Fix> = out.iter().flatten().map(fix).collect();
    let at_6 = fixes
        .iter()
        .find(|f| f.utc_s_of_day == 6.0)
        .expect("the fix at 6.0");
    assert_eq!(at_6.sd_east_m, None);
}

#[test]
fn an_epoch_missing_a_sentence_goes_out_when_the_next_begins() {
    let mut assembler = FixAssembler::new();
    let q = FixQuality::RtkFixed;
    run(
        &mut assembler,
        &[gga(1.0, q), gst(1.0), gga(2.0, q), gst(2.0)],
    );
    // Epoch 3's GST was lost to a checksum error.
    let out = run(&mut assembler, &[gga(3.0, q)]);
    assert!(
        out[0].is_empty(),
        "the assembler waits for the GST: {out:?}"
    );
    let out = run(&mut assembler, &[gga(4.0, q)]);
    let [ref late] = out[0][..] else {
        panic!("{out:?}")
    };
    assert_eq!((fix(late).utc_s_of_day, fix(late).sd_east_m), (3.0, None));
    assert_eq!(assembler.counters().late, 1);
    // One lost GST does not make the assembler stop waiting for the next one.
    let out = run(&mut assembler, &[gst(4.0)]);
    let [ref complete] = out[0][..] else {
        panic!("{out:?}")
    };
    assert_eq!(fix(complete).sd_east_m, Some(0.034));
    // And finish passes on what is still waiting.
    run(&mut assembler, &[gga(5.0, q)]);
    let mut rest = Vec::new();
    assembler.finish(|e| rest.push(e));
    assert_eq!(
        rest.iter().map(|e| fix(e).utc_s_of_day).collect::<Vec<_>>(),
        [5.0]
    );
}

#[test]
fn a_receiver_that_stops_sending_gst_is_waited_for_two_epochs_only() {
    let mut assembler = FixAssembler::new();
    let q = FixQuality::RtkFixed;
    run(
        &mut assembler,
        &[gga(1.0, q), gst(1.0), gga(2.0, q), gst(2.0)],
    );
    let out = run(
        &mut assembler,
        &[gga(3.0, q), gga(4.0, q), gga(5.0, q), gga(6.0, q)],
    );
    // 3 and 4 go out late (when 4 and 5 begin); 5 and 6 on time, at their GGA.
    let when: Vec<Vec<f64>> = out
        .iter()
        .map(|o| o.iter().map(|e| fix(e).utc_s_of_day).collect())
        .collect();
    assert_eq!(when, [vec![], vec![3.0], vec![4.0, 5.0], vec![6.0]]);
    assert_eq!(assembler.counters().late, 2);
}

#[test]
fn a_gga_without_a_fix_gives_a_no_fix_epoch() {
    let mut assembler = FixAssembler::new();
    let no_time = Sentence::Gga(Gga {
        utc_s_of_day: None,
        position: None,
        quality: FixQuality::None,
        satellites: Some(3),
        hdop: None,
        altitude_m: None,
        correction_age_s: None,
    });
    let out = run(&mut assembler, &[no_time, gga(7.0, FixQuality::None)]);
    assert_eq!(
        out[0],
        [Epoch::NoFix {
            utc_s_of_day: None,
            satellites: Some(3)
        }]
    );
    let mut rest = Vec::new();
    assembler.finish(|e| rest.push(e));
    assert_eq!(
        rest,
        [Epoch::NoFix {
            utc_s_of_day: Some(7.0),
            satellites: Some(20)
        }]
    );
    assert_eq!(assembler.counters().no_fixes, 2);
    assert_eq!(assembler.counters().fixes, 0);
}

#[test]
fn repeats_and_orphans_are_counted_not_passed_on() {
    let mut assembler = FixAssembler::new();
    run(
        &mut assembler,
        &[vtg(), gga(1.0, FixQuality::Gps), gga(1.0, FixQuality::Dgps)],
    );
    let mut out = Vec::new();
    assembler.finish(|e| out.push(e));
    assert_eq!(out.len(), 1);
    assert_eq!(fix(&out[0]).quality, FixQuality::Gps);
    let counters = assembler.counters();
    assert_eq!((counters.orphans, counters.repeated), (1, 1));
}

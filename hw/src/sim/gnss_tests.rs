//! Tests of the simulated GNSS receiver: its lines decoded by the program's own decoder.

use super::*;
use crate::nmea::{Epoch, FixAssembler, NmeaDecoder};
use crate::sim::pipe::byte_pipe;

/// A receiver on a robot standing at `pose`, run for `duration_s`: the fixes decoded
/// from its lines, each with its arrival time.
fn fixes(
    params: &SimParams,
    pose: &Pose,
    duration_s: f64,
    events: &[(f64, GnssState)],
) -> Vec<(f64, Epoch)> {
    let params = params.sanitized();
    let (receiver_end, robot_end) = byte_pipe(8192);
    let mut robot_end = robot_end;
    let mut rx = SimReceiver::new(&params, receiver_end);
    let (mut decoder, mut assembler) = (NmeaDecoder::new(), FixAssembler::new());
    let mut out = Vec::new();
    let mut buf = [0u8; 512];
    for k in 1..=(duration_s * 1000.0) as usize {
        let t_s = k as f64 * 0.001;
        for &(at_s, state) in events {
            if (at_s - t_s).abs() < 0.0005 {
                rx.set_state(state, t_s);
            }
        }
        rx.tick(t_s, pose, 0.0, pose.x_m);
        let n = robot_end.try_read(&mut buf);
        decoder.push(&buf[..n], |sentence| {
            assembler.push(sentence, |epoch| out.push((t_s, epoch)));
        });
    }
    out
}

fn pose() -> Pose {
    Pose {
        x_m: 30.0,
        y_m: 2.0,
        heading_rad: 0.3,
    }
}

#[test]
fn ten_fixes_a_second_of_the_antenna_within_centimetres_after_the_latency() {
    let params = SimParams::default().sanitized();
    let got = fixes(&params, &pose(), 10.0, &[]);
    assert!((97..=101).contains(&got.len()), "{} epochs", got.len());
    let frame = LocalFrame::new(Geodetic {
        lat_deg: 52.0,
        lon_deg: 5.66,
        height_m: 0.0,
    });
    // The antenna 0.5 m ahead of the rear axle along the heading.
    let (east_m, north_m) = pose().point_ahead(0.5);
    let mut errors_m = Vec::new();
    // The first epoch waits for the second to begin: the decoder's assembler learns
    // then which sentences an epoch has.
    for (arrived_s, epoch) in got.iter().skip(1) {
        let Epoch::Fix(fix) = epoch else {
            panic!("no fix in RTK fixed: {epoch:?}")
        };
        assert_eq!(fix.quality, FixQuality::RtkFixed);
        // The epoch's time is its capture (printed to 10 ms, the step is 1 ms); it
        // arrives 50 ms later.
        let captured_s = fix.utc_s_of_day - START_UTC_S;
        assert!(
            (arrived_s - captured_s - 0.05).abs() < 0.0035,
            "{arrived_s} {captured_s}"
        );
        let e = frame.to_enu(Geodetic {
            lat_deg: fix.lat_deg,
            lon_deg: fix.lon_deg,
            height_m: 0.0,
        });
        errors_m.push((e.east_m - east_m).hypot(e.north_m - north_m));
    }
    let rms_m = (errors_m.iter().map(|e| e * e).sum::<f64>() / errors_m.len() as f64).sqrt();
    assert!((0.005..0.04).contains(&rms_m), "RTK fixed error {rms_m} m");
}

#[test]
fn events_change_the_solution_and_a_lost_one_sends_no_position() {
    let params = SimParams::default().sanitized();
    let events = [
        (2.0, GnssState::Float),
        (4.0, GnssState::Lost),
        (6.0, GnssState::Fixed),
    ];
    let got = fixes(&params, &pose(), 8.0, &events);
    let quality_at = |t_s: f64| {
        got.iter()
            .find(|(arrived_s, _)| *arrived_s > t_s)
            .map(|(_, e)| match e {
                Epoch::Fix(f) => Some(f.quality),
                Epoch::NoFix { .. } => None,
            })
            .unwrap()
    };
    assert_eq!(quality_at(1.0), Some(FixQuality::RtkFixed));
    assert_eq!(quality_at(3.0), Some(FixQuality::RtkFloat));
    assert_eq!(quality_at(5.0), None);
    assert_eq!(quality_at(7.0), Some(FixQuality::RtkFixed));
}

//! Tests of the simulated camera computer, driven step by step from a fixed pose.

use super::*;
use crate::camproto::{Decoder, Frame};
use crate::sim::params::RowShape;
use crate::sim::pipe::byte_pipe;

const STEP_S: f64 = 0.001;

/// A camera computer, the robot computer's end of its pipe, and a clock.
struct Rig {
    camera: CameraComputer,
    robot_end: PipeEnd,
    field: Field,
    tier: FieldTier,
    pose: Pose,
    steps: u64,
}

impl Rig {
    fn new(params: SimParams) -> Rig {
        let params = params.sanitized();
        let (camera_end, robot_end) = byte_pipe(4096);
        Rig {
            camera: CameraComputer::new(&params, camera_end),
            robot_end,
            field: Field::new(&params),
            tier: FieldTier::new(&params, params.row_length_m),
            // 5 cm left of the row, 10 m along it.
            pose: Pose {
                x_m: 10.0,
                y_m: 0.05,
                heading_rad: 0.0,
            },
            steps: 0,
        }
    }

    fn straight() -> Rig {
        Rig::new(SimParams {
            row: RowShape::Straight,
            ..SimParams::default()
        })
    }

    fn t_s(&self) -> f64 {
        self.steps as f64 * STEP_S
    }

    fn command(&mut self, byte: u8) {
        self.robot_end.send(&[byte]);
    }

    /// Run for `duration_s` and return every byte the camera wrote, with its arrival time.
    fn run(&mut self, duration_s: f64) -> Vec<(f64, u8)> {
        let mut out = Vec::new();
        for _ in 0..(duration_s / STEP_S).round() as usize {
            self.steps += 1;
            let t_s = self.t_s();
            // The robot stands: it has driven as far as it is along the row.
            let distance_m = self.pose.x_m;
            let (pose, field, tier) = (&self.pose, &self.field, &self.tier);
            self.camera.tick(t_s, pose, field, tier, distance_m);
            let mut buf = [0u8; 64];
            let n = self.robot_end.try_read(&mut buf);
            out.extend(buf[..n].iter().map(|&b| (t_s, b)));
        }
        out
    }
}

fn decode(bytes: &[(f64, u8)], decoder: &mut Decoder) -> Vec<(f64, Frame)> {
    bytes
        .iter()
        .filter_map(|&(t, b)| decoder.push(b).map(|f| (t, f)))
        .collect()
}

fn rows(frames: &[(f64, Frame)]) -> Vec<RowEstimate> {
    frames
        .iter()
        .filter_map(|(_, f)| match f {
            Frame::Row(est) => Some(*est),
            Frame::Pong { .. } => None,
        })
        .collect()
}

#[test]
fn silent_until_start_then_ten_frames_a_second() {
    let mut rig = Rig::straight();
    assert!(rig.run(1.0).is_empty());
    rig.command(CMD_START);
    let bytes = rig.run(10.0);
    let frames = decode(&bytes, &mut Decoder::new());
    assert!(
        (97..=100).contains(&frames.len()),
        "{} frames",
        frames.len()
    );
    assert!(rig.camera.is_streaming());
}

#[test]
fn frames_decode_and_match_the_geometry_within_noise() {
    let mut rig = Rig::new(SimParams {
        row: RowShape::Straight,
        camera_drop: 0.0,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    let mut decoder = Decoder::new();
    let estimates = rows(&decode(&rig.run(30.0), &mut decoder));
    assert_eq!(decoder.counters.crc_errors + decoder.counters.seq_gaps, 0);
    assert!(estimates.len() >= 295);
    let n = estimates.len() as f64;
    // Robot 5 cm left of the row: the row lies 5 cm to the robot's right.
    let mean_offset_m = estimates.iter().map(|e| e.offset_m).sum::<f64>() / n;
    let mean_angle_rad = estimates.iter().map(|e| e.angle_rad).sum::<f64>() / n;
    assert!(
        (mean_offset_m + 0.05).abs() < 0.003,
        "mean offset {mean_offset_m}"
    );
    assert!(mean_angle_rad.abs() < 0.0015, "mean angle {mean_angle_rad}");
    let sd_offset_m = (estimates
        .iter()
        .map(|e| (e.offset_m - mean_offset_m).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    assert!(
        (0.008..0.012).contains(&sd_offset_m),
        "offset s.d. {sd_offset_m}"
    );
    assert!(estimates.iter().all(|e| e.quality == 90));
}

#[test]
fn frames_leave_after_the_latency() {
    let mut rig = Rig::straight();
    rig.command(CMD_START);
    let bytes = rig.run(0.2);
    // Captured at the first step (1 ms), sent 80..120 ms later.
    let first_t = bytes.first().map(|&(t, _)| t).unwrap();
    assert!(
        (0.080..=0.122).contains(&first_t),
        "first byte at {first_t}"
    );
}

#[test]
fn two_percent_drop_shows_as_seq_gaps() {
    let mut rig = Rig::straight();
    rig.command(CMD_START);
    let mut decoder = Decoder::new();
    let frames = decode(&rig.run(300.0), &mut decoder);
    let gaps = decoder.counters.seq_gaps;
    let counters = rig.camera.counters();
    // Each lone drop is one gap; two drops in a row make one longer gap.
    assert!(gaps <= counters.frames_dropped && gaps * 10 >= counters.frames_dropped * 9);
    assert!(
        (25..=100).contains(&gaps),
        "{gaps} gaps in {} frames",
        frames.len()
    );
    // Every capture was sent or dropped, but the last one or two still waiting.
    let accounted = frames.len() as u64 + counters.frames_dropped;
    assert!(counters.captures - accounted <= 2);
}

#[test]
fn stop_ping_and_pong() {
    let mut rig = Rig::new(SimParams {
        camera_drop: 0.0,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    rig.run(1.0);
    rig.command(CMD_STOP);
    let after_stop = rig.run(1.0);
    assert!(after_stop.len() <= 10, "at most the frame already pending");
    rig.command(0x55); // not a command: ignored
    rig.command(CMD_PING);
    let mut decoder = Decoder::new();
    let frames = decode(&rig.run(0.01), &mut decoder);
    assert_eq!(frames.len(), 1);
    let (t, frame) = frames[0];
    assert!(t - 2.0 < 0.0015, "pong at the next step");
    assert!(
        matches!(frame, Frame::Pong { seq } if seq == 10 || seq == 11),
        "{frame:?}"
    );
    assert!(rig.run(1.0).is_empty());
}

#[test]
fn link_silent_swallows_frames_then_streams_again() {
    let mut rig = Rig::new(SimParams {
        camera_drop: 0.0,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    rig.run(1.0);
    rig.camera.silence(rig.t_s(), 2.0);
    let during = rig.run(2.0);
    assert!(during.is_empty());
    let mut decoder = Decoder::new();
    let after = decode(&rig.run(1.0), &mut decoder);
    assert!(after.len() >= 9, "streams again without a new START");
}

#[test]
fn reboot_is_silent_then_needs_start_and_restarts_seq() {
    let mut rig = Rig::new(SimParams {
        camera_drop: 0.0,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    rig.run(3.0);
    rig.camera.reboot(rig.t_s());
    rig.command(CMD_START); // while booting: not heard
    assert!(rig.run(2.5).is_empty());
    assert!(!rig.camera.is_streaming());
    rig.command(CMD_START);
    let frames = decode(&rig.run(1.0), &mut Decoder::new());
    let estimates = rows(&frames);
    assert_eq!(estimates.first().map(|e| e.seq), Some(0));
    assert!(estimates.len() >= 9);
}

#[test]
fn corruption_fails_crcs() {
    let mut rig = Rig::new(SimParams {
        camera_corrupt: 0.01,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    let mut decoder = Decoder::new();
    let frames = decode(&rig.run(60.0), &mut decoder);
    assert!(decoder.counters.crc_errors >= 20, "{:?}", decoder.counters);
    assert!(frames.len() > 450);
}

#[test]
fn past_the_row_end_quality_is_zero() {
    let mut rig = Rig::new(SimParams {
        row: RowShape::Straight,
        row_length_m: 10.5,
        ..SimParams::default()
    });
    rig.command(CMD_START);
    rig.pose.x_m = 10.0 + crate::sim::field::PLANTED_BEYOND_M; // look-ahead past the plants
    let estimates = rows(&decode(&rig.run(1.0), &mut Decoder::new()));
    assert!(!estimates.is_empty());
    assert!(
        estimates
            .iter()
            .all(|e| e.quality == 0 && e.offset_m == 0.0 && e.angle_rad == 0.0)
    );
}

#[test]
fn same_seed_same_bytes() {
    let run = |seed: u64| {
        let mut rig = Rig::new(SimParams {
            seed,
            camera_corrupt: 0.002,
            ..SimParams::default()
        });
        rig.command(CMD_START);
        rig.run(20.0)
    };
    let a = run(5);
    assert_eq!(a, run(5));
    assert_ne!(a, run(6));
}

/// Where along the row (arclength, m) the first stretch that `is` picks starts.
fn first_stretch(rig: &Rig, is: impl Fn(crate::sim::field_tier::RowAt) -> bool) -> f64 {
    (0..6000)
        .map(|k| k as f64 * 0.01)
        .find(|&s_m| is(rig.tier.row_at(s_m)))
        .expect("the realistic 60 m row has one")
}

#[test]
fn in_a_realistic_field_a_gap_repeats_the_last_row_seen_and_a_weed_patch_pulls_it_aside() {
    let mut rig = Rig::new(SimParams {
        row: RowShape::Straight,
        field: crate::sim::FieldKind::Realistic,
        tier: crate::sim::FieldTierParams {
            camera_bias_sd_m: 0.0,
            ..Default::default()
        },
        camera_drop: 0.0,
        camera_noise_offset_m: 0.0,
        camera_noise_angle_deg: 0.0,
        ..SimParams::default()
    });
    let lookahead_m = SimParams::default().camera_lookahead_m;
    let gap_s_m = first_stretch(&rig, |at| at.gap);
    rig.command(CMD_START);
    // The look-ahead line 10 cm before the gap: the row, 5 cm to the right.
    rig.pose.x_m = gap_s_m - 0.1 - lookahead_m;
    let mut decoder = Decoder::new();
    let before = rows(&decode(&rig.run(1.0), &mut decoder));
    assert!(
        before
            .iter()
            .all(|e| e.quality == 90 && (e.offset_m + 0.05).abs() < 1e-4)
    );
    // Inside the gap, 20 cm further and a little closer to the row: the last row again.
    rig.pose.x_m += 0.2;
    rig.pose.y_m = 0.02;
    let inside = rows(&decode(&rig.run(1.0), &mut decoder));
    assert!(inside.len() >= 8);
    for e in &inside[1..] {
        assert_eq!(
            (e.quality, e.offset_m),
            (40, before.last().unwrap().offset_m)
        );
    }

    let weed_s_m = first_stretch(&rig, |at| at.weed_offset_m != 0.0);
    let weed_m = rig.tier.row_at(weed_s_m + 0.5).weed_offset_m;
    rig.pose.x_m = weed_s_m + 0.5 - lookahead_m;
    let weeds = rows(&decode(&rig.run(0.5), &mut decoder));
    let last = weeds.last().unwrap();
    assert!((0.05..=0.10).contains(&weed_m.abs()));
    assert!((last.offset_m - (-0.02 + weed_m)).abs() < 1e-4, "{last:?}");
}

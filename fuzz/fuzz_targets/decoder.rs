//! Fuzz the camera-link decoder with arbitrary bytes: it must never panic, and what it
//! passes on must be physically possible (docs/camera-link.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechweed_hw::camproto::{Decoder, FRAME_LEN, Frame, MAX_ANGLE_RAD, MAX_OFFSET_M};

fuzz_target!(|data: &[u8]| {
    let mut decoder = Decoder::new();
    for &byte in data {
        if let Some(Frame::Row(estimate)) = decoder.push(byte) {
            assert!(estimate.angle_rad.abs() <= MAX_ANGLE_RAD);
            assert!(estimate.offset_m.abs() <= MAX_OFFSET_M);
            assert!(estimate.quality <= 100);
        }
    }
    let counters = decoder.counters;
    assert!(counters.frames_ok as usize * FRAME_LEN <= data.len());
});

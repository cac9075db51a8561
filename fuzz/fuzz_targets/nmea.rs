//! Fuzz the GNSS receiver's NMEA decoder and fix assembler with arbitrary bytes: they
//! must never panic, every line must be counted once, and what they pass on must be a
//! possible position (docs/gnss.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mechweed_hw::nmea::fuzz::fuzz_one(data));

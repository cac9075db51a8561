//! A technician's robot.ini from before this round's settings still reads, and gets
//! the value each new key ships with: the wiring-mistake checks' limits (safety checks
//! an older robot gets too), no mistake made on purpose, a one-contact dead-man, a
//! watchdog relay fitted, and Test's low limits.

use mechweed_core::config::{MotionFaultSettings, Settings, TestSettings, WatchdogRelay};
use mechweed_hw::sim::Miswire;

const SHIPPED: &str = include_str!("../../../config/robot.ini");

/// Every key added since the file before them (and the optional [test] section).
const NEW_KEYS: [&str; 14] = [
    "steer_wrong_way_deg",
    "steer_response_s",
    "endswitch_backoff_s",
    "drive_wrong_way_s",
    "speed_error_mps",
    "speed_error_s",
    "uncommanded_m",
    "uncommanded_deg",
    "uncommanded_settle_s",
    "miswire",
    "joystick_released",
    "watchdog_relay",
    "drive_limit_v",
    "max_speed_mps",
];

/// The shipped file without the new keys and the [test] section.
fn older() -> String {
    let mut in_test = false;
    let mut kept = String::new();
    for line in SHIPPED.lines() {
        if line.starts_with('[') {
            in_test = line.trim() == "[test]";
        }
        let key = line.split('=').next().unwrap_or("").trim();
        // [supervisor] and [joystick] have a max_speed_mps of their own: only [test]'s goes.
        let new = NEW_KEYS.contains(&key) && (key != "max_speed_mps" || in_test);
        if !in_test && !new {
            kept += line;
            kept.push('\n');
        }
    }
    kept
}

#[test]
fn a_file_from_before_the_new_keys_reads_with_each_shipped_value() {
    let older = older();
    for key in NEW_KEYS {
        let line_start = format!("\n{key} =");
        assert!(
            key == "max_speed_mps" || !older.contains(&line_start),
            "{key} still there"
        );
    }
    assert!(!older.contains("\n[test]\n"));
    let s = Settings::parse("older.ini", &older, &[]).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(s.faults.motion, MotionFaultSettings::shipped());
    assert_eq!(s.sim.miswire, Miswire::None);
    assert_eq!(s.io.joystick_released, None);
    assert_eq!(s.watchdog_relay, WatchdogRelay::Fitted);
    assert_eq!(s.test, TestSettings::shipped());
    // Read as the shipped file reads, apart from the text it came from.
    let shipped = Settings::shipped();
    assert_eq!(s.faults, shipped.faults);
    assert_eq!(s.io, shipped.io);
    assert_eq!(s.sim, shipped.sim);
}

//! [test]: the limits of mode Test, where a person sets the outputs by hand on the
//! hardware test panel with the robot on its stand. The supervisor holds them whatever
//! the panel asks (supervisor/test_mode.rs). The section is optional: a settings file
//! from before it gets the shipped limits, which are low on purpose, raised only as far
//! as its own [faults] encoder_stuck_v needs (so that the older file still starts).

use super::reader::Reader;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TestSettings {
    /// No drive amplifier gets more than this in Test, V (either sign).
    pub drive_limit_v: f64,
    /// A drive wheel turning faster than this in Test gets 0 V until it slows, m/s.
    pub max_speed_mps: f64,
}

impl TestSettings {
    /// The values shipped in config/robot.ini, for a file without [test]: a free wheel
    /// at 3 V turns at about 0.36 m/s with the shipped motor model (kff 8.33 V per m/s),
    /// and 3 V is above [faults] encoder_stuck_v, so a dead encoder is still found.
    pub fn shipped() -> TestSettings {
        TestSettings {
            drive_limit_v: 3.0,
            max_speed_mps: 0.5,
        }
    }
}

/// A file's own encoder limit above the shipped drive limit gets a drive limit this far
/// above it, V: enough for the encoder check to look.
const ABOVE_ENCODER_STUCK_V: f64 = 0.5;

/// [test], or for a file without it the shipped limits (see the file's head).
pub(super) fn load(r: &mut Reader, faults: &super::FaultSettings) -> TestSettings {
    let s = "test";
    if !r.sections().iter().any(|name| name == s) {
        let shipped = TestSettings::shipped();
        let needed_v = (faults.encoder_stuck_v + ABOVE_ENCODER_STUCK_V).min(10.0);
        return TestSettings {
            drive_limit_v: shipped.drive_limit_v.max(needed_v),
            ..shipped
        };
    }
    TestSettings {
        drive_limit_v: r.f64(s, "drive_limit_v", 0.0, 10.0),
        max_speed_mps: r.f64(s, "max_speed_mps", 0.0, 3.0),
    }
}

/// At or below [faults] encoder_stuck_v the encoder check never looks in Test, and the
/// speed limit reads the same encoders: a dead one would go unseen.
pub(super) fn check(s: &super::Settings, r: &mut Reader) {
    let keys = [("test", "drive_limit_v"), ("faults", "encoder_stuck_v")];
    let (limit_v, stuck_v) = (s.test.drive_limit_v, s.faults.encoder_stuck_v);
    if limit_v <= stuck_v && r.all_read(&keys) {
        r.cross_error(
            &keys,
            format!(
                "[test] drive_limit_v = {limit_v} is not above [faults] encoder_stuck_v = {stuck_v}: in Test the encoder check would never look, and a dead encoder would also blind [test] max_speed_mps. Raise drive_limit_v or lower encoder_stuck_v"
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Settings;

    #[test]
    fn a_file_without_test_gets_the_low_shipped_limits() {
        let shipped = crate::config::DEFAULT_INI;
        let start = shipped.find("\n[test]").expect("robot.ini ships [test]");
        let end = shipped[start + 1..]
            .find("\n[")
            .map_or(shipped.len(), |k| start + 1 + k);
        let older = format!("{}{}", &shipped[..start], &shipped[end..]);
        let settings = Settings::parse("older.ini", &older, &[]).unwrap();
        assert_eq!(settings.test, super::TestSettings::shipped());
        assert!(settings.test.drive_limit_v <= 3.0);
        // An older file whose encoder limit is above the shipped drive limit still starts,
        // with a drive limit the encoder check can see.
        let stiff = ["faults.encoder_stuck_v=4".to_string()];
        let settings = Settings::parse("older.ini", &older, &stiff).unwrap();
        assert_eq!(settings.test.drive_limit_v, 4.5);
    }

    #[test]
    fn limits_beyond_the_amplifiers_are_refused_naming_the_key() {
        let over = ["test.drive_limit_v=12".to_string()];
        let errors = Settings::parse("robot.ini", crate::config::DEFAULT_INI, &over).unwrap_err();
        let text = format!("{errors:?}");
        assert!(text.contains("[test] drive_limit_v"), "{text}");
        let blind = ["test.drive_limit_v=2".to_string()];
        let errors = Settings::parse("robot.ini", crate::config::DEFAULT_INI, &blind).unwrap_err();
        let text = format!("{errors:?}");
        assert!(text.contains("encoder_stuck_v = 2"), "{text}");
    }
}

//! [faults]: the limits of the checks that see a wheel or the steering move the wrong
//! way, too fast, or with no command at all (faults/motion.rs), which is how wiring
//! mistakes show. Each key is optional, so that a settings file from before these
//! checks gets the shipped values below; why each value is what it is, is said there.

use super::reader::Reader;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionFaultSettings {
    /// The steering moving this far against the way it is driven is the fault, deg.
    pub steer_wrong_way_deg: f64,
    /// ... once it has been driven the same way this long (the motor's own lag), s.
    pub steer_response_s: f64,
    /// Driven off a closed end switch this long, the steering encoder must show it
    /// moving off, s.
    pub endswitch_backoff_s: f64,
    /// A drive wheel turning against its reference this long is the fault, s.
    pub drive_wrong_way_s: f64,
    /// A drive wheel's speed this far from its reference ...
    pub speed_error_mps: f64,
    /// ... for this long is the fault, s.
    pub speed_error_s: f64,
    /// Standing, a wheel moving this far with no volts commanded is the fault, m.
    pub uncommanded_m: f64,
    /// Standing, the steering turning this far with no volts commanded is the fault, deg.
    pub uncommanded_deg: f64,
    /// The wheels and the steering may still coast this long after their last volts, s.
    pub uncommanded_settle_s: f64,
}

impl MotionFaultSettings {
    /// The shipped values (config/robot.ini says the same with its reasons).
    pub fn shipped() -> MotionFaultSettings {
        MotionFaultSettings {
            // Twice the potentiometer's noise after its filter, and a tenth of the way
            // from the centre to an end switch: a reversed steering at full volts covers
            // it in about 0.05 s (60 deg/s on the simulated robot).
            steer_wrong_way_deg: 2.0,
            // Three times the simulated steering's lag (0.05 s): a wheel still turning
            // the old way after its volts changed sign is not turning the wrong way.
            steer_response_s: 0.15,
            // At 10 V the steering turns 60 deg/s: in 0.5 s it is far off any switch.
            endswitch_backoff_s: 0.5,
            // Five speed filter times: a wheel rolling back for a moment as its brake
            // lets go on a slope is not a wiring mistake.
            drive_wrong_way_s: 0.2,
            // A wheel that follows its reference is within a few cm/s of it; a quarter
            // of the shipped autonomous speed (0.5 m/s) is far from it.
            speed_error_mps: 0.25,
            speed_error_s: 0.5,
            // Brakes on, a wheel moves no more than its encoder's play.
            uncommanded_m: 0.02,
            uncommanded_deg: 1.0,
            // The spring brakes stop a wheel within [sim] brake_stop_s (0.3 s).
            uncommanded_settle_s: 0.5,
        }
    }
}

/// [faults]' motion keys, each the shipped value where the file does not have it.
pub(super) fn load(r: &mut Reader) -> MotionFaultSettings {
    let d = MotionFaultSettings::shipped();
    let mut key = |name: &str, min: f64, max: f64, shipped: f64| {
        let there = r.keys("faults").iter().any(|k| k == name);
        if there {
            r.f64("faults", name, min, max)
        } else {
            shipped
        }
    };
    MotionFaultSettings {
        steer_wrong_way_deg: key("steer_wrong_way_deg", 0.5, 10.0, d.steer_wrong_way_deg),
        steer_response_s: key("steer_response_s", 0.01, 1.0, d.steer_response_s),
        endswitch_backoff_s: key("endswitch_backoff_s", 0.05, 3.0, d.endswitch_backoff_s),
        drive_wrong_way_s: key("drive_wrong_way_s", 0.02, 1.0, d.drive_wrong_way_s),
        speed_error_mps: key("speed_error_mps", 0.05, 3.0, d.speed_error_mps),
        speed_error_s: key("speed_error_s", 0.05, 3.0, d.speed_error_s),
        uncommanded_m: key("uncommanded_m", 0.001, 1.0, d.uncommanded_m),
        uncommanded_deg: key("uncommanded_deg", 0.1, 10.0, d.uncommanded_deg),
        uncommanded_settle_s: key("uncommanded_settle_s", 0.0, 5.0, d.uncommanded_settle_s),
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Settings;

    #[test]
    fn a_file_without_the_motion_keys_gets_the_shipped_values_and_a_bad_one_is_named() {
        let shipped = crate::config::DEFAULT_INI;
        let older: String = shipped
            .lines()
            .filter(|line| !line.starts_with("steer_wrong_way_deg"))
            .map(|line| format!("{line}\n"))
            .collect();
        let settings = Settings::parse("older.ini", &older, &[]).unwrap();
        assert_eq!(
            settings.faults.motion,
            super::MotionFaultSettings::shipped()
        );
        let bad = ["faults.speed_error_s=9".to_string()];
        let errors = Settings::parse("robot.ini", shipped, &bad).unwrap_err();
        let text = format!("{errors:?}");
        assert!(text.contains("speed_error_s"), "{text}");
    }
}

use super::*;
use crate::config::Settings;

fn fix(utc_s: f64, quality: FixQuality, age_s: Option<f32>) -> Fix {
    Fix {
        utc_s_of_day: utc_s,
        lat_deg: 52.0,
        lon_deg: 5.66,
        altitude_m: None,
        quality,
        satellites: Some(12),
        hdop: Some(0.8),
        correction_age_s: age_s,
        sd_east_m: None,
        sd_north_m: None,
        speed_mps: None,
        course_deg: None,
    }
}

fn gnss() -> GnssSettings {
    Settings::shipped().gnss
}

#[test]
fn an_epoch_no_later_than_the_last_is_not_admitted_and_says_so() {
    let (mut checks, g) = (FixChecks::default(), gnss());
    assert!(checks.admit(&fix(100.0, FixQuality::RtkFixed, Some(1.0)), &g));
    // The same epoch again, and one from before it (a buffered sentence sent late).
    assert!(!checks.admit(&fix(100.0, FixQuality::RtkFixed, Some(1.0)), &g));
    assert!(!checks.admit(&fix(99.9, FixQuality::RtkFixed, Some(1.0)), &g));
    assert_eq!(checks.trouble, NOT_LATER);
    assert!(checks.admit(&fix(100.1, FixQuality::RtkFixed, Some(1.0)), &g));
    assert!(!checks.admit(&fix(f64::NAN, FixQuality::RtkFixed, Some(1.0)), &g));
    // Midnight: 23:59:59.9 then 00:00:00.0 is later.
    let mut checks = FixChecks::default();
    assert!(checks.admit(&fix(86_399.9, FixQuality::RtkFixed, Some(1.0)), &g));
    assert!(checks.admit(&fix(0.0, FixQuality::RtkFixed, Some(1.0)), &g));
    assert!(!checks.admit(&fix(86_399.9, FixQuality::RtkFixed, Some(1.0)), &g));
}

#[test]
fn a_fix_with_corrections_older_than_the_limit_is_not_admitted() {
    let (mut checks, g) = (FixChecks::default(), gnss());
    let limit = g.max_correction_age_s as f32;
    assert!(!checks.admit(&fix(1.0, FixQuality::RtkFixed, Some(limit + 0.5)), &g));
    assert_eq!(checks.trouble, OLD_CORRECTIONS);
    assert!(checks.admit(&fix(1.1, FixQuality::RtkFixed, Some(limit)), &g));
    // A receiver that gives no age is judged by its quality alone.
    assert!(checks.admit(&fix(1.2, FixQuality::RtkFixed, None), &g));
    // An untrusted quality is not admitted however young its corrections.
    assert!(!checks.admit(&fix(1.3, FixQuality::Gps, Some(0.0)), &g));
    assert_eq!(checks.trouble, NO_TRUSTED_FIX);
}

#[test]
fn a_fix_the_gate_rejected_is_not_heard() {
    let (mut checks, g) = (FixChecks::default(), gnss());
    let good = fix(1.0, FixQuality::RtkFixed, Some(1.0));
    assert!(!checks.heard(&good, false, 0.0, true, &g));
    assert_eq!(checks.trouble, REJECTED);
    assert!(checks.heard(&good, true, 0.0, true, &g));
}

#[test]
fn float_without_the_camera_is_heard_only_within_its_hold_past_the_last_fixed_fix() {
    let (mut checks, g) = (FixChecks::default(), gnss());
    let float = fix(1.0, FixQuality::RtkFloat, Some(1.0));
    // Float from the start: no fixed fix to hold from.
    assert!(!checks.heard(&float, true, 0.0, false, &g));
    assert_eq!(checks.trouble, FLOAT_TOO_LONG);
    assert!(checks.heard(&fix(1.0, FixQuality::RtkFixed, None), true, 10.0, false, &g));
    assert!(checks.heard(&float, true, 10.0 + g.float_hold_m, false, &g));
    assert!(!checks.heard(&float, true, 10.1 + g.float_hold_m, false, &g));
    // The camera beside it confirms it: heard however long it floats.
    assert!(checks.heard(&float, true, 50.0, true, &g));
    assert!(degraded(FixQuality::RtkFloat) && !degraded(FixQuality::RtkFixed));
}

#[test]
fn a_new_run_judges_float_from_its_own_first_fixed_fix() {
    // Fixed at the end of the last run, float from the start of this one: the last run's
    // fixed fix must not let this run's float steer alone.
    let (mut checks, g) = (FixChecks::default(), gnss());
    assert!(checks.heard(&fix(1.0, FixQuality::RtkFixed, None), true, 10.0, false, &g));
    checks.reset();
    let float = fix(2.0, FixQuality::RtkFloat, Some(1.0));
    assert!(!checks.heard(&float, true, 10.5, false, &g));
}

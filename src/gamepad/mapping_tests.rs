use std::time::{Duration, Instant};

use evdev::EventType;
use mechweed_hw::Inputs;

use super::*;
use crate::config::Settings;
use crate::steer::joystick;

/// A pad with the shipped settings: speed on ABS_Y (negative forward), steer on ABS_X,
/// dead-man BTN_TL, 1 s time-out, axes -32768..32767 like most USB pads.
fn shipped() -> (Pad, Settings) {
    let s = Settings::shipped();
    (Pad::new(PadMap::new(&s.gamepad, &s.joystick)), s)
}

fn opened(speed: i32, steer: i32, held: bool) -> Opened {
    let range = AxisRange {
        min: -32768,
        max: 32767,
    };
    Opened {
        speed: (range, speed),
        steer: (range, steer),
        deadman_held: held,
    }
}

fn ms(t0: Instant, ms: u64) -> Instant {
    t0 + Duration::from_millis(ms)
}

fn press(pad: &mut Pad, held: bool, at: Instant) {
    let value = i32::from(held);
    pad.event(EventType::KEY, KeyCode::BTN_TL.code(), value, at);
}

fn axis(pad: &mut Pad, code: AbsoluteAxisCode, value: i32, at: Instant) {
    pad.event(EventType::ABSOLUTE, code.0, value, at);
}

/// What steer/joystick.rs asks for from the pad's joystick: (speed m/s, angle deg).
fn command(pad: &Pad, s: &Settings, now: Instant) -> (f64, f64) {
    let j = pad.joystick(now);
    let inputs = Inputs {
        joystick_steer_v: j.steer_v,
        joystick_speed_v: j.speed_v,
        joystick_enable: j.enable,
        ..Inputs::default()
    };
    let (speed, angle) = joystick::command(&inputs, &s.joystick, 0.0);
    (speed, angle.to_degrees())
}

#[test]
fn the_sticks_become_the_analog_joysticks_volts_with_its_directions() {
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    press(&mut pad, true, ms(t0, 10));
    // Left stick fully forward (most pads read negative) and fully right.
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 20));
    axis(&mut pad, AbsoluteAxisCode::ABS_X, 32767, ms(t0, 30));
    let j = pad.joystick(ms(t0, 40));
    assert!(j.enable, "{j:?}");
    assert!((j.speed_v - s.joystick.full_scale_v).abs() < 1e-3, "{j:?}");
    assert!((j.steer_v - s.joystick.full_scale_v).abs() < 1e-3, "{j:?}");
    // Full forward is the joystick's top speed; full right is the largest angle to the
    // right (angles are positive to the left).
    let (speed, angle) = command(&pad, &s, ms(t0, 40));
    assert!((speed - s.joystick.max_speed_mps).abs() < 1e-3, "{speed}");
    assert!((angle + s.joystick.max_angle_deg).abs() < 1e-2, "{angle}");
    // Back and left: reverse, and to the left.
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, 16384, ms(t0, 50));
    axis(&mut pad, AbsoluteAxisCode::ABS_X, -32768, ms(t0, 60));
    let (speed, angle) = command(&pad, &s, ms(t0, 70));
    assert!(speed < -0.3 * s.joystick.max_speed_mps, "{speed}");
    assert!((angle - s.joystick.max_angle_deg).abs() < 1e-2, "{angle}");
}

#[test]
fn the_directions_follow_the_settings() {
    let mut s = Settings::shipped();
    s.gamepad.speed_forward_negative = false;
    s.gamepad.steer_right_negative = true;
    s.gamepad.steer_axis = AbsoluteAxisCode::ABS_RX;
    let mut pad = Pad::new(PadMap::new(&s.gamepad, &s.joystick));
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    press(&mut pad, true, ms(t0, 10));
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, 32767, ms(t0, 20));
    // ABS_X is no longer the steer axis; ABS_RX pushed right reads negative.
    axis(&mut pad, AbsoluteAxisCode::ABS_X, 32767, ms(t0, 30));
    let j = pad.joystick(ms(t0, 40));
    assert!(j.speed_v > 3.9 && j.steer_v.abs() < 1e-3, "{j:?}");
    axis(&mut pad, AbsoluteAxisCode::ABS_RX, -32768, ms(t0, 50));
    assert!(pad.joystick(ms(t0, 60)).steer_v > 3.9);
}

#[test]
fn a_stick_near_the_centre_is_in_the_analog_dead_band_and_a_trigger_range_is_centred() {
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    // A worn stick resting 3 % off centre does not creep.
    pad.connect(opened(-1000, 1000, false), t0);
    press(&mut pad, true, ms(t0, 10));
    assert_eq!(command(&pad, &s, ms(t0, 20)), (0.0, 0.0));
    // An axis reporting 0..255 (many pads' second stick) is centred on 127.5.
    let range = AxisRange { min: 0, max: 255 };
    assert!(range.unit(128).abs() < 0.01 && (range.unit(255) - 1.0).abs() < 1e-9);
    assert!((range.unit(0) + 1.0).abs() < 1e-9);
}

#[test]
fn nothing_moves_without_the_dead_man_button() {
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 5));
    assert_eq!(pad.joystick(ms(t0, 10)).dead_man, DeadMan::Released);
    assert_eq!(command(&pad, &s, ms(t0, 10)).0, 0.0);
    press(&mut pad, true, ms(t0, 20));
    assert!(command(&pad, &s, ms(t0, 30)).0 > 0.7);
    press(&mut pad, false, ms(t0, 40));
    assert!(!pad.joystick(ms(t0, 50)).enable);
    // The kernel's auto-repeat (value 2) of a held button is still held.
    pad.event(EventType::KEY, KeyCode::BTN_TL.code(), 1, ms(t0, 60));
    pad.event(EventType::KEY, KeyCode::BTN_TL.code(), 2, ms(t0, 70));
    assert!(pad.joystick(ms(t0, 80)).enable);
    // Another button is not the dead-man.
    press(&mut pad, false, ms(t0, 90));
    pad.event(EventType::KEY, KeyCode::BTN_TR.code(), 1, ms(t0, 100));
    assert!(!pad.joystick(ms(t0, 110)).enable);
}

#[test]
fn a_silent_pad_counts_as_released_and_needs_a_new_press() {
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 50));
    press(&mut pad, true, ms(t0, 100));
    // Driving full forward, then nothing more from the pad (out of range).
    assert!(pad.joystick(ms(t0, 1000)).enable);
    assert!(
        pad.joystick(ms(t0, 1100)).enable,
        "exactly at the time-out: still held"
    );
    let j = pad.joystick(ms(t0, 1101));
    assert!(
        !j.enable && matches!(j.dead_man, DeadMan::Silent(_)),
        "{j:?}"
    );
    assert_eq!(command(&pad, &s, ms(t0, 1101)).0, 0.0);
    // Back in range, still held: not until released and pressed again.
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32000, ms(t0, 3000));
    assert_eq!(pad.joystick(ms(t0, 3010)).dead_man, DeadMan::ReleaseFirst);
    press(&mut pad, false, ms(t0, 3100));
    press(&mut pad, true, ms(t0, 3200));
    assert!(pad.joystick(ms(t0, 3210)).enable);
}

#[test]
fn a_silence_without_the_button_held_needs_only_a_press() {
    let (mut pad, _) = shipped();
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    // Standing for a minute, the operator's hands off the pad.
    assert!(!pad.joystick(ms(t0, 60_000)).enable);
    press(&mut pad, true, ms(t0, 60_000));
    assert!(pad.joystick(ms(t0, 60_010)).enable);
}

#[test]
fn unplugged_the_pad_stops_the_robot_and_plugged_in_held_it_waits_for_a_new_press() {
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    assert_eq!(pad.joystick(t0).dead_man, DeadMan::NotConnected);
    pad.connect(opened(0, 0, false), t0);
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 5));
    press(&mut pad, true, ms(t0, 10));
    assert!(command(&pad, &s, ms(t0, 20)).0 > 0.7);
    pad.disconnect();
    let j = pad.joystick(ms(t0, 30));
    assert_eq!(j.dead_man, DeadMan::NotConnected);
    assert_eq!((j.enable, j.speed_v, j.steer_v), (false, 0.0, 0.0));
    // Plugged back in with the button held and the stick forward: it stands.
    pad.connect(opened(-32768, 0, true), ms(t0, 2000));
    assert_eq!(pad.joystick(ms(t0, 2010)).dead_man, DeadMan::ReleaseFirst);
    assert_eq!(command(&pad, &s, ms(t0, 2010)).0, 0.0);
    press(&mut pad, false, ms(t0, 2100));
    press(&mut pad, true, ms(t0, 2200));
    // Pressed again, but the stick has been forward since it was plugged in.
    assert_eq!(pad.joystick(ms(t0, 2210)).dead_man, DeadMan::NotCentred);
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, 0, ms(t0, 2300));
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 2400));
    assert!(command(&pad, &s, ms(t0, 2410)).0 > 0.7);
    assert_eq!(pad.connections, 2);
}

#[test]
fn an_axis_resting_at_its_end_never_drives() {
    // A trigger (0..255, resting at 0) named as the speed axis by mistake reads full
    // deflection at rest: the pad must not drive on it.
    let (mut pad, s) = shipped();
    let t0 = Instant::now();
    let trigger = AxisRange { min: 0, max: 255 };
    let mut at_rest = opened(0, 0, false);
    at_rest.speed = (trigger, 0);
    pad.connect(at_rest, t0);
    press(&mut pad, true, ms(t0, 10));
    let j = pad.joystick(ms(t0, 20));
    assert_eq!(
        (j.dead_man, j.enable),
        (DeadMan::NotCentred, false),
        "{j:?}"
    );
    assert_eq!(command(&pad, &s, ms(t0, 20)).0, 0.0);
}

#[test]
fn a_release_the_kernel_dropped_is_taken_from_its_state() {
    let (mut pad, _) = shipped();
    let t0 = Instant::now();
    pad.connect(opened(0, 0, false), t0);
    press(&mut pad, true, ms(t0, 10));
    axis(&mut pad, AbsoluteAxisCode::ABS_Y, -32768, ms(t0, 20));
    assert!(pad.joystick(ms(t0, 30)).enable);
    // The release and the stick's return were among the events the kernel dropped;
    // its state says the button is up and the stick in the middle.
    pad.reconcile(opened(0, 0, false));
    let j = pad.joystick(ms(t0, 40));
    assert!(!j.enable && j.speed_v.abs() < 0.01, "{j:?}");
    // The kernel's state is no sign of life: a silent pad stays silent.
    press(&mut pad, true, ms(t0, 50));
    pad.reconcile(opened(0, 0, true));
    assert!(matches!(
        pad.joystick(ms(t0, 2000)).dead_man,
        DeadMan::Silent(_)
    ));
}

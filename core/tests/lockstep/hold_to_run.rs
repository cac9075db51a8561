//! Hold-to-run in Test, through the emulated I/O cards: what the test panel sets
//! reaches the amplifiers only while a person holds a control (the panel's Hold to run
//! or the joystick's dead-man), and is 0 V in the tick after it is let go. Each test
//! starts from the unsafe state: the panel asking for volts on a drive with its brake
//! released, and nobody holding anything.

use crate::common;

use common::settings_with;
use mechweed_core::state::modes::{Mode, Request};
use mechweed_core::threads::lockstep::{Io, Lockstep};
use mechweed_hw::Outputs;

/// What the panel asks: relay closed, left brake released, left drive at 2.5 V.
const ASKED: Outputs = Outputs {
    amp_left_v: 2.5,
    main_power_on: true,
    brake_release_left: true,
    ..Outputs::SAFE
};

/// In Test through the cards, powered up, the panel's outputs asked, nobody holding.
fn in_test_nobody_holding(events: &str) -> Lockstep {
    let s = settings_with(events, &[]);
    let mut sim = Lockstep::with_io(&s, Mode::Halt, Io::cards(&s).unwrap());
    sim.run_for(2.5);
    assert_eq!(sim.supervisor.mode(), Mode::Test);
    sim.request(Request::TestOutputs(ASKED)).unwrap();
    sim
}

/// The left drive's volts and brake at the robot, as the cards wrote them.
fn at_the_robot(sim: &Lockstep) -> (f64, bool) {
    let out = sim.robot.outputs();
    (out.amp_left_v, out.brake_release_left)
}

fn near(volts: f64, want_v: f64) -> bool {
    // The DDA06's 12-bit steps on +-10 V are 4.9 mV.
    (volts - want_v).abs() < 0.01
}

#[test]
fn the_panel_moves_nothing_until_held_and_stops_in_the_tick_after_release() {
    let mut sim = in_test_nobody_holding("0.5 power_up, 2 mode test");
    for _ in 0..30 {
        sim.tick();
        let (volts, brake_off) = at_the_robot(&sim);
        assert!(near(volts, 0.0), "not held, yet {volts} V");
        assert!(!brake_off, "a driven wheel's brake released without a hold");
    }
    // Held (the GUI renews the hold every frame): the panel's volts reach the drive.
    for _ in 0..50 {
        sim.request(Request::TestHold(true)).unwrap();
        sim.tick();
    }
    let (volts, brake_off) = at_the_robot(&sim);
    assert!(near(volts, ASKED.amp_left_v), "held, {volts} V");
    assert!(brake_off);
    assert!(sim.robot.truth().speed_mps.abs() > 0.01, "the wheel turns");
    // Let go: 0 V and the brake on in the very next tick.
    sim.request(Request::TestHold(false)).unwrap();
    sim.tick();
    let (volts, brake_off) = at_the_robot(&sim);
    assert!(near(volts, 0.0), "let go, yet {volts} V");
    assert!(!brake_off);
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
}

#[test]
fn a_hold_that_is_not_renewed_ends_by_itself() {
    // A GUI that stops with the button down sends no release.
    let mut sim = in_test_nobody_holding("0.5 power_up, 2 mode test");
    sim.request(Request::TestHold(true)).unwrap();
    sim.tick();
    assert!(near(at_the_robot(&sim).0, ASKED.amp_left_v));
    sim.run_for(0.3);
    assert!(
        near(at_the_robot(&sim).0, 0.0),
        "the hold outlived its renewal"
    );
}

#[test]
fn the_dead_man_on_the_cards_is_a_hold_too() {
    let mut sim = in_test_nobody_holding("0.5 power_up, 2 mode test, 3 deadman on, 4 deadman off");
    sim.run_for(0.4); // to 2.9 s
    assert!(near(at_the_robot(&sim).0, 0.0));
    sim.run_for(0.5); // to 3.4 s: held since 3 s
    assert!(near(at_the_robot(&sim).0, ASKED.amp_left_v));
    while sim.now_s() < 4.0 {
        sim.tick();
    }
    // The dead-man is read in the tick at 4 s (or the next): 0 V within two ticks.
    sim.tick();
    sim.tick();
    assert!(near(at_the_robot(&sim).0, 0.0), "dead-man let go");
}

#[test]
fn a_dead_man_already_held_as_test_begins_is_no_hold_until_let_go_and_pressed_again() {
    // Taped down, or still held from driving in joystick mode before Test.
    let events = "0.5 power_up, 1 deadman on, 2 mode test, 3 deadman off, 3.5 deadman on";
    let mut sim = in_test_nobody_holding(events);
    sim.run_for(0.4); // to 2.9 s: the dead-man down since before Test
    assert!(
        near(at_the_robot(&sim).0, 0.0),
        "a hold from before Test counted"
    );
    sim.run_for(1.0); // to 3.9 s: let go at 3 s, pressed again at 3.5 s
    assert!(near(at_the_robot(&sim).0, ASKED.amp_left_v));
}

#[test]
fn held_the_drives_stay_within_the_test_voltage_limit() {
    let mut sim = in_test_nobody_holding("0.5 power_up, 2 mode test");
    let limit_v = 3.0;
    assert_eq!(
        settings_with("", &[]).test.drive_limit_v,
        limit_v,
        "the shipped [test] drive_limit_v"
    );
    let over = Outputs {
        amp_left_v: 8.0,
        ..ASKED
    };
    sim.request(Request::TestOutputs(over)).unwrap();
    for _ in 0..10 {
        sim.request(Request::TestHold(true)).unwrap();
        sim.tick();
    }
    assert!(
        near(at_the_robot(&sim).0, limit_v),
        "{}",
        at_the_robot(&sim).0
    );
}

//! A latched fault says what to check, and that it came back when a power-up did not
//! mend it; a pressed e-stop shows in the header whatever fault is latched. Over the
//! real controller on the simulated robot (a left wheel encoder that stops counting
//! while the robot drives, as in the field), and as `watch` shows the robot's words.

use std::time::Duration;

use mechweed::gui::remote::Flow;
use mechweed::state::fault_cause::FaultCause;
use mechweed::state::modes::Mode;
use mechweed::state::status::PowerState;
use mechweed_hw::EncoderId;

use crate::gui_harness::{Gui, gui_with};
use crate::watch_harness::{shows, watching};

const ENCODER_FAULT: &str = "FAULT: left wheel encoder does not count while its motor is driven";
const CHECK: &str = "what to check: the encoder and its cable, then Power up";
const ESTOP: &str = "E-STOP FRONT PRESSED";

/// From Halt: power up, drive off in Autonomous, and let the left wheel's encoder stop
/// counting (for the rest of the run) until its fault latches.
fn drive_until_the_encoder_fault(gui: &mut Gui) {
    gui.power_up();
    gui.wait_until("calibrated", |app| app.view.status.measured.calibrated);
    gui.harness.step();
    gui.click("Autonomous");
    gui.wait_until("autonomous", |app| app.view.status.mode == Mode::Autonomous);
    gui.wait_until("the robot moves", |app| app.view.truth.distance_m > 0.2);
    gui.click("Left encoder stuck");
    gui.wait_until("a fault", |app| app.view.status.mode == Mode::Fault);
    let fault = gui.harness.state().view.status.fault.expect("latched");
    assert_eq!(fault.cause, FaultCause::EncoderStuck(EncoderId::Left));
    gui.harness.step();
}

#[test]
fn an_encoder_fault_says_what_to_check_and_after_a_power_up_that_it_came_back() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    drive_until_the_encoder_fault(&mut gui);
    assert!(gui.shows(ENCODER_FAULT));
    assert!(gui.shows(CHECK), "the header says what to check");
    assert!(!gui.shows("came back"), "the first time it did not");
    // A mode button's reason is more than "power up to clear it".
    assert!(gui.shows("power up to clear it; what to check: the encoder and its cable"));

    // Power up is accepted (nothing stands in its way), and the encoder still does not
    // count: driving off again, the same fault latches at once.
    gui.power_up();
    gui.wait_until("calibrated again", |app| {
        app.view.status.measured.calibrated && app.view.status.power == PowerState::On
    });
    gui.harness.step();
    gui.click("Autonomous");
    gui.wait_until("the fault again", |app| {
        app.view
            .status
            .fault
            .is_some_and(|f| f.came_back_after_s.is_some())
    });
    gui.harness.step();
    assert!(gui.shows(ENCODER_FAULT));
    assert!(gui.shows(" s after power-up: its cause is still there, check again"));
    assert!(gui.shows("came back "));
    assert!(gui.shows(CHECK), "what to check, again");
    let outcome = gui.finish();
    let came_back: Vec<_> = outcome
        .faults
        .iter()
        .map(|f| f.came_back_after_s.is_some())
        .collect();
    assert_eq!(came_back, [false, true], "{:?}", outcome.faults);
}

#[test]
fn an_estop_pressed_while_another_fault_is_latched_shows_in_the_header() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    drive_until_the_encoder_fault(&mut gui);
    assert!(!gui.shows(ESTOP), "none pressed yet");
    gui.click("Press e-stop front");
    gui.wait_until("the front e-stop pressed", |app| {
        !app.view.status.inputs.estop_front_released
    });
    gui.harness.step();
    assert!(gui.shows(ESTOP), "whatever fault is latched");
    assert!(gui.shows(ENCODER_FAULT), "the first fault stays latched");
    gui.click("Release e-stops");
    gui.wait_until("released", |app| {
        app.view.status.inputs.estop_front_released
    });
    gui.harness.step();
    assert!(!gui.shows(ESTOP));
    gui.finish();
}

#[test]
fn watch_shows_what_to_check_that_it_came_back_and_a_pressed_estop() {
    let _one = crate::one_at_a_time();
    let harness = watching(Duration::from_millis(100), |flow, payload| match flow {
        Flow::Status => {
            payload["mode"] = "fault".into();
            payload["fault"] = "left wheel encoder does not count while its motor is driven".into();
            payload["fault_check"] = "the encoder and its cable, then Power up".into();
            payload["fault_came_back_after_s"] = 0.6.into();
        }
        Flow::Tick => payload["estop_front_released"] = 0.into(),
    });
    assert!(shows(&harness, ENCODER_FAULT));
    assert!(shows(&harness, CHECK));
    assert!(shows(
        &harness,
        "came back 0.6 s after power-up: its cause is still there, check again"
    ));
    assert!(shows(&harness, ESTOP));

    // A robot of before these fields: its fault, and nothing more.
    let older = watching(Duration::from_millis(100), |flow, payload| {
        if flow == Flow::Status {
            payload["mode"] = "fault".into();
            payload["fault"] = "left wheel encoder does not count while its motor is driven".into();
        }
    });
    assert!(shows(&older, ENCODER_FAULT));
    assert!(!shows(&older, "what to check"));
    assert!(!shows(&older, "came back"));
    assert!(!shows(&older, ESTOP), "its e-stops are released");
}

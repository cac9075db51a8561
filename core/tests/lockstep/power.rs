//! The motor contactor through the real supervisor on the simulated robot: power and
//! Test together, a welded contactor, and the steering's calibration after a
//! potentiometer fault.

use crate::common;

use common::{autonomous, record, settings_with};
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::{Mode, Refusal, Request};
use mechweed_core::state::status::PowerState;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::{EncoderId, Outputs};

/// What the test panel sends: the relay as given, brakes released, both wheels at `v`.
fn panel(relay: bool, v: f64) -> Outputs {
    Outputs {
        amp_left_v: v,
        amp_right_v: v,
        main_power_on: relay,
        brake_release_left: true,
        brake_release_right: true,
        ..Outputs::SAFE
    }
}

#[test]
fn power_up_then_test_keeps_power_and_the_relay_switch_is_the_power_switch() {
    // The ordinary order of a person at the test panel; it used to fault 20 ms after
    // entering Test with "motor power lost".
    // The dead-man held: the hold that lets the panel's volts reach the amplifiers.
    let s = settings_with("0.5 power_up, 3 mode test, 3.1 deadman on", &[]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    let ticks = record(&mut sim, 6.0);
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    let st = sim.supervisor.status();
    assert_eq!(st.mode, Mode::Test);
    assert_eq!(st.power, PowerState::On);
    assert!(ticks.last().unwrap().outputs.main_power_on, "relay opened");

    // Opening the relay from the panel switches power off, and is no fault.
    sim.request(Request::TestOutputs(panel(false, 0.0)))
        .unwrap();
    record(&mut sim, 0.5);
    assert_eq!(sim.supervisor.status().power, PowerState::Off);
    assert!(sim.supervisor.faults().is_empty());
    // Closing it again is a power-up, and the wheels turn.
    sim.request(Request::TestOutputs(panel(true, 3.0))).unwrap();
    record(&mut sim, 1.0);
    assert_eq!(sim.supervisor.status().power, PowerState::On);
    assert!(
        sim.robot.truth().speed_mps > 0.1,
        "the panel's volts move the wheels"
    );
    assert!(sim.supervisor.faults().is_empty());
}

#[test]
fn power_lost_in_test_is_a_fault() {
    let s = settings_with("0.5 power_up, 2 mode test, 4 power_loss", &[]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    let ticks = record(&mut sim, 5.0);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, FaultCause::MotorPowerLost);
    assert!((log[0].t_s - 4.0).abs() < 0.02, "at {}", log[0].t_s);
    assert!(
        ticks
            .iter()
            .filter(|t| t.t_s > 4.02)
            .all(|t| t.outputs == Outputs::SAFE)
    );
}

#[test]
fn test_without_power_up_still_finds_a_stuck_encoder() {
    // No Power up: the panel closes the relay and drives the amplifiers itself. The
    // encoder check must watch that as it watches driving.
    let s = settings_with("1 mode test, 1.1 deadman on, 2 encoder_stuck left", &[]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    record(&mut sim, 1.5);
    assert_eq!(sim.supervisor.mode(), Mode::Test);
    assert_eq!(sim.supervisor.status().power, PowerState::Off);
    sim.request(Request::TestOutputs(panel(true, 4.0))).unwrap();
    record(&mut sim, 2.5);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, FaultCause::EncoderStuck(EncoderId::Left));
    assert_eq!(sim.supervisor.status().outputs, Outputs::SAFE);
}

#[test]
fn a_welded_contactor_is_a_fault_of_its_own() {
    // Standing without power, the relay open: the contacts weld and power comes on.
    let s = settings_with("2 contactor_welded", &[]);
    let drop_s = s.faults.contactor_drop_s;
    let mut sim = Lockstep::new(&s, Mode::Halt);
    let ticks = record(&mut sim, 2.0 + drop_s + 0.3);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, FaultCause::ContactorWelded);
    assert!(
        log[0].t_s >= 2.0 + drop_s - 0.02 && log[0].t_s < 2.0 + drop_s + 0.05,
        "at {}",
        log[0].t_s
    );
    assert!(ticks.last().unwrap().outputs == Outputs::SAFE);
    let refusal = sim.request(Request::PowerUp).unwrap_err().to_string();
    assert!(refusal.contains("contactor did not open"), "{refusal}");
}

#[test]
fn a_contactor_that_stays_closed_after_an_estop_blocks_power_up() {
    let s = settings_with("5 contactor_welded, 6 estop_front", &[]);
    let drop_s = s.faults.contactor_drop_s;
    let mut sim = autonomous(&s);
    record(&mut sim, 6.0 + drop_s + 0.2);
    let log = sim.supervisor.faults().to_vec();
    assert_eq!(log[0].cause, FaultCause::EstopFront, "{log:?}");
    // The e-stop opened the chain; the welded contacts keep motor power on, and the
    // status says so while the e-stop fault is latched.
    assert_eq!(
        sim.supervisor.status().standing_cause,
        Some(FaultCause::EstopFront)
    );
    sim.robot
        .apply(&mechweed_hw::sim::EventAction::EstopRelease);
    record(&mut sim, 0.2);
    assert_eq!(
        sim.supervisor.status().standing_cause,
        Some(FaultCause::ContactorWelded)
    );
    let refusal = sim.request(Request::PowerUp).unwrap_err().to_string();
    assert!(refusal.contains("contactor did not open"), "{refusal}");
}

#[test]
fn an_open_contactor_within_its_drop_time_is_no_fault() {
    // HALT from driving keeps power; a fault opens the relay and power drops at once.
    let s = settings_with("5 estop_back", &[]);
    let mut sim = autonomous(&s);
    record(&mut sim, 7.0);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, FaultCause::EstopBack);
}

#[test]
fn the_steering_is_recalibrated_at_the_power_up_after_a_potentiometer_fault() {
    // The steering encoder's coupling slips: encoder and potentiometer disagree.
    let s = settings_with("5 steer_slip 8", &[]);
    let mut sim = autonomous(&s);
    record(&mut sim, 7.0);
    let log = sim.supervisor.faults().to_vec();
    assert!(
        matches!(log[0].cause, FaultCause::PotDisagrees { .. }),
        "{log:?}"
    );
    sim.request(Request::PowerUp).expect("power up");
    // Standing, the encoder's zero is taken again from the potentiometer.
    record(&mut sim, s.supervisor.calibration_s + 0.3);
    assert!(sim.supervisor.status().measured.calibrated);
    sim.request(Request::Mode(Mode::Autonomous))
        .expect("calibrated again");
    record(&mut sim, 5.0);
    assert_eq!(
        sim.supervisor.faults().len(),
        1,
        "faulted again: {:?}",
        sim.supervisor.faults()
    );
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    let m = sim.supervisor.status().measured;
    let truth_deg = sim.robot.truth().wheel_angle_rad.to_degrees();
    assert!(
        (m.wheel_angle_rad.to_degrees() - truth_deg).abs() < 1.0,
        "encoder angle {} deg, wheel {truth_deg} deg",
        m.wheel_angle_rad.to_degrees()
    );
}

#[test]
fn a_mode_asked_while_the_contactor_closes_is_told_power_is_still_coming_on() {
    // Power up accepted, the contactor not closed yet: "press Power up first" sent
    // operators back to a button they had just pressed.
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    record(&mut sim, 0.5);
    sim.request(Request::PowerUp).expect("power up");
    record(&mut sim, 0.01);
    assert!(matches!(
        sim.supervisor.status().power,
        PowerState::Closing { .. }
    ));
    let refusal = sim
        .request(Request::Mode(Mode::Joystick))
        .unwrap_err()
        .to_string();
    assert!(refusal.contains("still coming on"), "{refusal}");
    assert!(!refusal.contains("press Power up"), "{refusal}");
}

#[test]
fn from_test_a_driving_mode_is_refused_until_halt() {
    // In Test with the relay closed and the wheels turning on the panel's volts: a
    // driving mode taken directly would hand running motors and released brakes to the
    // regulators without the stop in Halt between.
    let s = settings_with("0.5 power_up, 2 mode test, 2.1 deadman on", &[]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    record(&mut sim, 2.5);
    sim.request(Request::TestOutputs(panel(true, 3.0))).unwrap();
    record(&mut sim, 1.0);
    let st = sim.supervisor.status();
    assert_eq!((st.mode, st.power), (Mode::Test, PowerState::On));
    assert!(st.measured.calibrated);
    for wanted in [Mode::Autonomous, Mode::Joystick] {
        assert_eq!(
            sim.request(Request::Mode(wanted)),
            Err(Refusal::OnlyFromHalt(Mode::Test)),
            "Test -> {wanted}"
        );
        let ticks = record(&mut sim, 0.2);
        assert_eq!(sim.supervisor.mode(), Mode::Test);
        assert!(
            ticks.iter().all(|t| t.outputs == panel(true, 3.0)),
            "the panel's outputs changed"
        );
    }
    assert!(sim.supervisor.faults().is_empty());
    // Through Halt: whatever the panel switched stays behind, the contactor opens.
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    let ticks = record(&mut sim, 0.5);
    assert_eq!(sim.supervisor.status().power, PowerState::Off);
    assert!(ticks.iter().all(|t| t.outputs == Outputs::SAFE));
}

//! The commissioning steps of Test on the simulated robot, straight and through the
//! emulated I/O cards: each actuator's step says the right sign on a robot wired right
//! and names the mistake on one wired wrong; the voltmeter step puts the known voltage
//! on the DDA06 with the contactor open and says what each range switch would show.

use crate::common;

use common::settings_with;
use mechweed_core::state::commission::{StepReport, StepVerdict, TestStep};
use mechweed_core::state::modes::{Mode, Request};
use mechweed_core::state::status::Notice;
use mechweed_core::threads::lockstep::{Io, Lockstep};
use mechweed_hw::cards::dda06::DacRange;
use mechweed_hw::{EncoderId, Outputs};

/// In Test after a power-up, the panel's relay closed and nothing else asked.
fn in_test(miswire: &str, cards: bool) -> Lockstep {
    in_test_after("0.5 power_up, 2 mode test", miswire, cards)
}

/// In Test after `events`, the panel's relay closed.
fn in_test_after(events: &str, miswire: &str, cards: bool) -> Lockstep {
    let s = settings_with(events, &[&format!("sim.miswire={miswire}")]);
    let io = if cards {
        Io::cards(&s).unwrap()
    } else {
        Io::Direct
    };
    let mut sim = Lockstep::with_io(&s, Mode::Halt, io);
    sim.run_for(2.5);
    assert_eq!(sim.supervisor.mode(), Mode::Test);
    let relay = Outputs {
        main_power_on: true,
        ..Outputs::SAFE
    };
    sim.request(Request::TestOutputs(relay)).unwrap();
    sim.run_for(0.2);
    sim
}

/// One step of `actuator`, Hold to run held throughout (renewed as the GUI does).
fn step(sim: &mut Lockstep, actuator: EncoderId) -> StepReport {
    sim.request(Request::TestStep(TestStep::Actuator(actuator)))
        .unwrap();
    for _ in 0..100 {
        sim.request(Request::TestHold(true)).unwrap();
        sim.tick();
        if let Some(Notice::StepDone { report, .. }) = sim.supervisor.status().notice {
            return report;
        }
    }
    panic!("the step did not end");
}

#[test]
fn each_actuator_step_says_the_right_sign_and_names_the_wrong_one() {
    let cases = [
        ("none", EncoderId::Left, StepVerdict::Right),
        ("none", EncoderId::Right, StepVerdict::Right),
        ("none", EncoderId::Steer, StepVerdict::Right),
        (
            "left_amp_reversed",
            EncoderId::Left,
            StepVerdict::DriveReversed,
        ),
        (
            "left_encoder_reversed",
            EncoderId::Left,
            StepVerdict::DriveReversed,
        ),
        (
            "right_amp_reversed",
            EncoderId::Right,
            StepVerdict::DriveReversed,
        ),
        (
            "steer_amp_reversed",
            EncoderId::Steer,
            StepVerdict::SteerAmplifierReversed,
        ),
        (
            "steer_encoder_reversed",
            EncoderId::Steer,
            StepVerdict::SteerEncoderReversed,
        ),
    ];
    for cards in [false, true] {
        for (miswire, actuator, want) in cases {
            let mut sim = in_test(miswire, cards);
            let report = step(&mut sim, actuator);
            eprintln!("{miswire}, cards {cards}: {report}");
            assert_eq!(report.verdict, want, "{miswire}, cards {cards}: {report}");
            // Moved enough to tell, and no more than a step should (robot on its stand).
            let moved = report.encoder_moved.abs();
            let most = if actuator == EncoderId::Steer {
                5.0
            } else {
                0.1
            };
            assert!(moved > 0.0 && moved < most, "{report}");
            let last = sim.tick();
            assert_eq!(
                (last.amp_left_v, last.amp_right_v, last.amp_steer_v),
                (0.0, 0.0, 0.0)
            );
            assert!(
                sim.supervisor.faults().is_empty(),
                "{:?}",
                sim.supervisor.faults()
            );
        }
    }
}

#[test]
fn the_voltmeter_step_is_refused_with_the_relay_closed() {
    // The amplifiers would drive what it writes.
    let mut sim = in_test("none", true);
    let refused = sim.request(Request::TestStep(TestStep::Voltmeter));
    assert!(refused.is_err(), "{refused:?}");
}

#[test]
fn in_test_with_nothing_held_a_dda06_switched_unipolar_is_uncommanded_motion() {
    let s = settings_with("1 mode test", &["sim.miswire=dda06_unipolar"]);
    let mut sim = Lockstep::with_io(&s, Mode::Halt, Io::cards(&s).unwrap());
    sim.run_for(1.5);
    let relay = Outputs {
        main_power_on: true,
        ..Outputs::SAFE
    };
    sim.request(Request::TestOutputs(relay)).unwrap();
    sim.run_for(1.0);
    let fault = sim.supervisor.status().fault.map(|f| f.cause);
    assert!(
        matches!(
            fault,
            Some(
                mechweed_core::state::fault_cause::FaultCause::UncommandedMotion {
                    part: EncoderId::Steer,
                    ..
                }
            )
        ),
        "{fault:?}"
    );
}

#[test]
fn a_step_let_go_of_stops_at_once_and_says_so() {
    let mut sim = in_test("none", false);
    sim.request(Request::TestStep(TestStep::Actuator(EncoderId::Left)))
        .unwrap();
    for _ in 0..5 {
        sim.request(Request::TestHold(true)).unwrap();
        sim.tick();
    }
    assert!(
        sim.robot.outputs().amp_left_v > 1.0,
        "the step drives while held"
    );
    sim.request(Request::TestHold(false)).unwrap();
    sim.tick();
    assert_eq!(sim.robot.outputs().amp_left_v, 0.0);
    let Some(Notice::StepDone { report, .. }) = sim.supervisor.status().notice else {
        panic!("no report");
    };
    assert_eq!(report.verdict, StepVerdict::LetGo);
}

#[test]
fn the_voltmeter_step_writes_the_known_volts_with_the_contactor_open() {
    for miswire in ["none", "dda06_unipolar"] {
        // Never powered up: with dda06_unipolar power would be uncommanded motion.
        let s = settings_with("1 mode test", &[&format!("sim.miswire={miswire}")]);
        let mut sim = Lockstep::with_io(&s, Mode::Halt, Io::cards(&s).unwrap());
        sim.run_for(1.5);
        assert_eq!(sim.supervisor.mode(), Mode::Test);
        sim.request(Request::TestStep(TestStep::Voltmeter)).unwrap();
        let Some(Notice::Voltmeter { reading, .. }) = sim.supervisor.status().notice else {
            panic!("no reading");
        };
        let said = reading.to_string();
        sim.run_for(0.5);
        let Io::Cards(rig) = &sim.io else {
            unreachable!()
        };
        let code = rig.dda06.dac_code(0);
        assert_eq!(code, DacRange::Bipolar10.code(2.0));
        // What the emulated card's switch puts out is what the notice said it would.
        let at_switch = match miswire {
            "none" => DacRange::Bipolar10,
            _ => DacRange::Unipolar10,
        };
        let volts = at_switch.volts(code);
        assert!(said.contains(&format!("{volts:+.2} V")), "{said}");
        assert!(said.contains("+6.00 V: 0..10"), "{said}");
        let out = sim.robot.outputs();
        assert!(!out.main_power_on && !out.brake_release_left && !out.brake_release_right);
        // Stopped: 0 V again.
        sim.request(Request::TestStep(TestStep::Stop)).unwrap();
        sim.run_for(0.1);
        let Io::Cards(rig) = &sim.io else {
            unreachable!()
        };
        assert_eq!(rig.dda06.dac_code(0), 0x8000);
    }
}

//! Wiring mistakes on the simulated robot ([sim] miswire), straight and through the
//! emulated I/O cards, in Autonomous and in Joystick: each must end in its own named
//! fault with safe outputs in that tick, before the steering reaches an end switch or
//! the robot has driven 0.5 m. Each test starts from the unsafe state: the robot
//! wired wrong and about to be driven.

use crate::common;

use common::settings_with;
use mechweed_core::config::Settings;
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::Mode;
use mechweed_core::threads::lockstep::{Io, Lockstep};
use mechweed_hw::sim::Miswire;
use mechweed_hw::{EncoderId, Outputs, Side};

/// How a run with a mistake ended.
#[derive(Debug)]
struct Ended {
    fault: Option<FaultCause>,
    /// From the first volts on the mistaken part to the fault, s.
    after_s: f64,
    /// Largest true wheel angle, deg, and whether an end switch closed.
    widest_deg: f64,
    end_switch: bool,
    /// Driven by the robot from the first volts to the fault, m.
    driven_m: f64,
    safe_in_that_tick: bool,
}

/// Run `mode` with `miswire` for up to 10 s: through the cards or straight. In
/// Joystick the operator holds the dead-man with the stick half forward and a little
/// to the right. The wheel starts 5 deg left, so that the first steering is firm.
fn run(miswire: &str, mode: Mode, cards: bool) -> Ended {
    let set = [
        format!("sim.miswire={miswire}"),
        "sim.initial_wheel_angle_deg=5".to_string(),
    ];
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let events = if mode == Mode::Joystick {
        "0 deadman on, 0 joystick 1 2"
    } else {
        ""
    };
    let s: Settings = settings_with(events, &set);
    let io = if cards {
        Io::cards(&s).unwrap()
    } else {
        Io::Direct
    };
    let mut sim = Lockstep::with_io(&s, mode, io);
    let part = match Miswire::parse(miswire).unwrap() {
        Miswire::SteerAmpReversed | Miswire::SteerEncoderReversed => 2,
        Miswire::RightAmpReversed => 1,
        _ => 0,
    };
    let (mut first_s, mut start_m) = (None, 0.0);
    let (mut widest_deg, mut end_switch) = (0.0f64, false);
    while sim.now_s() < 10.0 {
        let outputs = sim.tick();
        let truth = sim.robot.truth();
        let inputs = sim.robot.inputs();
        widest_deg = widest_deg.max(truth.wheel_angle_rad.to_degrees().abs());
        end_switch |= inputs.end_switch_left || inputs.end_switch_right;
        let volts = [outputs.amp_left_v, outputs.amp_right_v, outputs.amp_steer_v][part];
        if first_s.is_none() && volts.abs() > 0.5 {
            first_s = Some(sim.now_s());
            start_m = truth.distance_m;
        }
        if let Some(record) = sim.supervisor.status().fault {
            return Ended {
                fault: Some(record.cause),
                after_s: record.t_s - first_s.unwrap_or(record.t_s),
                widest_deg,
                end_switch,
                driven_m: truth.distance_m - start_m,
                safe_in_that_tick: record.tick_safe == record.tick_seen && outputs == Outputs::SAFE,
            };
        }
    }
    Ended {
        fault: None,
        after_s: f64::NAN,
        widest_deg,
        end_switch,
        driven_m: sim.robot.truth().distance_m - start_m,
        safe_in_that_tick: false,
    }
}

/// Every combination of the straight path and the cards, Autonomous and Joystick.
fn each_way(miswire: &str, expect: impl Fn(&FaultCause) -> bool) {
    for cards in [false, true] {
        for mode in [Mode::Autonomous, Mode::Joystick] {
            let ended = run(miswire, mode, cards);
            let how = format!("{miswire}, {mode:?}, cards {cards}: {ended:?}");
            eprintln!("{how}");
            let fault = ended.fault.unwrap_or_else(|| panic!("no fault: {how}"));
            assert!(expect(&fault), "{fault}: {how}");
            assert!(ended.safe_in_that_tick, "{how}");
            assert!(!ended.end_switch && ended.widest_deg < 28.0, "{how}");
            assert!(ended.driven_m < 0.5, "{how}");
            assert!(ended.after_s < 1.0, "{how}");
        }
    }
}

#[test]
fn a_steering_amplifier_of_the_wrong_sign_stops_the_robot_before_an_end_switch() {
    each_way("steer_amp_reversed", |f| {
        matches!(
            f,
            FaultCause::SteerWrongWay {
                pot_driven_way: false,
                ..
            }
        )
    });
}

#[test]
fn a_steering_encoder_counting_backwards_is_named_as_the_encoder() {
    each_way("steer_encoder_reversed", |f| {
        matches!(
            f,
            FaultCause::SteerWrongWay {
                pot_driven_way: true,
                ..
            }
        )
    });
}

#[test]
fn a_reversed_drive_amplifier_or_encoder_stops_the_robot_within_half_a_metre() {
    let left = |f: &FaultCause| {
        matches!(
            f,
            FaultCause::DriveWrongWay {
                wheel: Side::Left,
                ..
            }
        )
    };
    each_way("left_amp_reversed", left);
    each_way("left_encoder_reversed", left);
    each_way("right_amp_reversed", |f| {
        matches!(
            f,
            FaultCause::DriveWrongWay {
                wheel: Side::Right,
                ..
            }
        )
    });
}

/// Halt, powered up at 0.5 s, with `miswire`, straight or through the cards: the
/// first fault, and the widest wheel angle by then.
fn halt_after_power_up(miswire: &str, cards: bool) -> (Option<FaultCause>, f64) {
    let s = settings_with("0.5 power_up", &[&format!("sim.miswire={miswire}")]);
    let io = if cards {
        Io::cards(&s).unwrap()
    } else {
        Io::Direct
    };
    let mut sim = Lockstep::with_io(&s, Mode::Halt, io);
    let mut widest_deg = 0.0f64;
    while sim.now_s() < 4.0 && sim.supervisor.status().fault.is_none() {
        sim.tick();
        widest_deg = widest_deg.max(sim.robot.truth().wheel_angle_rad.to_degrees().abs());
    }
    (sim.supervisor.status().fault.map(|f| f.cause), widest_deg)
}

#[test]
fn a_dda06_switched_unipolar_is_uncommanded_motion_in_halt_after_power_up() {
    for cards in [false, true] {
        let (fault, widest_deg) = halt_after_power_up("dda06_unipolar", cards);
        eprintln!("cards {cards}: {fault:?}, widest {widest_deg:.1} deg");
        assert!(
            matches!(
                fault,
                Some(FaultCause::UncommandedMotion {
                    part: EncoderId::Steer,
                    ..
                })
            ),
            "cards {cards}: {fault:?}"
        );
        assert!(widest_deg < 28.0, "reached the end switch: {widest_deg}");
        // Wired right, the same power-up stands still in Halt.
        assert_eq!(halt_after_power_up("none", cards).0, None);
    }
}

#[test]
fn a_mistake_made_while_driving_by_a_scripted_event_is_caught_too() {
    let s = settings_with("3 miswire left_amp_reversed", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    sim.run_for(6.0);
    let fault = sim.supervisor.status().fault.map(|f| f.cause);
    assert!(
        matches!(
            fault,
            Some(FaultCause::DriveWrongWay {
                wheel: Side::Left,
                ..
            })
        ),
        "{fault:?}"
    );
}

#[test]
fn at_a_closed_end_switch_only_motion_the_encoder_confirms_is_off_it_goes_on() {
    // A stone kicks the wheel onto the left end switch on a robot whose steering
    // amplifier is reversed: the procedure's back-off pushes it into its stop instead.
    let s = settings_with("3 miswire steer_amp_reversed, 3 endswitch left", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    sim.run_for(3.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    while sim.now_s() < 7.0 && sim.supervisor.status().fault.is_none() {
        sim.tick();
    }
    let record = sim.supervisor.status().fault.expect("a fault");
    assert!(
        matches!(
            record.cause,
            FaultCause::EndSwitchNoBackOff {
                side: Side::Left,
                ..
            }
        ),
        "{}",
        record.cause
    );
    // Within the back-off time, not the 3 s of "could not steer off the end switch".
    let after_s = record.t_s - 3.0;
    eprintln!("faulted {after_s:.2} s after the kick: {}", record.cause);
    assert!(after_s < 1.0, "{after_s}");
    assert_eq!(sim.robot.outputs(), Outputs::SAFE);
}

#[test]
fn a_drive_that_cannot_reach_its_reference_is_too_slow_by_name() {
    // Motors a sixth as strong as the controller's model: 0.2 m/s at 10 V, asked 0.5.
    let s = settings_with("", &["sim.motor_gain_mps_per_v=0.02"]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    while sim.now_s() < 15.0 && sim.supervisor.status().fault.is_none() {
        sim.tick();
    }
    let cause = sim.supervisor.status().fault.map(|f| f.cause);
    let Some(FaultCause::DriveSpeed {
        speed_mps, ref_mps, ..
    }) = cause
    else {
        panic!("{cause:?}");
    };
    assert!(speed_mps < ref_mps - 0.25, "{speed_mps} {ref_mps}");
    assert!(cause.unwrap().to_string().contains("too slow"));
}

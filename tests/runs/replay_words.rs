//! What `mechweed replay` says: which outputs are identical, and the steer commands
//! made again apart from them, in words that do not read as a failure when only the
//! steer commands differ.

use mechweed::programs::replay::words;
use mechweed::replay::{Difference, Outcome, SteerFigures};

fn outcome(steer: SteerFigures, first_difference: Option<Difference>) -> Outcome {
    Outcome {
        ticks: 4000,
        compared: 4000,
        requests: 3,
        first_difference,
        faults_recorded: Vec::new(),
        faults_replayed: Vec::new(),
        steer,
        written: Vec::new(),
        notes: Vec::new(),
    }
}

#[test]
fn identical_outputs_and_differing_steer_commands_are_said_apart() {
    let steer = SteerFigures {
        commands: 794,
        max_angle_diff_deg: 1.662,
        max_speed_diff_mps: 0.5,
        beyond: 3,
        first_beyond: Some((12.5, 1.25, -0.412)),
    };
    let said = words(&outcome(steer, None), false);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(lines.len(), 3, "{said}");
    assert_eq!(
        lines[0],
        "4000 ticks, outputs identical to the record: the mode, the amplifiers (to the bit), the main power relay, the brakes and the tool, and the answers to the operator's requests"
    );
    assert_eq!(
        lines[1],
        "steer commands: 794 made again by the steering law from the recorded estimates: 791 within 0.1 deg and 0.001 m/s of the recorded, 3 differ from it by at most 1.662 deg and 0.5000 m/s, the first at 12.500 s (recorded 1.250 deg, made again -0.412 deg)"
    );
    assert!(
        lines[2].starts_with(
            "steer commands: such differences are expected and do not touch the outputs above"
        ),
        "{said}"
    );
    // The old words put the worst difference where the tolerance is read.
    assert!(!said.contains("within 1.662 deg"), "{said}");
}

#[test]
fn steer_commands_within_the_tolerance_are_one_line_and_a_difference_of_outputs_is_named() {
    let close = SteerFigures {
        commands: 120,
        max_angle_diff_deg: 0.004,
        ..SteerFigures::default()
    };
    let said = words(&outcome(close.clone(), None), false);
    assert!(
        said.ends_with("steer commands: 120 made again by the steering law from the recorded estimates, all within 0.1 deg and 0.001 m/s of the recorded (at most 0.004 deg and 0.0000 m/s)\n"),
        "{said}"
    );
    let differs = Difference {
        tick: 300,
        t_s: 3.0,
        what: "amp_left_v".into(),
        recorded: "9.5".into(),
        replayed: "1.25".into(),
    };
    let said = words(&outcome(close, Some(differs)), false);
    assert!(
        said.starts_with(
            "4000 ticks; first difference at tick 300 (3.000 s): amp_left_v: recorded 9.5, replayed 1.25\n"
        ),
        "{said}"
    );
    assert!(!said.contains("identical"), "{said}");
}

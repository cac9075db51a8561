//! The camera alone through a gap in the row: the row filter carries the row by the
//! robot's own motion, and the robot slows while it does.

use crate::gnss_safety::said;
use crate::row_following::gappy_row;
use mechweed_core::state::modes::Mode;
use mechweed_core::threads::lockstep::Lockstep;

#[test]
fn through_a_gap_the_camera_alone_slows_to_its_gap_speed_and_says_so() {
    // Gaps of 2.5 m, inside [camera] gap_hold_m, every 10 m, driven at 1 m/s: the robot
    // used to cross each at full speed on a row line a gap's length old.
    let s = gappy_row(2.5, 10.0);
    let gap_speed_mps = s.camera.gap_speed_mps;
    assert!(gap_speed_mps < 0.5 && s.steer.speed_mps == 1.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let (mut numbers, mut new_at_m) = ((f64::NAN, f64::NAN), 0.0);
    let (mut late_in_a_gap_mps, mut top_mps) = (None::<f64>, 0.0f64);
    while !sim.robot.truth().row_done && sim.now_s() < 120.0 {
        sim.tick();
        let truth = sim.robot.truth();
        let last = sim.link.status().last_usable;
        if (last.offset_m, last.angle_rad) != numbers {
            (numbers, new_at_m) = ((last.offset_m, last.angle_rad), truth.distance_m);
        }
        top_mps = top_mps.max(truth.speed_mps);
        // 1.5 m into a gap: the braking from 1 m/s (1.4 s at 0.5 m/s/s) is over.
        let held_m = truth.distance_m - new_at_m;
        if held_m > 1.5 {
            late_in_a_gap_mps = Some(late_in_a_gap_mps.unwrap_or(0.0).max(truth.speed_mps));
        }
    }
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    assert!(sim.robot.truth().row_done, "the row was not finished");
    assert!(top_mps > 0.9, "{top_mps} m/s at most");
    let late_in_a_gap_mps = late_in_a_gap_mps.expect("no gap came");
    assert!(
        late_in_a_gap_mps < gap_speed_mps + 0.05,
        "{late_in_a_gap_mps} m/s late in a gap, gap speed {gap_speed_mps}"
    );
    assert!(
        said(&sim, "a gap in the row"),
        "{:?}",
        sim.supervisor.notices()
    );
}

#[test]
fn a_silent_camera_never_sends_the_robot_looking_for_plants() {
    // The camera computer falls silent while the robot stands in Halt (the link streams
    // only while driving, so nothing shows yet). Autonomous is taken; the robot must not
    // then drive off blind "to find the first plants": it stands, and the silence is
    // the camera's fault.
    let s = crate::common::settings_with("0.2 link_silent 30", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    while sim.supervisor.faults().is_empty() && sim.now_s() < 10.0 {
        sim.tick();
    }
    assert_eq!(
        sim.supervisor.faults().first().map(|f| f.cause.to_string()),
        Some("camera link lost: no row frame for 0.51 s".to_string()),
        "{:?}",
        sim.supervisor.faults()
    );
    let driven_m = sim.robot.truth().distance_m;
    assert!(driven_m < 0.01, "drove {driven_m} m with a silent camera");
    assert!(
        !said(&sim, "no row in sight yet"),
        "{:?}",
        sim.supervisor.notices()
    );
}

#[test]
fn a_camera_computer_that_answers_nothing_while_standing_keeps_the_robot_out_of_autonomous() {
    // The camera computer is switched off (its line silent from the start): the port
    // opens, but no keep-alive PING is answered. Autonomous is refused with the reason
    // rather than taken and faulted a moment later with the robot moving.
    let s = crate::common::settings_with("0 link_silent 30", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    sim.run_for(5.0);
    let st = sim.supervisor.status();
    assert_eq!(st.mode, Mode::Halt, "{:?}", sim.supervisor.faults());
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    let why = st.sensor_down.expect("the camera is down").to_string();
    assert!(
        why.contains("the camera computer has answered nothing"),
        "{why}"
    );
    assert!(sim.robot.truth().distance_m < 0.01);
}

//! `mechweed check-config FILE` refuses settings a field robot cannot live with: values
//! each in range that would steer on "no row seen" frames, drive on a minute-old row
//! estimate, be cut short silently, or back off an end switch beyond the end switches.
//! Each error names the line, every key involved and its value, and why.

use crate::config_file;

use config_file::{File, SHIPPED, assert_refused, check, line_of, shipped_with};

/// check-config accepts the shipped file with these changes.
fn assert_accepted(changes: &[(&str, &str, &str)]) {
    let file = File::new(shipped_with(changes));
    assert_eq!(check(&file.path), (Some(0), Vec::new()), "{changes:?}");
}

fn line(section: &str, key: &str) -> usize {
    line_of(SHIPPED, section, key)
}

// Item 8.

const BACK_WHY: &str = "the end-switch procedure steers back off the switch towards the centre";

#[test]
fn the_end_switch_back_off_angle_lies_inside_the_end_switches() {
    let back = line("steer", "endswitch_back_deg");
    assert_refused(
        &shipped_with(&[("steer", "endswitch_back_deg", "26")]),
        &[(
            back,
            &format!(
                "[steer] endswitch_back_deg = 26 must be below [robot] max_wheel_angle_deg = 25: {BACK_WHY}"
            ),
        )],
    );
    assert_refused(
        &shipped_with(&[("sim", "end_switch_deg", "20")]),
        &[
            (
                back,
                &format!(
                    "[steer] endswitch_back_deg = 20 must be below [sim] end_switch_deg = 20: {BACK_WHY}"
                ),
            ),
            (
                line("robot", "max_wheel_angle_deg"),
                "[robot] max_wheel_angle_deg = 25 must be below [sim] end_switch_deg = 20: \
                 the controller would steer into the end switches in normal driving",
            ),
        ],
    );
    assert_refused(
        &shipped_with(&[("sim", "end_switch_deg", "30")]),
        &[(
            line("sim", "end_switch_deg"),
            "[sim] end_switch_deg = 30 must be below [sim] steer_limit_deg = 30: \
             the end switches must close before the mechanical stop",
        )],
    );
    assert_accepted(&[("steer", "endswitch_back_deg", "24.5")]);
}

// Item 9: ranges.

#[test]
fn frames_that_see_no_row_never_steer() {
    assert_refused(
        &shipped_with(&[("camera", "min_quality", "0")]),
        &[(
            line("camera", "min_quality"),
            "[camera] min_quality = 0 is out of range (1 to 100)",
        )],
    );
    assert_accepted(&[("camera", "min_quality", "1")]);
}

#[test]
fn time_outs_that_guard_motion_are_at_most_about_a_second() {
    assert_refused(
        &shipped_with(&[
            ("camera", "link_timeout_s", "1.5"),
            ("camera", "restart_after_s", "60"),
            ("rt", "heartbeat_timeout_s", "60"),
            ("rt", "gui_heartbeat_timeout_s", "10"),
        ]),
        &[
            (
                line("camera", "link_timeout_s"),
                "[camera] link_timeout_s = 1.5 is out of range (0.05 to 1)",
            ),
            (
                line("camera", "restart_after_s"),
                "[camera] restart_after_s = 60 is out of range (0.05 to 5)",
            ),
            (
                line("rt", "heartbeat_timeout_s"),
                "[rt] heartbeat_timeout_s = 60 is out of range (0.05 to 1)",
            ),
            (
                line("rt", "gui_heartbeat_timeout_s"),
                "[rt] gui_heartbeat_timeout_s = 10 is out of range (0.1 to 5)",
            ),
        ],
    );
    assert_accepted(&[
        ("camera", "link_timeout_s", "1"),
        ("camera", "restart_after_s", "5"),
        ("rt", "heartbeat_timeout_s", "1"),
        ("rt", "gui_heartbeat_timeout_s", "5"),
    ]);
}

#[test]
fn fault_timers_are_short_enough_to_matter() {
    let changes = [
        ("faults", "battery_low_s", "30", "0 to 10"),
        ("faults", "pot_disagree_deg", "20", "0.1 to 10"),
        ("faults", "pot_disagree_s", "5", "0 to 1"),
        ("faults", "encoder_stuck_s", "5", "0.05 to 1"),
        ("faults", "endswitch_unhandled_s", "2", "0.01 to 1"),
        ("faults", "endswitch_timeout_s", "30", "0.1 to 10"),
    ];
    let set: Vec<(&str, &str, &str)> = changes.iter().map(|&(s, k, v, _)| (s, k, v)).collect();
    let expected: Vec<(usize, String)> = changes
        .iter()
        .map(|&(s, k, v, range)| {
            (
                line(s, k),
                format!("[{s}] {k} = {v} is out of range ({range})"),
            )
        })
        .collect();
    let expected: Vec<(usize, &str)> = expected.iter().map(|(n, w)| (*n, w.as_str())).collect();
    assert_refused(&shipped_with(&set), &expected);
}

#[test]
fn whole_numbers_are_whole() {
    let cpu = line("rt", "supervisor_cpu");
    assert_refused(
        &shipped_with(&[("rt", "supervisor_cpu", "1.7")]),
        &[(cpu, "[rt] supervisor_cpu = '1.7' is not a whole number")],
    );
    assert_refused(
        &shipped_with(&[("rt", "supervisor_cpu", "-2")]),
        &[(cpu, "[rt] supervisor_cpu = -2 is out of range (-1 to 1023)")],
    );
    // -1 (not pinned) is the shipped value; a CPU number is taken too.
    assert_accepted(&[("rt", "supervisor_cpu", "1")]);
}

// Item 9: settings that must agree.

#[test]
fn the_potentiometer_band_is_not_empty_and_holds_the_steering_range() {
    let min = line("faults", "pot_min_v");
    assert_refused(
        &shipped_with(&[
            ("faults", "pot_min_v", "4.7"),
            ("faults", "pot_max_v", "0.3"),
        ]),
        &[(
            min,
            "[faults] pot_min_v = 4.7 must be below [faults] pot_max_v = 0.3: \
             no potentiometer reading would count as good",
        )],
    );
    assert_refused(
        &shipped_with(&[("faults", "pot_min_v", "1")]),
        &[(
            min,
            "the potentiometer reads 0.83 to 4.17 V over the steering range \
             ([robot] pot_centre_v = 2.5, [robot] pot_v_per_deg = 0.0666667, \
             [robot] max_wheel_angle_deg = 25), not inside [faults] pot_min_v = 1 to \
             [faults] pot_max_v = 4.7: steering to the limit would be the fault \
             'potentiometer out of range'",
        )],
    );
}

#[test]
fn each_amplifier_range_switch_covers_its_regulator_limit() {
    let ranges = line("hw", "dda06_ranges_v");
    assert_refused(
        &shipped_with(&[("hw", "dda06_ranges_v", "+-5, +-10, +-10, +-5, +-5, +-5")]),
        &[(
            ranges,
            "[hw] dda06_ranges_v sets AO0 to +-5 V, but [pid.left] out_max_v = 10 on \
             [io] amp_left_v = dda06 ao 0, scale 1 needs +-10 V: the card would clip the \
             left wheel amplifier without notice; set the switch and dda06_ranges_v to \
             +-10, or lower out_max_v",
        )],
    );
    assert_refused(
        &shipped_with(&[("hw", "dda06_ranges_v", "+-10, +-10, 0..10, +-5, +-5, +-5")]),
        &[(
            ranges,
            "[hw] dda06_ranges_v sets AO2 to 0..10 V, but [io] amp_steer_v = dda06 ao 2 \
             drives the steering amplifier, which needs negative volts too: set the card's \
             switch and dda06_ranges_v to +-10",
        )],
    );
    // A scale of 2 at the card doubles the volts the range must hold.
    assert_refused(
        &shipped_with(&[("io", "amp_right_v", "dda06 ao 1, scale 2")]),
        &[(
            ranges,
            "[hw] dda06_ranges_v sets AO1 to +-10 V, but [pid.right] out_max_v = 10 on \
             [io] amp_right_v = dda06 ao 1, scale 2 needs +-20 V: the card would clip the \
             right wheel amplifier without notice; set the switch and dda06_ranges_v to \
             +-10, or lower out_max_v",
        )],
    );
    assert_accepted(&[
        ("hw", "dda06_ranges_v", "+-5, +-10, +-10, +-5, +-5, +-5"),
        ("pid.left", "out_max_v", "5"),
    ]);
}

#[test]
fn no_mode_asks_for_more_speed_than_the_supervisor_allows() {
    assert_refused(
        &shipped_with(&[
            ("steer", "speed_mps", "1.5"),
            ("joystick", "max_speed_mps", "2"),
        ]),
        &[
            (
                line("steer", "speed_mps"),
                "[steer] speed_mps = 1.5 is above [supervisor] max_speed_mps = 1.2, \
                 the highest speed any mode may ask for",
            ),
            (
                line("joystick", "max_speed_mps"),
                "[joystick] max_speed_mps = 2 is above [supervisor] max_speed_mps = 1.2, \
                 the highest speed any mode may ask for",
            ),
        ],
    );
    assert_accepted(&[
        ("steer", "speed_mps", "1.2"),
        ("joystick", "max_speed_mps", "1.2"),
    ]);
}

#[test]
fn the_supervisor_runs_before_the_threads_it_watches() {
    let why =
        "(or 0, normal scheduling): the supervisor watches the other threads and must run first";
    assert_refused(
        &shipped_with(&[
            ("rt", "steer_priority", "80"),
            ("rt", "camlink_priority", "90"),
        ]),
        &[
            (
                line("rt", "steer_priority"),
                &format!(
                    "[rt] steer_priority = 80 must be below [rt] supervisor_priority = 80 {why}"
                ),
            ),
            (
                line("rt", "camlink_priority"),
                &format!(
                    "[rt] camlink_priority = 90 must be below [rt] supervisor_priority = 80 {why}"
                ),
            ),
        ],
    );
    assert_refused(
        &shipped_with(&[
            ("rt", "supervisor_priority", "0"),
            ("rt", "camlink_priority", "0"),
        ]),
        &[(
            line("rt", "steer_priority"),
            &format!("[rt] steer_priority = 70 must be below [rt] supervisor_priority = 0 {why}"),
        )],
    );
    assert_accepted(&[
        ("rt", "supervisor_priority", "0"),
        ("rt", "steer_priority", "0"),
        ("rt", "camlink_priority", "0"),
    ]);
}

#[test]
fn the_gui_is_not_pinned_to_the_supervisors_cpu() {
    assert_refused(
        &shipped_with(&[("rt", "supervisor_cpu", "1"), ("rt", "gui_cpu", "1")]),
        &[(
            line("rt", "gui_cpu"),
            "[rt] gui_cpu = 1 is the supervisor's own CPU: the GUI is pinned to keep its \
             drawing away from the supervisor, so give it another CPU (or -1, any)",
        )],
    );
    assert_accepted(&[("rt", "supervisor_cpu", "1"), ("rt", "gui_cpu", "0")]);
    assert_accepted(&[("rt", "supervisor_cpu", "-1"), ("rt", "gui_cpu", "-1")]);
}

#[test]
fn the_joystick_agrees_with_the_robot() {
    assert_refused(
        &shipped_with(&[
            ("joystick", "deadband_v", "4"),
            ("joystick", "max_angle_deg", "30"),
        ]),
        &[
            (
                line("joystick", "deadband_v"),
                "[joystick] deadband_v = 4 must be below [joystick] full_scale_v = 4: \
                 the stick would jump from standstill to full deflection",
            ),
            (
                line("joystick", "max_angle_deg"),
                "[joystick] max_angle_deg = 30 is above [robot] max_wheel_angle_deg = 25, \
                 the largest wheel angle the controller commands",
            ),
        ],
    );
}

#[test]
fn fault_checks_can_see_what_they_watch() {
    let stuck = line("faults", "encoder_stuck_v");
    let expected: Vec<String> = [
        ("pid.left", "left wheel"),
        ("pid.right", "right wheel"),
        ("pid.steer", "steering"),
    ]
    .iter()
    .map(|(pid, what)| {
        format!(
            "[faults] encoder_stuck_v = 10 must be below [{pid}] out_max_v = 10: the \
                 amplifier never gets there, so a stuck {what} encoder would never be noticed"
        )
    })
    .collect();
    let mut expected: Vec<(usize, &str)> = expected.iter().map(|w| (stuck, w.as_str())).collect();
    // Test's drive limit must stay above it too, or the check never looks in Test.
    expected.push((
        line("test", "drive_limit_v"),
        "[test] drive_limit_v = 3 is not above [faults] encoder_stuck_v = 10: in Test the \
         encoder check would never look, and a dead encoder would also blind [test] \
         max_speed_mps. Raise drive_limit_v or lower encoder_stuck_v",
    ));
    assert_refused(
        &shipped_with(&[("faults", "encoder_stuck_v", "10")]),
        &expected,
    );

    assert_refused(
        &shipped_with(&[("rt", "heartbeat_timeout_s", "0.15")]),
        &[(
            line("rt", "heartbeat_timeout_s"),
            "[rt] heartbeat_timeout_s = 0.15 is shorter than two periods of the steer thread \
             ([steer] rate_hz = 10: 0.2 s), which beats once a period: it would be taken for \
             stopped",
        )],
    );
}

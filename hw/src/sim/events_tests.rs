//! Tests of the event list's text form.

use super::*;

#[test]
fn parses_and_sorts_by_time_stably() {
    let events =
        parse_events("3 estop_release, 1 estop_front ,1 mode autonomous, 2.5 link_silent 2")
            .unwrap();
    let actions: Vec<_> = events.iter().map(|e| (e.t_s, e.action)).collect();
    assert_eq!(
        actions,
        vec![
            (1.0, EventAction::EstopFront),
            (1.0, EventAction::Mode(OperatorMode::Autonomous)),
            (2.5, EventAction::LinkSilent(2.0)),
            (3.0, EventAction::EstopRelease),
        ]
    );
    assert_eq!(parse_events("  ").unwrap(), vec![]);
}

#[test]
fn display_round_trips_every_action() {
    let all = [
        EventAction::EstopFront,
        EventAction::EstopBack,
        EventAction::EstopRelease,
        EventAction::PowerUp,
        EventAction::Mode(OperatorMode::Test),
        EventAction::PowerLoss,
        EventAction::PowerRestore,
        EventAction::EncoderStuck(EncoderId::Steer),
        EventAction::LinkSilent(2.0),
        EventAction::CameraReboot,
        EventAction::EndSwitch(Side::Right),
        EventAction::Battery(21.5),
        EventAction::PotBroken,
        EventAction::ContactorWelded,
        EventAction::SteerSlip(-3.5),
        EventAction::Joystick {
            steer_v: -0.5,
            speed_v: 2.0,
        },
        EventAction::Deadman(true),
        EventAction::Deadman(false),
    ];
    for action in all {
        let text = SimEvent { t_s: 1.5, action }.to_string();
        assert_eq!(
            parse_events(&text).unwrap(),
            vec![SimEvent { t_s: 1.5, action }],
            "{text}"
        );
    }
    assert_eq!(EventAction::LinkSilent(2.0).to_string(), "link_silent 2");
    assert_eq!(
        EventAction::Mode(OperatorMode::Autonomous).to_string(),
        "mode autonomous"
    );
    assert!(EventAction::PowerUp.is_operator() && !EventAction::PowerLoss.is_operator());
}

#[test]
fn errors_name_the_item_and_the_problem() {
    let err = parse_events("1 estop_front, 1.5 estop_release, 2.0 estop_middle").unwrap_err();
    assert!(
        err.starts_with("sim.events item 3 \"2.0 estop_middle\": unknown action \"estop_middle\" (known: estop_front, estop_back,"),
        "{err}"
    );
    let err = parse_events("x estop_front").unwrap_err();
    assert_eq!(
        err,
        "sim.events item 1 \"x estop_front\": time \"x\" is not a number"
    );
    let err = parse_events("1 encoder_stuck").unwrap_err();
    assert_eq!(
        err,
        "sim.events item 1 \"1 encoder_stuck\": missing argument: left, right or steer"
    );
    let err = parse_events("1 endswitch up").unwrap_err();
    assert!(
        err.contains("argument \"up\" is not one of left or right"),
        "{err}"
    );
    assert!(parse_events("1 battery -3").unwrap_err().contains("item 1"));
    assert!(
        parse_events("1 pot_broken now")
            .unwrap_err()
            .contains("takes no argument")
    );
    assert!(
        parse_events("1 pot_broken,")
            .unwrap_err()
            .contains("item 2 \"\": empty item")
    );
    assert!(
        parse_events("-1 pot_broken")
            .unwrap_err()
            .contains("0 or more")
    );
    assert!(
        parse_events("1 link_silent 2 3")
            .unwrap_err()
            .contains("unexpected word \"3\"")
    );
}

#[test]
fn the_action_list_covers_every_action_and_its_examples_parse() {
    let list = action_list();
    let names: Vec<&str> = list.iter().map(|a| a.name).collect();
    assert_eq!(names, ACTIONS);
    for help in &list {
        let events = parse_events(&help.example).unwrap();
        assert_eq!(events.len(), 1, "{}", help.example);
        assert_eq!(help.argument.is_some(), takes_argument(help.name));
    }
    let mode = list.iter().find(|a| a.name == "mode").unwrap();
    assert_eq!(
        mode.argument.as_deref(),
        Some("halt, joystick, autonomous or test")
    );
    let battery = list.iter().find(|a| a.name == "battery").unwrap();
    assert_eq!(battery.argument.as_deref(), Some("a voltage in volts"));
}

#[test]
fn joystick_takes_two_voltages_and_says_so_when_one_is_missing() {
    let err = parse_events("1 joystick 2").unwrap_err();
    assert!(err.contains("STEER_V SPEED_V"), "{err}");
    let err = parse_events("1 joystick 0 2 3").unwrap_err();
    assert!(err.contains("unexpected word \"3\""), "{err}");
    let err = parse_events("1 deadman maybe").unwrap_err();
    assert!(err.contains("on or off"), "{err}");
    let err = parse_events("1 battery 2 3").unwrap_err();
    assert!(err.contains("unexpected word \"3\""), "{err}");
}

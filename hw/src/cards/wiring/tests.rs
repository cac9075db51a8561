//! The wiring: parsing robot.ini's lines, the conversions in both directions for the
//! robot's wiring of function_spec.md section 4a, and the checks of a whole wiring.

use super::*;

/// The robot's wiring as the table of function_spec.md section 4a gives it (and config/robot.ini ships).
pub(crate) fn robot() -> Wiring {
    let ai = |t: &str| parse_analog_in(t).unwrap();
    let sw_in = |t: &str| parse_switch_in(t).unwrap();
    let sw_out = |t: &str| parse_switch_out(t).unwrap();
    let enc = |t: &str| parse_encoder(t).unwrap();
    let ao = |t: &str| parse_analog_out(t).unwrap();
    Wiring {
        pot_v: ai("das08 ai 0, scale 1"),
        joystick_steer_v: ai("das08 ai 1, scale 1"),
        joystick_speed_v: ai("das08 ai 2, scale 1"),
        battery_v: ai("das08 ai 3, scale 10"),
        estop_front_released: sw_in("das08 ip 1, active high"),
        estop_back_released: sw_in("das08 ip 2, active high"),
        motor_power_present: sw_in("das08 ip 3, active high"),
        end_switch_left: sw_in("dda06 port a bit 0, active high"),
        end_switch_right: sw_in("dda06 port a bit 1, active high"),
        joystick_enable: sw_in("dda06 port a bit 2, active high"),
        enc_left_counts: enc("quad04 ch 1, scale 1"),
        enc_right_counts: enc("quad04 ch 2, scale 1"),
        enc_steer_counts: enc("quad04 ch 3, scale 1"),
        amp_left_v: ao("dda06 ao 0, scale 1"),
        amp_right_v: ao("dda06 ao 1, scale 1"),
        amp_steer_v: ao("dda06 ao 2, scale 1"),
        main_power_on: sw_out("das08 op 1, active high"),
        brake_release_left: sw_out("das08 op 2, active high"),
        brake_release_right: sw_out("das08 op 3, active high"),
        tool_on: sw_out("das08 op 4, active high"),
        joystick_released: None,
        watchdog: parse_watchdog("dda06 port b bit 0, active high").unwrap(),
    }
}

fn driving() -> Outputs {
    Outputs {
        amp_left_v: 6.0,
        amp_right_v: -3.0,
        amp_steer_v: 1.5,
        main_power_on: true,
        brake_release_left: true,
        brake_release_right: false,
        tool_on: true,
    }
}

#[test]
fn card_values_become_physical_inputs_as_io_cards_md_says() {
    let mut c = CardInputs::default();
    c.das08_ai_v[0] = 0.5;
    c.das08_ai_v[1] = -4.0;
    c.das08_ai_v[2] = 4.0;
    c.das08_ai_v[3] = 2.4;
    c.das08_ip = 0b101; // IP1 and IP3 high
    c.dda06_ports[0] = 0b110; // end switch right and joystick enable
    c.quad04_counts = [100, -200, 300, 999];
    let i = robot().inputs(&c);
    assert_eq!(
        (i.pot_v, i.joystick_steer_v, i.joystick_speed_v),
        (0.5, -4.0, 4.0)
    );
    assert!(
        (i.battery_v - 24.0).abs() < 1e-12,
        "battery = A/D volts x 10"
    );
    assert!(i.estop_front_released && !i.estop_back_released && i.motor_power_present);
    assert!(!i.end_switch_left && i.end_switch_right && i.joystick_enable);
    assert_eq!(
        (i.enc_left_counts, i.enc_right_counts, i.enc_steer_counts),
        (100, -200, 300)
    );
}

#[test]
fn outputs_become_card_values_and_safe_is_all_off_at_zero_volts() {
    let w = robot();
    let safe = w.card_outputs(&Outputs::SAFE);
    assert_eq!(safe, CardOutputs::default());
    let c = w.card_outputs(&driving());
    assert_eq!(c.dda06_ao_v, [6.0, -3.0, 1.5, 0.0, 0.0, 0.0]);
    assert_eq!(c.das08_op, 0b1011, "OP1 relay, OP2 left brake, OP4 tool");
    assert_eq!(c.dda06_ports, [0; 3]);
}

#[test]
fn polarity_and_scale_apply_both_ways() {
    let mut w = robot();
    // Port b to main_power_on alone: no watchdog line beside it.
    w.watchdog = None;
    w.estop_front_released = parse_switch_in("das08 ip 1, active low").unwrap();
    w.main_power_on = parse_switch_out("dda06 port b bit 7, active low").unwrap();
    w.amp_right_v = parse_analog_out("dda06 ao 5, scale -1").unwrap();
    w.enc_left_counts = parse_encoder("quad04 ch 4, scale -1").unwrap();
    let mut c = CardInputs::default();
    c.quad04_counts[3] = 50;
    let i = w.inputs(&c);
    assert!(i.estop_front_released, "active low: 0 at the card is true");
    assert_eq!(i.enc_left_counts, -50);
    let out = w.card_outputs(&Outputs::SAFE);
    assert_eq!(out.dda06_ports[1], 0x80, "active low off is a 1");
    let out = w.card_outputs(&driving());
    assert_eq!(out.dda06_ports[1], 0x00);
    assert_eq!(out.dda06_ao_v[5], 3.0);
    assert_eq!(w.dda06_directions().output_bits, [0, 0x80, 0]);
    assert_eq!(w.dda06_directions().control_word(), 0x99);
}

#[test]
fn the_inverse_conversions_give_back_what_went_in() {
    for w in [robot(), {
        let mut w = robot();
        w.battery_v.scale = 11.0;
        w.end_switch_left = parse_switch_in("dda06 port c bit 6, active low").unwrap();
        w.tool_on = parse_switch_out("dda06 port b bit 0, active high").unwrap();
        w
    }] {
        let inputs = Inputs {
            pot_v: 2.5,
            joystick_steer_v: -1.0,
            joystick_speed_v: 3.0,
            battery_v: 25.0,
            estop_front_released: true,
            estop_back_released: false,
            motor_power_present: true,
            end_switch_left: true,
            end_switch_right: false,
            joystick_enable: true,
            enc_left_counts: 12345,
            enc_right_counts: -54321,
            enc_steer_counts: 7,
        };
        let back = w.inputs(&w.wires_for(&inputs));
        assert!((back.battery_v - inputs.battery_v).abs() < 1e-12);
        assert_eq!(
            Inputs {
                battery_v: 25.0,
                ..back
            },
            inputs
        );
        assert_eq!(w.outputs_from(&w.card_outputs(&driving())), driving());
    }
}

#[test]
fn the_reads_needed_follow_the_wiring() {
    let w = robot();
    assert!(w.reads_das08_inputs());
    assert_eq!(w.dda06_input_ports(), [true, false, false]);
    assert_eq!(
        w.dda06_directions().control_word(),
        0x99,
        "port b an output for the watchdog, every other 8255 line an input"
    );
    let no_watchdog = Wiring {
        watchdog: None,
        ..w
    };
    assert_eq!(
        no_watchdog.dda06_directions().control_word(),
        0x9B,
        "every 8255 line an input"
    );
}

#[test]
fn a_channel_or_bit_the_card_does_not_have_is_refused_with_the_real_ones() {
    let analog = |t: &str| parse_analog_in(t).map(|_| ());
    let switch = |t: &str| parse_switch_in(t).map(|_| ());
    let encoder = |t: &str| parse_encoder(t).map(|_| ());
    type Parse<'a> = &'a dyn Fn(&str) -> Result<(), String>;
    let cases: [(Parse, &str, &str); 11] = [
        (
            &analog,
            "das08 ai 8, scale 1",
            "das08 analog input 8 does not exist: the card has 0..7",
        ),
        (
            &switch,
            "das08 ip 4, active high",
            "das08 input ip 4 does not exist: the card has 1..3",
        ),
        (
            &switch,
            "dda06 port d bit 0, active high",
            "dda06 port d does not exist",
        ),
        (
            &switch,
            "dda06 port a bit 8, active high",
            "dda06 port bit 8 does not exist",
        ),
        (
            &encoder,
            "quad04 ch 0, scale 1",
            "quad04 channel 0 does not exist: the card has 1..4",
        ),
        (
            &switch,
            "das08 op 1, active high",
            "das08 op 1 cannot carry this signal",
        ),
        (
            &analog,
            "das08 ai 0",
            "needs its card channel and one option",
        ),
        (&analog, "das08 ai 0, active high", "takes a scale"),
        (&analog, "das08 ai 0, scale 0", "other than 0"),
        (&analog, "das08 ai 0, scale x", "not a number"),
        (&analog, "pcm ai 0, scale 1", "is not a card channel"),
    ];
    for (parse, text, expected) in cases {
        let err = parse(text).unwrap_err();
        assert!(err.contains(expected), "{text}: {err}");
    }
    assert!(
        parse_switch_out("das08 op 1, scale 1")
            .unwrap_err()
            .contains("active high or active low")
    );
    assert!(
        parse_encoder("quad04 ch 1, scale 4")
            .unwrap_err()
            .contains("1 or -1")
    );
    assert_eq!(
        parse_analog_in(" DAS08 AI 3 , Scale 10 ").unwrap().scale,
        10.0
    );
}

#[test]
fn two_signals_on_one_channel_or_bit_name_both_keys() {
    let mut w = robot();
    assert!(check(&w).is_empty(), "{:?}", check(&w));
    w.joystick_speed_v = w.pot_v;
    w.end_switch_right = w.end_switch_left;
    w.amp_steer_v.channel = 0;
    let problems = check(&w);
    let keys: Vec<&str> = problems.iter().map(|(k, _)| *k).collect();
    assert_eq!(
        keys,
        ["joystick_speed_v", "end_switch_right", "amp_steer_v"]
    );
    assert!(
        problems[0]
            .1
            .contains("das08 ai 0 is already wired to pot_v"),
        "{problems:?}"
    );
    assert!(
        problems[1]
            .1
            .contains("dda06 port a bit 0 is already wired to end_switch_left")
    );
}

#[test]
fn an_input_in_an_8255_group_that_drives_an_output_is_refused() {
    let mut w = robot();
    w.tool_on = parse_switch_out("dda06 port a bit 7, active high").unwrap();
    let problems = check(&w);
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert_eq!(problems[0].0, "end_switch_left");
    assert!(
        problems[0]
            .1
            .contains("same 8255 port group as the output tool_on")
    );
    w.tool_on = parse_switch_out("dda06 port c bit 3, active high").unwrap();
    w.joystick_enable = parse_switch_in("dda06 port c bit 4, active high").unwrap();
    assert!(
        check(&w).is_empty(),
        "upper and lower port C are separate groups"
    );
}

#[test]
fn the_watchdog_is_a_free_output_line_or_none() {
    assert_eq!(parse_watchdog(" None ").unwrap(), None);
    let line = parse_watchdog("dda06 port b bit 0, active high").unwrap();
    assert_eq!(
        line,
        Some(Switch {
            bit: Bit::Dda06 { port: 1, bit: 0 },
            active_high: true
        })
    );
    let not_an_output = parse_watchdog("das08 ip 1, active high").unwrap_err();
    assert!(
        not_an_output.contains("cannot carry this signal"),
        "{not_an_output}"
    );
    let nonsense = parse_watchdog("blink").unwrap_err();
    assert!(
        nonsense.ends_with("; or none for no watchdog output"),
        "{nonsense}"
    );

    let mut w = robot();
    w.watchdog = parse_watchdog("das08 op 1, active high").unwrap();
    assert_eq!(
        check(&w),
        [(
            "watchdog",
            "das08 op 1 is already wired to main_power_on".to_string()
        )]
    );
    w.watchdog = parse_watchdog("dda06 port a bit 7, active low").unwrap();
    let problems = check(&w);
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].0, "watchdog");
    assert!(
        problems[0].1.starts_with(
            "dda06 port a bit 7 is in the same 8255 port group as the input end_switch_left"
        ),
        "{problems:?}"
    );
}

#[test]
fn a_two_contact_dead_man_is_held_only_while_its_contacts_disagree_and_a_broken_wire_lets_go() {
    let one_contact = robot();
    let two_contacts = Wiring {
        joystick_released: parse_second_contact("dda06 port a bit 3, active high").unwrap(),
        ..robot()
    };
    // Port A bit 2: the open contact (1 = closed); bit 3: the closed contact (1 = closed).
    let read = |w: &Wiring, open_contact: bool, closed_contact: bool| {
        let mut c = CardInputs::default();
        c.dda06_ports[0] = u8::from(open_contact) << 2 | u8::from(closed_contact) << 3;
        w.inputs(&c).joystick_enable
    };
    assert!(read(&two_contacts, true, false), "held");
    assert!(!read(&two_contacts, false, true), "let go");
    // A broken wire leaves its input floating, high or low: never "held".
    assert!(!read(&two_contacts, true, true));
    assert!(!read(&two_contacts, false, false));
    // One contact, active high: a broken wire that floats high reads as held.
    assert!(read(&one_contact, true, false));
    // The emulated robot's wires for "held" read back as held.
    let held = Inputs {
        joystick_enable: true,
        ..Inputs::default()
    };
    let back = two_contacts.inputs(&two_contacts.wires_for(&held));
    assert!(back.joystick_enable);
    assert!(
        !two_contacts
            .inputs(&two_contacts.wires_for(&Inputs::default()))
            .joystick_enable
    );
    // It shares no bit with another signal.
    let clash = Wiring {
        joystick_released: parse_second_contact("dda06 port a bit 2, active high").unwrap(),
        ..robot()
    };
    let problems = check(&clash);
    assert!(
        problems.iter().any(|(key, _)| *key == "joystick_released"),
        "{problems:?}"
    );
}

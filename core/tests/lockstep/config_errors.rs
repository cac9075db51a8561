//! Broken settings files each give an error naming the file, line, section and key.

use mechweed_core::config::Settings;

const SHIPPED: &str = include_str!("../../../config/robot.ini");

/// The shipped file with one line replaced; returns the 1-based line number too.
fn with_line(find: &str, replace: &str) -> (String, usize) {
    let line = SHIPPED.lines().position(|l| l.trim() == find).expect(find) + 1;
    (SHIPPED.replacen(find, replace, 1), line)
}

fn errors(text: &str, overrides: &[&str]) -> Vec<String> {
    let set: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match Settings::parse("robot.ini", text, &set) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn the_shipped_file_is_valid() {
    assert_eq!(errors(SHIPPED, &[]), Vec::<String>::new());
}

#[test]
fn not_a_number_names_line_section_and_key() {
    let (text, line) = with_line("kd = 2.0", "kd = abc");
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {line}: [pid.steer] kd = 'abc' is not a number"
        )]
    );
}

#[test]
fn out_of_range() {
    let (text, line) = with_line("rate_hz = 100", "rate_hz = 5");
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {line}: [supervisor] rate_hz = 5 is out of range (10 to 2000)"
        )]
    );
}

#[test]
fn unknown_key() {
    let (text, line) = with_line("speed_mps = 0.5", "speed_mps = 0.5\nspeeed_mps = 0.4");
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {}: [steer] speeed_mps is not a known setting",
            line + 1
        )]
    );
}

#[test]
fn missing_section_and_unknown_section() {
    let text = SHIPPED.replace("[joystick]", "[joystik]");
    let errs = errors(&text, &[]);
    assert!(
        errs.contains(&"robot.ini: missing section [joystick]".to_string()),
        "{errs:?}"
    );
    assert!(
        errs.iter()
            .any(|e| e.ends_with("unknown section [joystik]")),
        "{errs:?}"
    );
}

#[test]
fn missing_key_names_its_section_line() {
    let (text, _) = with_line("link_timeout_s = 0.5", "");
    let section_line = SHIPPED.lines().position(|l| l == "[camera]").unwrap() + 1;
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {section_line}: [camera] link_timeout_s is missing"
        )]
    );
}

#[test]
fn duplicate_key() {
    let (text, _) = with_line("seed = 1", "seed = 1\nseed = 2");
    let errs = errors(&text, &[]);
    assert!(
        errs.iter()
            .any(|e| e.contains("[sim] seed is set more than once")),
        "{errs:?}"
    );
}

#[test]
fn bad_event_script_names_the_item() {
    let errs = errors(SHIPPED, &["sim.events=1 mode autonomous, 2 estop_middle"]);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(
        errs[0].starts_with("--set sim.events=1 mode autonomous, 2 estop_middle: [sim] events:"),
        "{errs:?}"
    );
    assert!(errs[0].contains("estop_middle"), "{errs:?}");
}

#[test]
fn overrides_apply_and_bad_ones_are_named() {
    let s = Settings::parse(
        "robot.ini",
        SHIPPED,
        &["steer.speed_mps=0.3".into(), "pid.left.kp=20".into()],
    )
    .unwrap();
    assert_eq!(s.steer.speed_mps, 0.3);
    assert_eq!(s.pid_left.kp, 20.0);
    assert_eq!(
        errors(SHIPPED, &["pid.left.kp=abc"]),
        vec!["--set pid.left.kp=abc: [pid.left] kp = 'abc' is not a number".to_string()]
    );
    assert_eq!(
        errors(SHIPPED, &["steer.nope=1"]),
        vec!["--set steer.nope=1: [steer] nope is not a setting in robot.ini".to_string()]
    );
    assert_eq!(errors(SHIPPED, &["speed"]).len(), 1);
}

#[test]
fn every_error_is_reported_at_once() {
    let (text, _) = with_line("kd = 2.0", "kd = abc");
    let text = text
        .replacen("rate_hz = 100", "rate_hz = x", 1)
        .replace("[hw]", "[hardware]");
    assert!(errors(&text, &[]).len() >= 4, "{:?}", errors(&text, &[]));
}

#[test]
fn the_shipped_wiring_is_io_cards_md() {
    use mechweed_hw::cards::pci::CardLocation;
    let on_cards = [
        "hw.backend=cards".to_string(),
        "camera.port=/dev/ttyS0".to_string(),
    ];
    let s = Settings::parse("robot.ini", SHIPPED, &on_cards).unwrap();
    assert_eq!(s.backend, mechweed_core::config::Backend::Cards);
    assert_eq!(s.cards.das08, CardLocation::PciAuto);
    assert_eq!((s.io.battery_v.channel, s.io.battery_v.scale), (3, 10.0));
    assert_eq!(s.io.enc_steer_counts.channel, 3);
    assert_eq!(s.cards.dda06_ranges[0].name(), "+-10");
}

#[test]
fn two_signals_on_one_channel_name_the_second_key_and_its_line() {
    let (text, line) = with_line(
        "joystick_speed_v = das08 ai 2, scale 1",
        "joystick_speed_v = das08 ai 0, scale 1",
    );
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {line}: [io] joystick_speed_v: das08 ai 0 is already wired to pot_v"
        )]
    );
}

#[test]
fn a_channel_the_card_does_not_have_names_the_key() {
    let (text, line) = with_line(
        "tool_on = das08 op 4, active high",
        "tool_on = das08 op 5, active high",
    );
    assert_eq!(
        errors(&text, &[]),
        vec![format!(
            "robot.ini line {line}: [io] tool_on: das08 output op 5 does not exist: the card has 1..4"
        )]
    );
    let errs = errors(SHIPPED, &["io.amp_left_v=das08 ai 5, scale 1"]);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(errs[0].starts_with(
        "--set io.amp_left_v=das08 ai 5, scale 1: [io] amp_left_v: das08 ai 5 cannot carry"
    ));
}

#[test]
fn each_card_is_found_one_way() {
    use mechweed_hw::cards::pci::CardLocation;
    let set = [
        "hw.quad04_pci=none",
        "hw.quad04_port_base=0xE000",
        "hw.dda06_pci=0000:03:00.0",
    ];
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let s = Settings::parse("robot.ini", SHIPPED, &set).unwrap();
    assert_eq!(s.cards.quad04, CardLocation::PortBase(0xE000));
    assert_eq!(
        s.cards.dda06,
        CardLocation::PciAddress("0000:03:00.0".into())
    );

    let both = errors(SHIPPED, &["hw.das08_port_base=0xe000"]);
    assert_eq!(both.len(), 1, "{both:?}");
    assert!(both[0].contains("[hw] das08_pci: set das08_pci = none to use das08_port_base"));
    let neither = errors(SHIPPED, &["hw.das08_pci=none"]);
    assert!(neither[0].contains("set das08_pci (auto or an address) or das08_port_base"));
    let bad = errors(SHIPPED, &["hw.das08_pci=3:0.0"]);
    assert!(
        bad[0].contains("is not a PCI address like 0000:03:00.0"),
        "{bad:?}"
    );
}

#[test]
fn dac_ranges_are_six_known_ranges() {
    let few = errors(SHIPPED, &["hw.dda06_ranges_v=+-10, +-10"]);
    assert!(
        few[0].contains("[hw] dda06_ranges_v: needs six ranges"),
        "{few:?}"
    );
    let odd = errors(
        SHIPPED,
        &["hw.dda06_ranges_v=+-10, +-10, +-10, +-5, +-5, 0..20"],
    );
    assert!(odd[0].contains("AO5: '0..20' is not one of"), "{odd:?}");
}

#[test]
fn a_check_across_settings_is_placed_at_the_set_that_broke_it() {
    // As the tuning panel checks its values: a lower amplifier limit would blind the
    // encoder-stuck check.
    assert_eq!(
        errors(SHIPPED, &["pid.left.out_max_v=1.5"]),
        vec![
            "--set pid.left.out_max_v=1.5: [faults] encoder_stuck_v = 2 must be below \
             [pid.left] out_max_v = 1.5: the amplifier never gets there, so a stuck left \
             wheel encoder would never be noticed"
                .to_string()
        ]
    );
    // A value that is wrong on its own is not also reported by the checks across.
    assert_eq!(errors(SHIPPED, &["steer.speed_mps=fast"]).len(), 1);
}

#[test]
fn gnss_settings_that_cannot_work_are_named() {
    let (text, line) = with_line("trust = rtk_fixed, rtk_float", "trust = rtk_fixed, rtk");
    let got = errors(&text, &[]);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(
        got[0].starts_with(&format!("robot.ini line {line}: [gnss] trust"))
            && got[0].contains(
                "'rtk' is not a fix quality (one or more of rtk_fixed, rtk_float, dgps, gps"
            ),
        "{got:?}"
    );
    let got = errors(SHIPPED, &["gnss.origin=52.0,east"]);
    assert!(
        got[0].contains("'52.0,east' is not map or LAT,LON in degrees"),
        "{got:?}"
    );
    assert_eq!(
        errors(SHIPPED, &["gnss.origin=52.0, 5.66"]),
        Vec::<String>::new()
    );
    let got = errors(SHIPPED, &["gnss.port=bus"]);
    assert!(
        got[0].contains("the bus carries no GNSS positions"),
        "{got:?}"
    );
    // Steering by GNSS without a receiver.
    let got = errors(SHIPPED, &["steer.source=fused"]);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(
        got[0].contains("[steer] source = fused steers by GNSS, but [gnss] port = none"),
        "{got:?}"
    );
    assert_eq!(
        errors(SHIPPED, &["steer.source=fused", "gnss.port=sim"]),
        Vec::<String>::new()
    );
    // A receiver so late that, at the top speed, the filter could place no fix: each
    // would be refused and the robot would steer on odometry alone until GNSS timed out.
    let late = ["steer.source=gnss", "gnss.port=sim", "gnss.latency_s=0.9"];
    let got = errors(SHIPPED, &late);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(
        got[0].contains("[gnss] latency_s = 0.9 and a steer period of [steer] rate_hz = 10")
            && got[0].contains("beyond the 1 m the filter relates a fix over"),
        "{got:?}"
    );
    assert_eq!(
        errors(SHIPPED, &late[1..]),
        Vec::<String>::new(),
        "the camera steers"
    );
}

#[test]
fn the_realistic_fields_ranges_must_not_cross() {
    let got = errors(SHIPPED, &["sim.field_gap_min_m=3"]);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(
        got[0].contains("[sim] field_gap_min_m = 3 is larger than field_gap_max_m = 2"),
        "{got:?}"
    );
}

//! The real robot never runs on simulated parts: a settings file with `[hw] backend =
//! cards` and a simulated camera, receiver or field map is refused, each naming its key
//! and line, and `--real-robot` refuses a file that is not for the cards at all.

use mechweed_core::config::Settings;

const SHIPPED: &str = include_str!("../../../config/robot.ini");

/// The 1-based line of the first line reading `line`, after `after` (a section header).
fn line_of(text: &str, after: &str, line: &str) -> usize {
    let start = text.lines().position(|l| l.trim() == after).expect(after);
    start
        + 1
        + text
            .lines()
            .skip(start)
            .position(|l| l.trim() == line)
            .expect(line)
}

fn errors(text: &str) -> Vec<String> {
    match Settings::parse("robot.ini", text, &[]) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

/// The shipped file as a technician would first change it: only `[hw] backend`.
fn cards_only() -> String {
    SHIPPED.replacen("\nbackend = sim\n", "\nbackend = cards\n", 1)
}

#[test]
fn cards_with_the_simulated_camera_receiver_and_map_are_refused_each_by_key_and_line() {
    // The unsafe state: real amplifiers, simulated rows and fixes.
    let text = cards_only().replacen("\n[gnss]\n", "\n[gnss]\nport = sim\n", 1);
    let text = text.replacen("\nport = none\n", "\n", 1);
    let text = text.replacen("\nsource = camera\n", "\nsource = fused\n", 1);
    let found = errors(&text);
    let camera = line_of(&text, "[camera]", "port = sim");
    let gnss = line_of(&text, "[gnss]", "port = sim");
    let map = line_of(&text, "[gnss]", "map = sim");
    for (line, key) in [
        (camera, "[camera] port = sim"),
        (gnss, "[gnss] port = sim"),
        (map, "[gnss] map = sim"),
    ] {
        let want = format!("robot.ini line {line}: {key} is the simulated");
        assert!(
            found
                .iter()
                .any(|e| e.starts_with(&want) && e.contains("Set ")),
            "no '{want}' with what to set in {found:#?}"
        );
    }
    assert_eq!(found.len(), 3, "{found:#?}");
}

#[test]
fn cards_with_a_real_camera_and_no_receiver_are_taken_and_the_unused_map_is_not_judged() {
    let text = cards_only().replacen("\nport = sim\n", "\nport = /dev/ttyS0\n", 1);
    assert_eq!(errors(&text), Vec::<String>::new());
}

#[test]
fn a_file_for_the_real_robot_must_be_on_the_cards() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.ini");
    std::fs::write(&path, SHIPPED).unwrap();
    let refused = Settings::load_real_robot(&path).unwrap_err();
    let line = line_of(SHIPPED, "[hw]", "backend = sim");
    let text: Vec<String> = refused.iter().map(|e| e.to_string()).collect();
    assert!(
        text.iter()
            .any(|e| e.contains(&format!("line {line}: [hw] backend = sim"))),
        "{text:#?}"
    );
    // The shipped file on the cards still has the simulated camera: refused too.
    std::fs::write(&path, cards_only()).unwrap();
    let refused = Settings::load_real_robot(&path).unwrap_err();
    assert!(
        refused
            .iter()
            .any(|e| e.to_string().contains("[camera] port = sim"))
    );
    let real = cards_only().replacen("\nport = sim\n", "\nport = /dev/ttyS0\n", 1);
    std::fs::write(&path, real).unwrap();
    assert!(Settings::load_real_robot(&path).is_ok());
}

#[test]
fn on_the_cards_no_watchdog_line_is_refused_unless_no_relay_is_accepted_in_words() {
    // The unsafe state: the real robot, and nothing that stops it if the program is killed.
    let real = cards_only().replacen("\nport = sim\n", "\nport = /dev/ttyS0\n", 1);
    let unwatched = real.replacen(
        "\nwatchdog = dda06 port b bit 0, active high\n",
        "\nwatchdog = none\n",
        1,
    );
    let found = errors(&unwatched);
    let line = line_of(&unwatched, "[io]", "watchdog = none");
    assert_eq!(found.len(), 1, "{found:#?}");
    assert!(
        found[0].starts_with(&format!("robot.ini line {line}: [io] watchdog = none"))
            && found[0].contains("watchdog_relay = none_accepted"),
        "{found:#?}"
    );
    // Accepted in words: taken, and the settings say so for the start line.
    let accepted = unwatched.replacen(
        "\nwatchdog_relay = fitted\n",
        "\nwatchdog_relay = none_accepted\n",
        1,
    );
    let settings = Settings::parse("robot.ini", &accepted, &[]).unwrap();
    assert_eq!(
        settings.watchdog_relay,
        mechweed_core::config::WatchdogRelay::NoneAccepted
    );
    // A file from before the setting, without a watchdog line, is refused the same way;
    // on the simulated robot nothing is asked.
    let older = unwatched.replacen("\nwatchdog_relay = fitted\n", "\n", 1);
    assert_eq!(errors(&older).len(), 1);
    let sim = SHIPPED.replacen(
        "\nwatchdog = dda06 port b bit 0, active high\n",
        "\nwatchdog = none\n",
        1,
    );
    assert_eq!(errors(&sim), Vec::<String>::new());
}

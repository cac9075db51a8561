//! What the bus and its tools say is true: the loops' figures agree with the run's own
//! summary, and a tool with nothing to reach, or a flow the robot does not have, says
//! so in seconds instead of waiting in silence.

use std::time::{Duration, Instant};

use super::{Robot, endpoint, free_port, json_lines};
use crate::common::{mechweed, text};

/// `steer loop: N ticks at R Hz` from the run's closing summary.
fn summary_ticks(stdout: &str, name: &str) -> f64 {
    let line = (stdout.lines())
        .find(|l| l.trim_start().starts_with(&format!("{name} loop: ")))
        .unwrap_or_else(|| panic!("no {name} loop line: {stdout}"));
    let after = line.split("loop: ").nth(1).unwrap();
    after.split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn the_steer_loops_rate_on_the_bus_is_the_one_the_run_summary_gives() {
    let _machine = crate::shared_machine();
    // Camera frames wake the steer thread between its scheduled ticks; it published its
    // figures only on scheduled ticks that were a multiple of its rate, and the bus said
    // "steer 0 Hz, 0 ticks" (or froze) while the summary counted over a thousand.
    let robot = Robot::start(&["--mode", "autonomous", "--duration", "12"]);
    let status_at = |wait_s: f64| {
        std::thread::sleep(Duration::from_secs_f64(wait_s));
        let out = robot.bus(&["echo", "status", "--count", "1"]);
        let p = json_lines(&out)[0]["payload"].clone();
        let steer = &p["loops"]["steer"];
        (
            p["t_s"].as_f64().unwrap(),
            steer["ticks"].as_f64().unwrap(),
            steer["rate_hz"].as_f64().unwrap(),
        )
    };
    let (t0, ticks0, rate_hz) = status_at(2.0);
    let (t1, ticks1, _) = status_at(6.0);
    let (stdout, _, _) = robot.finish();
    assert!(
        rate_hz > 0.0 && ticks1 > ticks0,
        "{ticks0} then {ticks1} ticks at {rate_hz} Hz"
    );
    let on_bus = (ticks1 - ticks0) / (t1 - t0);
    let in_summary = summary_ticks(&stdout, "steer") / 12.0;
    assert!(
        (on_bus / in_summary - 1.0).abs() < 0.10,
        "steer {on_bus:.2} ticks/s on the bus, {in_summary:.2} in the summary\n{stdout}"
    );
}

#[test]
fn tools_with_nothing_to_reach_say_so_in_seconds_naming_the_endpoint() {
    let _machine = crate::shared_machine();
    let nowhere = endpoint(free_port());
    for args in [
        &["get", "supervisor.rate_hz"][..],
        &["list", "--seconds", "1"],
    ] {
        let started = Instant::now();
        let out = mechweed()
            .arg("bus")
            .args(args)
            .args(["--connect", &nowhere])
            .output()
            .unwrap();
        let said = text(&out.stderr);
        assert!(!out.status.success(), "{args:?}: {said}");
        assert!(
            started.elapsed() < Duration::from_secs(15),
            "{args:?} took {:?}",
            started.elapsed()
        );
        assert!(
            said.contains(&nowhere),
            "{args:?} does not name {nowhere}: {said}"
        );
        assert!(
            !said.contains(".rs:"),
            "{args:?} quotes a source file: {said}"
        );
    }
    // A subscriber waits for the robot, but not in silence.
    let out = mechweed()
        .args([
            "bus",
            "echo",
            "status",
            "--seconds",
            "6",
            "--connect",
            &nowhere,
        ])
        .output()
        .unwrap();
    let said = text(&out.stderr);
    assert!(
        said.contains(&format!(
            "no mechweed robot program 'mechweed' answers at {nowhere}"
        )),
        "{said}"
    );
}

#[test]
fn a_flow_the_robot_does_not_have_is_refused_with_the_ones_it_has() {
    let _machine = crate::shared_machine();
    // "events" for "event": it waited for ever.
    let started = Instant::now();
    let out = mechweed()
        .args(["bus", "echo", "events", "--connect", &endpoint(free_port())])
        .output()
        .unwrap();
    let said = text(&out.stderr);
    assert!(!out.status.success(), "{said}");
    assert!(started.elapsed() < Duration::from_secs(5));
    assert!(
        said.contains("'events' is not a flow of the robot"),
        "{said}"
    );
    assert!(said.contains("status, tick, event, camera/row"), "{said}");
}

/// `bus list` names every program on the robot's bus, not only the robot program: a
/// tool's session sees the robot's token alone, so the robot's status names the rest.
#[test]
fn bus_list_names_every_program_present() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "10"]);
    let mut camsim = mechweed()
        .args(["camsim", "--bus", "--connect", &robot.endpoint])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut echo = robot
        .bus_command(&["echo", "tick", "--seconds", "8"])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let echo_token = format!("mechweed/alive/echo-{}", echo.id());
    let from = Instant::now();
    let said = loop {
        let said = text(&robot.bus(&["list", "--seconds", "0.5"]).stdout);
        if said.contains("mechweed/alive/camsim") && said.contains(&echo_token) {
            break said;
        }
        assert!(from.elapsed().as_secs() < 8, "{said}");
    };
    assert!(said.contains("mechweed/alive/controller"), "{said}");
    let _ = (camsim.kill(), echo.kill());
    let _ = (camsim.wait(), echo.wait());
}

/// A receiver says what it gets, and the robot's status names it with that: the
/// off-board recorder here, whose figures `cluster status` then shows.
#[test]
fn the_robots_status_names_each_receiver_with_what_it_gets() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "10"]);
    let folder = tempfile::tempdir().unwrap();
    let mut recorder = mechweed()
        .args([
            "record",
            "--bus",
            "--connect",
            &robot.endpoint,
            "--seconds",
            "8",
        ])
        .arg("--set")
        .arg(format!("record.folder={}", folder.path().display()))
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let name = format!("record-{}", recorder.id());
    let from = Instant::now();
    let seen = loop {
        let status = json_lines(&robot.bus(&["echo", "status", "--count", "1"]));
        let receivers = status[0]["payload"]["bus"]["receivers"].clone();
        let mine = (receivers.as_array().into_iter().flatten())
            .find(|r| r["name"] == name.as_str())
            .cloned();
        if let Some(mine) = mine.filter(|m| m["report"]["received"].as_u64() > Some(10)) {
            break mine;
        }
        assert!(from.elapsed() < Duration::from_secs(8), "{receivers}");
        std::thread::sleep(Duration::from_millis(200));
    };
    assert_eq!(seen["report"]["program"], "off-board recorder", "{seen}");
    assert!(
        seen["report"]["status_age_s"].as_f64().unwrap() < 2.0,
        "{seen}"
    );
    assert_eq!(seen["report"]["wrong_key"], 0, "{seen}");
    let _ = recorder.kill();
    let _ = recorder.wait();
}

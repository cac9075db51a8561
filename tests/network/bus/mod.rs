//! The bus between real processes on loopback: the robot program (`mechweed run
//! --headless`) and the bus tools (`mechweed bus ...`, `camsim --bus`), each test on
//! ports of its own.

use crate::common;
mod flap;
mod flood;
mod gnss;
mod guards;
mod hearing;
mod holders;
mod input;
mod junk;
mod netns;
mod process;
pub mod secured;
mod sockets;
mod starve;
mod third_party;
mod truth;

use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{mechweed, text};

/// A port no one listens on now.
/// A query's reply as text: the answer's payload, or the error's.
pub fn reply_text(reply: &zenoh::query::Reply) -> String {
    let body = match reply.result() {
        Ok(sample) => sample.payload().to_bytes().into_owned(),
        Err(error) => error.payload().to_bytes().into_owned(),
    };
    text(&body)
}

pub fn free_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    listener.local_addr().unwrap().port()
}

pub fn endpoint(port: u16) -> String {
    format!("tcp/127.0.0.1:{port}")
}

/// The shipped [bus] listen, as config/robot.ini says it.
pub fn shipped_listen() -> String {
    let listen = mechweed::config::Settings::shipped().bus.listen;
    assert_eq!(listen.len(), 1, "{listen:?}");
    listen[0].clone()
}

/// A robot program with its bus listening at `endpoint`, recording into `folder`.
pub struct Robot {
    /// None once `finish` has waited for it.
    child: Option<Child>,
    pub endpoint: String,
    folder: Option<tempfile::TempDir>,
    /// What every `bus` tool is given besides --connect (a secured robot's identity).
    pub tool_args: Vec<String>,
}

/// A test that fails half-way leaves no robot program running behind it.
impl Drop for Robot {
    fn drop(&mut self) {
        if let Some(child) = &mut self.child {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

impl Robot {
    /// `mechweed run --headless ARGS` with the bus listening on a loopback port of its
    /// own, once it answers.
    pub fn start(args: &[&str]) -> Robot {
        let robot = Robot::spawn(Some(endpoint(free_port())), args);
        robot.wait_until_answering();
        robot
    }

    /// `mechweed run --headless ARGS` with the bus on, listening at `listen` (None: the
    /// shipped [bus] listen), without waiting for it.
    pub fn spawn(listen: Option<String>, args: &[&str]) -> Robot {
        let folder = tempfile::tempdir().unwrap();
        let mut cmd = mechweed();
        cmd.args(["run", "--headless"])
            .args(common::test_run_settings(folder.path()))
            .args(["--set", "bus.enabled=yes"]);
        if let Some(listen) = &listen {
            cmd.arg("--set").arg(format!("bus.listen={listen}"));
        }
        let child = cmd
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        Robot {
            child: Some(child),
            endpoint: listen.unwrap_or_else(shipped_listen),
            folder: Some(folder),
            tool_args: Vec::new(),
        }
    }

    /// The bus answers once the controller runs (at most 10 s on a busy machine).
    pub fn wait_until_answering(&self) {
        let end = Instant::now() + Duration::from_secs(10);
        while Instant::now() < end {
            if self.bus(&["get", "supervisor.rate_hz"]).status.success() {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        panic!("the robot program never answered on its bus");
    }

    /// `mechweed bus ARGS --connect` this robot.
    pub fn bus(&self, args: &[&str]) -> Output {
        self.bus_command(args).output().unwrap()
    }

    pub fn bus_command(&self, args: &[&str]) -> Command {
        let mut cmd = mechweed();
        cmd.arg("bus")
            .args(args)
            .arg("--connect")
            .arg(&self.endpoint)
            .args(&self.tool_args);
        cmd
    }

    /// Power up and ask for autonomous over the bus (accept_requests = operator); the
    /// contactor takes a moment to close, so autonomous is asked until accepted.
    pub fn power_up_and_drive(&self) {
        assert!(self.bus(&["request", "power_up"]).status.success());
        let end = Instant::now() + Duration::from_secs(3);
        while !self
            .bus(&["request", "mode", "autonomous"])
            .status
            .success()
        {
            assert!(Instant::now() < end, "autonomous never accepted");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Wait for the run to end (it was given a --duration); its stdout and stderr, and
    /// the folder of its record (deleted when dropped).
    pub fn finish(mut self) -> (String, String, tempfile::TempDir) {
        let child = self.child.take().expect("running");
        let out = child.wait_with_output().unwrap();
        let folder = self.folder.take().expect("made at start");
        (text(&out.stdout), text(&out.stderr), folder)
    }

    /// The robot program's process id.
    pub fn pid(&self) -> u32 {
        self.child.as_ref().map_or(0, Child::id)
    }
}

/// One JSON line per message, as `bus echo` prints them.
pub fn json_lines(out: &Output) -> Vec<serde_json::Value> {
    text(&out.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

#[test]
fn a_headless_run_publishes_status_ticks_and_a_fault_event() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "8", "--set", "sim.events=4 estop_front"]);
    let status = robot.bus(&["echo", "status", "--count", "3"]);
    let ticks = robot.bus(&["echo", "tick", "--count", "3"]);
    let events = robot.bus(&["echo", "event", "--seconds", "4"]);
    let (stdout, _, _) = robot.finish();
    let status = json_lines(&status);
    assert_eq!(status.len(), 3, "{status:?}");
    for s in &status {
        let p = &s["payload"];
        assert_eq!(s["key"], "mechweed/status");
        assert_eq!(p["mode"], "halt", "{p}");
        assert!(p["battery_v"].as_f64().unwrap() > 20.0, "{p}");
        assert!(p["loops"]["supervisor"]["rate_hz"].is_number(), "{p}");
    }
    // Ticks carry the record's columns, in its names and units.
    let ticks = json_lines(&ticks);
    assert_eq!(ticks.len(), 3);
    for column in ["t_s", "tick", "mode", "amp_left_v", "battery_v", "cam_seq"] {
        assert!(
            !ticks[0]["payload"][column].is_null(),
            "{column}: {}",
            ticks[0]
        );
    }
    let tick_numbers: Vec<u64> = ticks
        .iter()
        .map(|t| t["payload"]["tick"].as_u64().unwrap())
        .collect();
    assert!(
        tick_numbers.windows(2).all(|w| w[1] > w[0]),
        "{tick_numbers:?}"
    );
    // The fault as the console says it.
    let events = json_lines(&events);
    let fault = events
        .iter()
        .find(|e| e["payload"]["kind"] == "fault")
        .unwrap_or_else(|| panic!("no fault event in {events:?}\n{stdout}"));
    assert!(
        fault["payload"]["text"]
            .as_str()
            .unwrap()
            .contains("front emergency stop pressed"),
        "{fault}"
    );
}

#[test]
fn halt_over_the_bus_stops_an_autonomous_run_and_the_robot_says_who_asked() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--mode", "autonomous", "--duration", "8"]);
    std::thread::sleep(Duration::from_secs(2));
    let halt = robot.bus(&["request", "halt"]);
    assert!(halt.status.success(), "{}", text(&halt.stderr));
    assert_eq!(text(&halt.stdout).trim(), "accepted");
    let (stdout, stderr, _) = robot.finish();
    assert!(stdout.contains("mode: autonomous -> halt"), "{stdout}");
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    assert!(
        stderr.contains("bus: halt requested by another program: accepted"),
        "{stderr}"
    );
}

#[test]
fn a_mode_request_is_refused_by_default_and_decided_by_the_supervisor_with_operator() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "6"]);
    let refused = robot.bus(&["request", "mode", "autonomous"]);
    assert!(!refused.status.success());
    assert!(
        text(&refused.stderr)
            .contains("refused: the bus may only ask for halt here ([bus] accept_requests = halt)"),
        "{}",
        text(&refused.stderr)
    );
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("final mode: halt"), "{stdout}");

    let robot = Robot::start(&["--duration", "6", "--set", "bus.accept_requests=operator"]);
    // The supervisor's own refusal, in the GUI's words.
    let unpowered = robot.bus(&["request", "mode", "autonomous"]);
    assert!(
        text(&unpowered.stderr).contains("refused: motor power is off: press Power up first"),
        "{}",
        text(&unpowered.stderr)
    );
    robot.power_up_and_drive();
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("mode: halt -> autonomous"), "{stdout}");
}

#[test]
fn a_setting_set_in_halt_is_taken_and_refused_while_driving() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "8", "--set", "bus.accept_requests=operator"]);
    let get = robot.bus(&["get", "pid.left.kp"]);
    assert!(
        text(&get.stdout).starts_with("pid.left.kp = "),
        "{}",
        text(&get.stdout)
    );
    let set = robot.bus(&["set", "pid.left.kp", "21.5"]);
    assert!(set.status.success(), "{}", text(&set.stderr));
    let get = robot.bus(&["get", "pid.left.kp"]);
    assert!(
        text(&get.stdout).starts_with("pid.left.kp = 21.5"),
        "{}",
        text(&get.stdout)
    );
    // Out of range: checked as robot.ini is, and nothing changes.
    let wild = robot.bus(&["set", "pid.left.kp", "1e9"]);
    assert!(!wild.status.success());
    assert!(
        text(&wild.stderr).contains("[pid.left] kp"),
        "{}",
        text(&wild.stderr)
    );
    assert!(text(&robot.bus(&["get", "pid.left.kp"]).stdout).starts_with("pid.left.kp = 21.5"));
    // A setting read at start is not changed on a running robot.
    let start_only = robot.bus(&["set", "faults.battery_min_v", "20"]);
    assert!(text(&start_only.stderr).contains("is read when the program starts"));
    // The steer thread's period and back-off are read when it starts: refused, not
    // "accepted" and left unchanged.
    for setting in ["steer.rate_hz", "steer.endswitch_back_deg"] {
        let value = if setting == "steer.rate_hz" {
            "50"
        } else {
            "3"
        };
        let refused = robot.bus(&["set", setting, value]);
        assert!(
            !refused.status.success(),
            "{setting}: {}",
            text(&refused.stdout)
        );
        assert!(
            text(&refused.stderr).contains("is read when the threads start"),
            "{}",
            text(&refused.stderr)
        );
    }
    // Driving: the supervisor refuses, as it does the GUI's Apply.
    robot.power_up_and_drive();
    let moving = robot.bus(&["set", "pid.left.kp", "25"]);
    assert!(!moving.status.success());
    assert!(
        text(&moving.stderr).contains("changed only in halt"),
        "{}",
        text(&moving.stderr)
    );
    assert!(text(&robot.bus(&["get", "pid.left.kp"]).stdout).starts_with("pid.left.kp = 21.5"));
    robot.finish();
}

#[test]
fn a_port_in_use_is_one_clear_error_or_a_run_without_the_bus() {
    let _machine = crate::shared_machine();
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port();
    let dir = tempfile::tempdir().unwrap();
    let run = |required: &str| {
        mechweed()
            .args(["run", "--headless", "--duration", "1"])
            .args(common::test_run_settings(dir.path()))
            .args(["--set", "bus.enabled=yes", "--set"])
            .arg(format!("bus.listen={}", endpoint(port)))
            .args(["--set", &format!("bus.required={required}")])
            .output()
            .unwrap()
    };
    let required = run("yes");
    assert!(!required.status.success());
    let why = text(&required.stderr);
    assert!(
        why.contains(&format!(
            "cannot listen on tcp/127.0.0.1:{port} ([bus] listen): port {port} is already in use"
        )),
        "{why}"
    );
    let optional = run("no");
    assert!(optional.status.success(), "{}", text(&optional.stderr));
    assert!(text(&optional.stderr).contains("the robot runs without the bus"));
    assert!(
        text(&optional.stdout).contains("bus: off"),
        "{}",
        text(&optional.stdout)
    );
}

/// A receiver that takes 0.4 s over each status, four times the publishing period, as a
/// receiver must: zenoh's callback hands each message to a ring of one place and the
/// slow work happens outside it (`bus echo --slow`). A receiver that sleeps inside
/// zenoh's callback holds up its own session, and its backlog grows there whatever the
/// robot does (docs/bus.md).
#[test]
fn a_slow_receiver_gets_the_newest_status_and_the_robot_does_not_wait() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--mode", "autonomous", "--duration", "10"]);
    let slow = robot.bus(&["echo", "status", "--seconds", "6", "--slow", "0.4"]);
    let lines = json_lines(&slow);
    assert!(lines.len() >= 10, "{} messages", lines.len());
    for line in &lines {
        let age_s =
            line["received_s"].as_f64().unwrap() - line["payload"]["wall_s"].as_f64().unwrap();
        assert!(age_s < 1.0, "a status {age_s:.2} s old: {line}");
    }
    // The loops never waited: the run drove on to its end without a fault.
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("faults: none"), "{stdout}");
    assert!(stdout.contains("final mode: autonomous"), "{stdout}");
}

//! The bus in a process of its own: the robot program's bus process killed, and the
//! robot program killed, as a defect in the network library or an operator's kill
//! would do it.

use std::time::{Duration, Instant};

use super::{Robot, json_lines};

/// The processes whose parent is `pid`, from /proc.
pub(super) fn children_of(pid: u32) -> Vec<u32> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|&child| parent_of(child) == Some(pid))
        .collect()
}

/// The parent and state of `pid` by /proc/PID/stat (the fields after the name).
fn stat(pid: u32) -> Option<(char, u32)> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let mut after_name = stat.rsplit_once(')')?.1.split_whitespace();
    let state = after_name.next()?.chars().next()?;
    Some((state, after_name.next()?.parse().ok()?))
}

fn parent_of(pid: u32) -> Option<u32> {
    stat(pid).map(|(_, parent)| parent)
}

/// Whether `pid` has ended (gone, or a zombie nobody has reaped yet).
fn ended(pid: u32) -> bool {
    stat(pid).is_none_or(|(state, _)| state == 'Z' || state == 'X')
}

/// The one `mechweed bus-gateway` the robot program runs.
fn bus_process_of(robot: u32) -> u32 {
    let gateways: Vec<u32> = children_of(robot)
        .into_iter()
        .filter(|&pid| {
            std::fs::read(format!("/proc/{pid}/cmdline"))
                .is_ok_and(|c| c.split(|&b| b == 0).any(|arg| arg == b"bus-gateway"))
                && !ended(pid)
        })
        .collect();
    assert_eq!(gateways.len(), 1, "bus processes of {robot}: {gateways:?}");
    gateways[0]
}

/// The names of `pid`'s threads.
fn thread_names(pid: u32) -> Vec<String> {
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task")).unwrap();
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok())
        .map(|name| name.trim().to_string())
        .collect()
}

fn kill(pid: u32, signal: i32) {
    // SAFETY: kill(2) on a process id this test found among the robot's children.
    assert_eq!(unsafe { libc::kill(pid as i32, signal) }, 0, "kill {pid}");
}

/// Wait until the robot answers on its bus again; how long it took.
fn answering_again(robot: &Robot, within: Duration) -> Duration {
    let from = Instant::now();
    while !robot.bus(&["get", "supervisor.rate_hz"]).status.success() {
        assert!(
            from.elapsed() < within,
            "no answer {within:?} after the kill"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    from.elapsed()
}

#[test]
fn the_bus_process_killed_the_robot_drives_on_and_starts_it_again() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--mode", "autonomous", "--duration", "14"]);
    std::thread::sleep(Duration::from_secs(3));
    let first = bus_process_of(robot.pid());
    kill(first, libc::SIGKILL);
    let back_after = answering_again(&robot, Duration::from_secs(10));
    eprintln!(
        "the robot answered on its bus again {back_after:?} after its bus process was killed"
    );
    let second = bus_process_of(robot.pid());
    assert_ne!(first, second);
    // A tool sees status again.
    let status = json_lines(&robot.bus(&["echo", "status", "--count", "2"]));
    assert_eq!(status.len(), 2, "{status:?}");
    assert_eq!(status[1]["payload"]["mode"], "autonomous", "{}", status[1]);
    let (stdout, _, _) = robot.finish();
    assert!(
        stdout.contains("bus: the bus process ended (signal 9 (killed)): restarting in 1 s"),
        "{stdout}"
    );
    assert!(
        stdout.contains("bus: the bus process runs again (restart 1"),
        "{stdout}"
    );
    assert!(
        stdout.contains("the bus process was started again 1 times"),
        "{stdout}"
    );
    // The robot drove on: no fault, still autonomous at the end.
    assert!(stdout.contains("faults: none"), "{stdout}");
    assert!(stdout.contains("final mode: autonomous"), "{stdout}");
    let lateness: Vec<&str> = stdout.lines().filter(|l| l.contains("late")).collect();
    eprintln!("{}", lateness.join("\n"));
}

#[test]
fn rows_from_the_bus_stop_with_the_bus_process_and_the_robot_faults_as_for_a_lost_camera() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&[
        "--duration",
        "12",
        "--set",
        "camera.port=bus",
        "--set",
        "sim.events=3 power_up, 4 mode autonomous",
    ]);
    let mut camsim = crate::common::mechweed()
        .args(["camsim", "--bus", "--connect", &robot.endpoint])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(6));
    let status = json_lines(&robot.bus(&["echo", "status", "--count", "1"]));
    assert_eq!(status[0]["payload"]["mode"], "autonomous", "{status:?}");
    kill(bus_process_of(robot.pid()), libc::SIGKILL);
    std::thread::sleep(Duration::from_secs(2));
    let _ = camsim.kill();
    let _ = camsim.wait();
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("FAULT: camera link lost"), "{stdout}");
    assert!(
        stdout.contains("bus: the bus process ended (signal 9"),
        "{stdout}"
    );
}

#[test]
fn the_robot_program_killed_its_bus_process_ends_too() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "30"]);
    let gateway = bus_process_of(robot.pid());
    kill(robot.pid(), libc::SIGKILL);
    let from = Instant::now();
    while !ended(gateway) {
        assert!(
            from.elapsed() < Duration::from_secs(3),
            "the bus process {gateway} outlived its robot program by 3 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    eprintln!(
        "the bus process ended {:?} after its robot program",
        from.elapsed()
    );
}

/// None of the network library's threads runs in the controller: they are all in the
/// bus process. The names to look for are taken from the bus process itself.
#[test]
fn the_controller_runs_no_thread_of_the_network_library() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "8"]);
    let gateway = bus_process_of(robot.pid());
    let controller = thread_names(robot.pid());
    let own = ["mechweed", "to-controller", "from-controller"];
    let network: Vec<String> = (thread_names(gateway).into_iter())
        .filter(|name| !own.contains(&name.as_str()))
        .collect();
    assert!(
        !network.is_empty(),
        "the bus process has no thread of its library"
    );
    let shared: Vec<&String> = controller.iter().filter(|n| network.contains(n)).collect();
    assert!(
        shared.is_empty(),
        "the controller runs {shared:?}, threads of the network library (its threads: {controller:?})"
    );
    for thread in ["supervisor", "steer", "camlink", "bus"] {
        assert!(
            controller.iter().any(|n| n == thread),
            "{thread}: {controller:?}"
        );
    }
    drop(robot);
}

/// `watch`'s view of a robot whose bus process is killed: a HALT sent while it is away
/// is said as no answer, and the same view shows the robot's status again once the bus
/// process runs again.
#[test]
fn a_view_recovers_when_the_robot_starts_its_bus_process_again() {
    use mechweed::gui::remote::RemoteView;
    use mechweed::gui::view::ViewSource;
    use mechweed::state::modes::{Mode, Request};
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "20"]);
    let mut view = RemoteView::connect(&robot.endpoint, "mechweed", None).unwrap();
    let status_time = |view: &mut RemoteView| view.view().status.t_s;
    let wait_for = |view: &mut RemoteView, after_s: f64, what: &str| {
        let from = Instant::now();
        while status_time(view) <= after_s {
            assert!(from.elapsed() < Duration::from_secs(15), "{what}");
            std::thread::sleep(Duration::from_millis(50));
        }
        from.elapsed()
    };
    wait_for(&mut view, 0.0, "no status before the kill");
    kill(bus_process_of(robot.pid()), libc::SIGKILL);
    let killed_at_s = status_time(&mut view);
    let (reply, _) = crossbeam_channel::bounded(1);
    view.send(Request::Mode(Mode::Halt), &reply).unwrap();
    let from = Instant::now();
    let answer = loop {
        if let Some(said) = view.answers_in_words().pop() {
            break said;
        }
        assert!(
            from.elapsed() < Duration::from_secs(5),
            "the HALT got nothing at all"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(
        answer,
        (Request::Mode(Mode::Halt), Err("no answer".to_string()))
    );
    let back = wait_for(
        &mut view,
        killed_at_s + 0.5,
        "the view never saw status again",
    );
    eprintln!("the view saw status again {back:?} after the HALT's no answer");
    drop(robot);
}

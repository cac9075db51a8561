//! The gamepad end to end: a virtual gamepad made through /dev/uinput drives the
//! simulated robot (the program itself, `run --headless`) forward and left in joystick
//! mode, and pulling it out stops the robot within the time-out. Skips with a message
//! where the machine cannot make input devices (no uinput in the kernel, no permission,
//! or no device files appearing in /dev/input).

use crate::common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{mechweed, test_run_settings};
use evdev::uinput::VirtualDevice;
use evdev::{
    AbsInfo, AbsoluteAxisCode, AttributeSet, EventType, InputEvent, KeyCode, UinputAbsSetup,
};

/// The shipped [joystick] gamepad_timeout_s.
const TIMEOUT_S: f64 = 1.0;

/// A pad like most USB pads: two sticks' worth of axes, face and shoulder buttons.
fn virtual_pad() -> Result<(VirtualDevice, PathBuf), String> {
    let why = |e: std::io::Error| e.to_string();
    let mut keys = AttributeSet::<KeyCode>::new();
    for key in [
        KeyCode::BTN_SOUTH,
        KeyCode::BTN_EAST,
        KeyCode::BTN_TL,
        KeyCode::BTN_TR,
    ] {
        keys.insert(key);
    }
    // No fuzz: the kernel passes on a change of one count (a pad's driver may ignore a
    // few counts; the test's stick wanders by one to keep the pad alive).
    let axis = |code| UinputAbsSetup::new(code, AbsInfo::new(0, -32768, 32767, 0, 0, 0));
    let mut pad = VirtualDevice::builder()
        .map_err(|e| format!("/dev/uinput: {e}"))?
        .name("mechweed test pad")
        .with_keys(&keys)
        .map_err(why)?
        .with_absolute_axis(&axis(AbsoluteAxisCode::ABS_X))
        .map_err(why)?
        .with_absolute_axis(&axis(AbsoluteAxisCode::ABS_Y))
        .map_err(why)?
        .build()
        .map_err(why)?;
    // The device file is made by devtmpfs or udev, a moment after the device.
    let end = Instant::now() + Duration::from_secs(5);
    while Instant::now() < end {
        let nodes = pad.enumerate_dev_nodes_blocking().map_err(why)?;
        // The file appears first, readable a moment later (udev sets its group and mode).
        let readable = |p: &PathBuf| evdev::Device::open(p).is_ok();
        if let Some(path) = nodes.filter_map(Result::ok).find(readable) {
            return Ok((pad, path));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Err("no readable device file for it appeared in /dev/input".into())
}

fn send(pad: &mut VirtualDevice, events: &[(EventType, u16, i32)]) {
    let events: Vec<InputEvent> = events
        .iter()
        .map(|&(kind, code, value)| InputEvent::new(kind.0, code, value))
        .collect();
    pad.emit(&events).expect("the virtual pad takes events");
}

/// Lines of the program's output as they come, with the time each arrived.
fn lines_of(child: &mut std::process::Child) -> mpsc::Receiver<(Instant, String)> {
    let (tx, rx) = mpsc::channel();
    let out: Box<dyn std::io::Read + Send> = Box::new(child.stdout.take().unwrap());
    let err: Box<dyn std::io::Read + Send> = Box::new(child.stderr.take().unwrap());
    for stream in [out, err] {
        let tx = tx.clone();
        std::thread::spawn(move || {
            for line in BufReader::new(stream).lines().map_while(Result::ok) {
                let _ = tx.send((Instant::now(), line));
            }
        });
    }
    rx
}

/// Wait (up to 20 s) until a line containing each of `words` has come, in any order;
/// when and what each line was. Every line so far goes into `seen`.
fn wait_for_all(
    lines: &mpsc::Receiver<(Instant, String)>,
    words: &[&str],
    seen: &mut String,
) -> Vec<(Instant, String)> {
    let end = Instant::now() + Duration::from_secs(20);
    let mut found: Vec<Option<(Instant, String)>> = vec![None; words.len()];
    while found.iter().any(Option::is_none) {
        let left = end.saturating_duration_since(Instant::now());
        let Ok((at, line)) = lines.recv_timeout(left) else {
            panic!("no line with each of {words:?} from the program:\n{seen}");
        };
        seen.push_str(&line);
        seen.push('\n');
        for (i, w) in words.iter().enumerate() {
            if found[i].is_none() && line.contains(w) {
                found[i] = Some((at, line.clone()));
            }
        }
    }
    found.into_iter().map(Option::unwrap).collect()
}

/// The record's rows as (t_s, joystick_enable, speed_mps, wheel_angle_rad, brakes on).
fn record_rows(folder: &Path) -> Vec<(f64, bool, f64, f64, bool)> {
    let csv = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.extension().is_some_and(|x| x == "csv")
                && !p.to_string_lossy().ends_with(".events.csv")
        })
        .expect("the run left a record");
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, enable, speed, angle, brake) = (
        col("t_s"),
        col("joystick_enable"),
        col("speed_mps"),
        col("wheel_angle_rad"),
        col("brake_release_left"),
    );
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |i: usize| f[i].parse::<f64>().unwrap();
            let on = |i: usize| matches!(f[i], "1" | "true");
            (num(t), on(enable), num(speed), num(angle), !on(brake))
        })
        .collect()
}

#[test]
fn a_virtual_gamepad_drives_the_simulated_robot_and_pulled_out_stops_it() {
    let (mut pad, path) = match virtual_pad() {
        Ok(pad) => pad,
        Err(why) => {
            eprintln!("skipped: this machine cannot make a virtual gamepad ({why})");
            return;
        }
    };
    let folder = tempfile::tempdir().unwrap();
    let mut child = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "joystick",
            "--duration",
            "12",
        ])
        .args(["--set", "joystick.source=gamepad"])
        .arg("--set")
        .arg(format!("joystick.gamepad_device={}", path.display()))
        .args(test_run_settings(folder.path()))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lines = lines_of(&mut child);
    let mut seen = String::new();
    // "   0.24 s  mode: halt -> joystick": the controller's clock against the test's.
    let words = ["gamepad mechweed test pad", "mode: halt -> joystick"];
    let (at, line) = wait_for_all(&lines, &words, &mut seen).remove(1);
    let t_mode_s: f64 = line.split_whitespace().next().unwrap().parse().unwrap();
    let controller_s = |when: Instant| t_mode_s + when.duration_since(at).as_secs_f64();

    // Dead-man held, stick full forward and half left, for 3 s; the stick wanders by a
    // count, as under a thumb, so the pad is never silent.
    let (abs, key) = (EventType::ABSOLUTE, EventType::KEY);
    let (x, y) = (AbsoluteAxisCode::ABS_X.0, AbsoluteAxisCode::ABS_Y.0);
    send(
        &mut pad,
        &[
            (key, KeyCode::BTN_TL.code(), 1),
            (abs, x, -16384),
            (abs, y, -32767),
        ],
    );
    let driving = Instant::now();
    let mut n = 0;
    while driving.elapsed() < Duration::from_secs(3) {
        n += 1;
        send(&mut pad, &[(abs, y, -32767 + n % 2)]);
        std::thread::sleep(Duration::from_millis(100));
    }
    let pulled = Instant::now();
    drop(pad);
    let lost_line = ["gamepad mechweed test pad lost"];
    let (lost, _) = wait_for_all(&lines, &lost_line, &mut seen).remove(0);
    let silent = seen.contains("nothing from the gamepad");
    assert!(!silent, "the pad went silent while driving:\n{seen}");
    let status = child.wait().unwrap();
    assert!(status.success(), "{seen}");

    let rows = record_rows(folder.path());
    let enabled: Vec<_> = rows.iter().filter(|r| r.1).collect();
    assert!(
        !enabled.is_empty(),
        "the dead-man never counted as held:\n{seen}"
    );
    let top_speed = enabled.iter().map(|r| r.2).fold(0.0, f64::max);
    let left = enabled.iter().map(|r| r.3).fold(0.0, f64::max);
    assert!(
        top_speed > 0.5,
        "forward: top speed {top_speed} m/s\n{seen}"
    );
    assert!(left > 0.1, "left: wheel angle at most {left} rad\n{seen}");
    // Pulled out: the dead-man released within the time-out, brakes on in that tick,
    // and nothing held it again.
    let t_pulled = controller_s(pulled);
    let last_held = enabled.last().unwrap().0;
    // Held until the pad was pulled out (the clocks agree to about a tick: the mode
    // line is printed after its tick), and released within the time-out after.
    let held = format!("held until {last_held} s, pulled at {t_pulled} s\n{seen}");
    assert!(last_held > t_pulled - 0.15, "{held}");
    assert!(last_held - t_pulled < TIMEOUT_S, "{held}");
    let after: Vec<_> = rows.iter().filter(|r| r.0 > last_held).collect();
    assert!(
        after.iter().all(|r| !r.1 && r.4),
        "released with brakes on after {last_held} s"
    );
    let stopped = after
        .iter()
        .find(|r| r.2.abs() < 0.02)
        .expect("the robot stopped");
    assert!(
        stopped.0 - t_pulled < TIMEOUT_S + 1.0,
        "stopped at {} s, pulled at {t_pulled} s",
        stopped.0
    );
    eprintln!(
        "pulled out at {t_pulled:.2} s: 'lost' said {:.0} ms later, last held tick {last_held:.2} s, stopped at {:.2} s",
        lost.duration_since(pulled).as_secs_f64() * 1e3,
        stopped.0
    );
}

//! The operator GUI, clicked through by label with egui_kittest (no window, no GPU),
//! over the real controller: the real threads on the simulated robot, in this process.
//! No timing is asserted: each step waits for its condition with a generous time-out.

use std::time::{Duration, Instant};

use eframe::egui::ViewportId;
use egui_kittest::kittest::Queryable;
use mechweed::config::Settings;
use mechweed::gui::app::Tab;
use mechweed::gui::view::ViewSource;
use mechweed::state::modes::Mode;
use mechweed::state::status::PowerState;
use mechweed_hw::Outputs;
use mechweed_hw::sim::EventAction;

use crate::gui_harness;
use gui_harness::{gui_customised, gui_with};

#[test]
fn halt_then_autonomous_and_the_robot_moves_then_space_halts() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    assert_eq!(gui.harness.state().view.status.mode, Mode::Halt);
    assert!(!gui.enabled("Autonomous"), "not before power-up");
    assert!(gui.shows("motor power is off: press Power up first"));
    gui.power_up();
    assert!(gui.enabled("Autonomous"));
    gui.click("Autonomous");
    gui.wait_until("autonomous", |app| app.view.status.mode == Mode::Autonomous);
    gui.wait_until("the robot moves 0.5 m", |app| {
        app.view.truth.distance_m > 0.5
    });
    gui.harness.key_press(eframe::egui::Key::Space);
    gui.harness.step();
    gui.wait_until("halt by the Space key", |app| {
        app.view.status.mode == Mode::Halt
    });
    let outcome = gui.finish();
    assert!(outcome.faults.is_empty(), "{:?}", outcome.faults);
}

#[test]
fn an_estop_shows_its_cause_and_power_up_waits_for_its_release() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.power_up();
    gui.click("Press e-stop front");
    gui.wait_until("fault", |app| app.view.status.mode == Mode::Fault);
    gui.harness.step();
    assert!(gui.shows("FAULT: front emergency stop pressed (or its wire is broken)"));
    assert!(gui.shows("s ago)"), "the time since the fault");
    assert!(!gui.enabled("Autonomous"));
    assert!(gui.shows("a fault is latched (front emergency stop pressed"));
    assert!(!gui.enabled("Power up"), "not while the e-stop is pressed");
    assert!(gui.shows("cannot power up: front emergency stop pressed"));
    gui.click("Release e-stops");
    gui.wait_until("e-stops released", |app| {
        app.view.status.inputs.estop_front_released && app.view.status.standing_cause.is_none()
    });
    gui.harness.step();
    assert!(gui.enabled("Power up"));
    gui.click("Power up");
    gui.wait_until("halt without fault", |app| {
        app.view.status.mode == Mode::Halt && app.view.status.fault.is_none()
    });
    gui.finish();
}

#[test]
fn a_tuned_gain_is_applied_and_saved_changing_only_its_value() {
    let _one = crate::one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.ini");
    let original = std::fs::read_to_string("config/robot.ini").unwrap();
    std::fs::write(&path, &original).unwrap();
    let mut gui = gui_with(Some(path.clone()));
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    gui.click("Tuning");
    assert_eq!(gui.harness.state().tab, Tab::Tuning);
    assert!(gui.harness.state_mut().tuning.set("pid.left", "kp", 20.5));
    gui.click("Apply");
    // The GUI does not wait for the supervisor: its answer shows a pass or two later.
    gui.wait_until("the supervisor's answer", |app| app.feedback().is_some());
    let feedback = gui.harness.state().feedback().cloned().unwrap();
    assert!(!feedback.refused, "{}", feedback.text);
    gui.click("Save to robot.ini");
    let saved = std::fs::read_to_string(&path).unwrap();
    let left = original.find("[pid.left]").unwrap();
    let kp = left + original[left..].find("kp = 16.7").unwrap();
    let expected = format!(
        "{}kp = 20.5{}",
        &original[..kp],
        &original[kp + "kp = 16.7".len()..]
    );
    assert_eq!(saved, expected);

    // A read-only file is not replaced, and says so.
    let mut perms = std::fs::metadata(&path).unwrap().permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&path, perms).unwrap();
    gui.harness.state_mut().tuning.set("pid.left", "kp", 30.0);
    gui.click("Save to robot.ini");
    let feedback = gui.harness.state().feedback().cloned().unwrap();
    assert!(
        feedback.refused && feedback.text.contains("read-only"),
        "{}",
        feedback.text
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), expected);
    assert_eq!(gui.harness.state().tuning.values[0], 30.0, "nothing lost");

    gui.click("Revert");
    assert_eq!(gui.harness.state().tuning.values[0], 20.5);
    gui.finish();
}

#[test]
fn the_relay_switch_reaches_the_robot_and_leaving_test_restores_safe_outputs() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    gui.click("Test panel");
    gui.click("Enter Test");
    gui.wait_until("test", |app| app.view.status.mode == Mode::Test);
    gui.click("Main power relay");
    gui.wait_until("the contactor closes", |app| {
        app.view.status.outputs.main_power_on && app.view.status.inputs.motor_power_present
    });
    gui.click("Leave Test");
    gui.wait_until("halt with safe outputs", |app| {
        app.view.status.mode == Mode::Halt
            && app.view.status.outputs == Outputs::SAFE
            && !app.view.status.inputs.motor_power_present
    });
    assert_eq!(gui.harness.state().test.outputs, Outputs::SAFE);
    gui.finish();
}

#[test]
fn a_reset_restarts_the_robot_at_the_row_start_on_the_row_chosen() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.power_up();
    gui.click("Autonomous");
    gui.wait_until("the robot moves 0.3 m", |app| {
        app.view.truth.distance_m > 0.3
    });
    assert!(
        !gui.enabled("Reset robot to row start"),
        "not while driving"
    );
    gui.click("HALT");
    gui.wait_until("standing in halt", |app| {
        app.view.status.mode == Mode::Halt && app.view.status.measured.speed_mps.abs() < 0.01
    });
    gui.click("arc");
    gui.click("Reset robot to row start");
    gui.wait_until("a new run at the row start", |app| {
        app.view.status.tick > 0 && app.view.truth.distance_m < 0.01
    });
    assert_eq!(gui.harness.state().sim.row, mechweed_hw::sim::RowShape::Arc);
    assert_eq!(gui.harness.state().view.status.power, PowerState::Off);
    gui.finish();
}

#[test]
fn without_a_display_the_gui_says_to_run_headless_and_fails() {
    let _one = crate::one_at_a_time();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechweed"))
        .args(["run", "--duration", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--headless"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn the_first_tab_is_a_command_line_flag_not_a_hidden_setting() {
    let _one = crate::one_at_a_time();
    let mechweed = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechweed"))
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    // Taken: the run goes on as far as looking for a display.
    let (code, stderr) = mechweed(&["run", "--tab", "plots", "--duration", "1"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("no display for the operator GUI"),
        "{stderr}"
    );
    let (code, stderr) = mechweed(&["run", "--tab", "map"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("[possible values: status, plots, tuning, test]"),
        "{stderr}"
    );
    let (code, stderr) = mechweed(&["run", "--headless", "--tab", "plots"]);
    assert_eq!(code, Some(2), "a tab without a GUI: {stderr}");
    let (code, stderr) = mechweed(&["bench", "loop", "--tab", "plots"]);
    assert_eq!(code, Some(2), "a tab without --gui: {stderr}");
}

#[test]
fn in_test_an_amplifier_follows_the_panel_and_an_estop_still_stops_everything() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    gui.click("Test panel");
    gui.click("Enter Test");
    gui.wait_until("test", |app| app.view.status.mode == Mode::Test);
    gui.click("Main power relay");
    // The first of the three "Fixed" buttons is the left drive's: 1 V by default.
    gui.harness
        .get_all_by_label("Fixed")
        .next()
        .unwrap()
        .click();
    assert!(gui.shows("must be on its stand with the drive wheels off the ground"));
    gui.wait_until("the relay closed", |app| {
        app.view.status.outputs.main_power_on
    });
    // The H key held: the volt reaches the amplifier; let go, it is 0 V again.
    gui.harness.key_down(eframe::egui::Key::H);
    gui.wait_until("1 V on the left amplifier", |app| {
        app.view.status.outputs.amp_left_v == 1.0 && app.view.status.outputs.main_power_on
    });
    gui.harness.key_up(eframe::egui::Key::H);
    gui.wait_until("0 V when the key is let go", |app| {
        app.view.status.outputs.amp_left_v == 0.0
    });
    // Nobody holds anything now: the panel's volt, which reached the amplifier a moment
    // ago, stays on the panel.
    for _ in 0..20 {
        gui.harness.step();
        std::thread::sleep(std::time::Duration::from_millis(10));
        let volts = gui.harness.state().view.status.outputs.amp_left_v;
        assert_eq!(volts, 0.0, "not held");
    }
    // The pointer held down on Hold to run does the same.
    let centre = gui.harness.get_by_label("Hold to run").rect().center();
    let button = |pressed| eframe::egui::Event::PointerButton {
        pos: centre,
        button: eframe::egui::PointerButton::Primary,
        pressed,
        modifiers: eframe::egui::Modifiers::NONE,
    };
    gui.harness.hover_at(centre);
    gui.harness.event(button(true));
    gui.wait_until("1 V while the button is held", |app| {
        app.view.status.outputs.amp_left_v == 1.0
    });
    gui.click("Press e-stop front");
    gui.wait_until("fault with safe outputs", |app| {
        app.view.status.mode == Mode::Fault && app.view.status.outputs == Outputs::SAFE
    });
    gui.finish();
}

#[test]
fn a_start_mode_waits_for_the_operators_confirmation() {
    let _one = crate::one_at_a_time();
    // As `--mode autonomous` on the real robot: nothing powers up until a person says so.
    let mut gui = gui_with(None);
    gui.harness.state_mut().ask_to_start(Mode::Autonomous);
    gui.wait_until("calibrated", |app| app.view.status.measured.calibrated);
    for _ in 0..20 {
        gui.harness.step();
    }
    let st = gui.harness.state().view.status;
    assert_eq!((st.mode, st.power), (Mode::Halt, PowerState::Off));
    assert!(gui.shows("will power up the real robot and drive it"));
    gui.click("Power up and start autonomous");
    gui.wait_until("autonomous", |app| app.view.status.mode == Mode::Autonomous);
    gui.finish();
}

#[test]
fn the_header_says_when_the_robot_runs_without_real_time_priorities() {
    let _one = crate::one_at_a_time();
    use mechweed::config::Backend;
    use mechweed::run::not_realtime;
    let mut rt = Settings::shipped().rt;
    let warning = not_realtime(Backend::Cards, &rt, Some("SCHED_FIFO refused"));
    assert!(warning.as_deref().unwrap().contains("NOT REAL-TIME"));
    assert_eq!(not_realtime(Backend::Sim, &rt, Some("refused")), None);
    assert_eq!(not_realtime(Backend::Cards, &rt, None), None);
    rt.supervisor_priority = 0;
    assert!(not_realtime(Backend::Cards, &rt, None).is_some());
    let mut gui = gui_customised(None, |handles| handles.not_realtime = warning);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    assert!(gui.shows("NOT REAL-TIME: the robot drives without real-time priorities"));
    gui.finish();
}

/// Repaint by need, through the whole GUI: once settled, the GUI thread asks for no
/// frame of its own; a change made elsewhere (an e-stop pressed on the simulated robot,
/// not in the window) makes the pacer's next look ask for a frame, and that frame shows
/// it. (How soon in time is measured by `bench loop --gui`, not asserted here.)
#[test]
fn a_settled_gui_asks_for_no_frame_and_a_change_elsewhere_is_drawn_at_the_next_look() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    let shared = gui.harness.state().shared.clone();
    gui.look();
    for _ in 0..5 {
        gui.harness.step();
    }
    let root = &gui.harness.output().viewport_output[&ViewportId::ROOT];
    assert_eq!(
        root.repaint_delay,
        Duration::MAX,
        "the settled GUI asked for a frame"
    );
    assert!(!gui.shows("PRESSED"));

    let sim = shared.lock().source.sim().expect("the simulated robot");
    assert!(sim.apply(EventAction::EstopFront));
    let end = Instant::now() + Duration::from_secs(30);
    while shared
        .lock()
        .source
        .view()
        .status
        .inputs
        .estop_front_released
    {
        assert!(Instant::now() < end, "the e-stop never reached the status");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(!gui.harness.ctx.has_requested_repaint());
    assert!(!gui.shows("PRESSED"), "not on screen before a frame");
    gui.look();
    assert!(
        gui.harness.ctx.has_requested_repaint(),
        "the next look asks for a frame"
    );
    gui.harness.step();
    assert!(gui.shows("PRESSED"), "the frame asked for shows the e-stop");
    gui.finish();
}

/// With `[rt] gui_cpu` the GUI thread is pinned; a reset of the simulated robot starts
/// the new controller from the GUI thread, and its threads must not inherit that CPU.
#[test]
fn a_reset_from_a_pinned_gui_starts_the_controllers_threads_on_every_cpu() {
    let _one = crate::one_at_a_time();
    let every_cpu = allowed_cpus("self").expect("this process's CPUs");
    if !every_cpu.contains(['-', ',']) {
        eprintln!("skipped: this machine has one CPU ({every_cpu}), nothing to pin away from");
        return;
    }
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    // This test's thread plays the GUI thread, pinned as run_gui pins it.
    assert_eq!(mechweed::rt::set_this_thread(0, 0), None);
    gui.click("Reset robot to row start");
    gui.wait_until("a new run", |app| {
        app.view.status.tick > 0 && app.feedback().is_some_and(|f| f.text.contains("reset"))
    });
    mechweed::rt::unpin_this_thread();
    let task_dir = std::fs::read_dir("/proc/self/task").expect("the process's threads");
    let mut checked = 0;
    for task in task_dir.flatten() {
        let tid = task.file_name().to_string_lossy().to_string();
        let name = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        if ["supervisor", "steer", "camlink"].contains(&name.trim()) {
            let cpus = allowed_cpus(&format!("self/task/{tid}")).unwrap();
            assert_eq!(cpus, every_cpu, "the {} thread is pinned", name.trim());
            checked += 1;
        }
    }
    assert!(checked >= 3, "found {checked} controller threads");
    gui.finish();
}

/// The CPUs a process or thread may run on, as /proc says them ("0-1").
fn allowed_cpus(proc_path: &str) -> Option<String> {
    let status = std::fs::read_to_string(format!("/proc/{proc_path}/status")).ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("Cpus_allowed_list:"))
        .map(|v| v.trim().to_string())
}

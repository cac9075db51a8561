//! The operator window in a field, through egui_kittest: a light theme for daylight
//! and a key to switch, no text under 12 px, abnormal inputs in the fault colour, the
//! whole window usable at 1280x720, a layout that does not jump at the first answer,
//! and Space = HALT from the first frame.

use std::time::Duration;

use eframe::egui::{self, Color32};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use mechweed::config::{Settings, Theme};
use mechweed::gui::GuiApp;
use mechweed::gui::pacer::Source;
use mechweed::state::modes::{Mode, Request};

use crate::watch_harness;
use watch_harness::{fed, sent, shows, watching, window};

#[allow(dead_code)]
use crate::gui_harness;

use crate::common;
use common::{mechweed as mechweed_command, test_run_settings, text};

/// Every piece of text drawn in the last frame, with its colour.
fn texts(harness: &Harness<'static, GuiApp>) -> Vec<(String, Color32)> {
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        if let egui::Shape::Text(text) = &clipped.shape {
            for section in &text.galley.job.sections {
                let range = section.byte_range.start.0..section.byte_range.end.0;
                let words = &text.galley.job.text[range];
                let colour = text.override_text_color.unwrap_or(section.format.color);
                out.push((words.to_string(), colour));
            }
        }
    }
    out
}

#[test]
fn the_shipped_theme_is_light_and_f2_switches_it() {
    let _one = crate::one_at_a_time();
    let mut harness = watching(Duration::from_millis(100), |_, _| {});
    assert_eq!(harness.state().theme, Theme::Light);
    assert!(!harness.ctx.global_style().visuals.dark_mode);
    harness.key_press(egui::Key::F2);
    harness.run_steps(2);
    assert_eq!(harness.state().theme, Theme::Dark);
    assert!(harness.ctx.global_style().visuals.dark_mode);
    // [gui] theme chooses the start.
    let mut settings = Settings::shipped();
    settings.gui.theme = Theme::Dark;
    let harness = window(fed(Duration::ZERO, |_, _| {}), settings, [1280.0, 720.0]);
    assert!(harness.ctx.global_style().visuals.dark_mode);
}

#[test]
fn no_text_is_smaller_than_12_px() {
    let _one = crate::one_at_a_time();
    // The reasons under the mode buttons were about 9 px, grey on dark.
    let harness = watching(Duration::from_millis(100), |_, _| {});
    for (style, font) in &harness.ctx.global_style().text_styles {
        assert!(font.size >= 12.0, "{style:?}: {} px", font.size);
    }
    // And every piece of text the window drew, whatever size it was asked for.
    let mut drawn = 0;
    for clipped in &harness.output().shapes {
        if let egui::Shape::Text(text) = &clipped.shape {
            for section in &text.galley.job.sections {
                drawn += 1;
                let px = section.format.font_id.size;
                assert!(px >= 12.0, "{px} px: {:?}", text.galley.job.text);
            }
        }
    }
    assert!(drawn > 50, "only {drawn} texts drawn");
    // The weak text (the reasons, the hints) is dark on the light ground.
    let weak = harness.ctx.global_style().visuals.weak_text_color();
    assert!(
        weak.r() < 100 && weak.g() < 100 && weak.b() < 100,
        "{weak:?}"
    );
}

#[test]
fn a_pressed_estop_is_drawn_in_the_fault_colour() {
    let _one = crate::one_at_a_time();
    let harness = watching(Duration::from_millis(100), |flow, payload| {
        if flow == mechweed::gui::remote::Flow::Tick {
            payload["estop_front_released"] = 0.into();
        }
    });
    let drawn = texts(&harness);
    let colour_of = |word: &str| {
        drawn
            .iter()
            .find(|(text, _)| text.trim() == word)
            .unwrap_or_else(|| panic!("'{word}' not drawn"))
            .1
    };
    let pressed = colour_of("PRESSED");
    let released = colour_of("released");
    assert_ne!(pressed, released, "PRESSED looks like released");
    assert!(
        pressed.r() > 150 && pressed.g() < 60 && pressed.b() < 60,
        "not the fault colour: {pressed:?}"
    );
}

#[test]
fn the_layout_does_not_move_when_the_robots_first_status_comes() {
    let _one = crate::one_at_a_time();
    // Nothing received: no fault line, then "no fault" pushed the tabs down.
    let remote = mechweed::gui::remote::RemoteView::offline("mechweed", "tcp/10.0.0.7:7510");
    let mut harness = window(remote, Settings::shipped(), [1280.0, 720.0]);
    let before = harness.get_by_label("Status").rect();
    if let Source::Remote(remote) = &harness.state().shared.lock().source {
        remote.set_operator(false);
        for (flow, payload) in watch_harness::recorded() {
            remote.feed(
                flow,
                payload.to_string().as_bytes(),
                std::time::Instant::now(),
            );
        }
    }
    harness.run_steps(2);
    assert!(shows(&harness, "AUTONOMOUS"), "the status did not arrive");
    assert_eq!(
        harness.get_by_label("Status").rect(),
        before,
        "the tabs moved"
    );
}

#[test]
fn the_layout_does_not_move_when_the_first_answer_comes() {
    let _one = crate::one_at_a_time();
    let mut harness = watching(Duration::from_millis(100), |_, _| {});
    let before = harness.get_by_label("Status").rect();
    harness.key_press(egui::Key::Space);
    harness.run_steps(2);
    assert_eq!(sent(&harness), [r#"{"request":"halt"}"#]);
    if let Source::Remote(remote) = &harness.state().shared.lock().source {
        remote.answer_by_hand(Request::Mode(Mode::Halt), Ok(()));
    }
    harness.run_steps(2);
    assert!(shows(&harness, "halted"), "no answer line");
    let after = harness.get_by_label("Status").rect();
    assert_eq!(before, after, "the tabs moved");
}

#[test]
fn the_window_asks_for_the_keyboard_at_start_and_says_when_it_is_not_its() {
    let _one = crate::one_at_a_time();
    let remote = fed(Duration::ZERO, |_, _| {});
    let mut harness = window(remote, Settings::shipped(), [1280.0, 720.0]);
    assert!(shows(
        &harness,
        "Space = HALT: this window has the keyboard"
    ));
    // Another window has the keyboard: the header says Space is not ours, in the same
    // line's place (the tabs do not move).
    let tabs_at = harness.get_by_label("Status").rect();
    harness.input_mut().focused = false;
    harness.run_steps(2);
    assert!(shows(&harness, "the keyboard is another window's"));
    assert_eq!(
        harness.get_by_label("Status").rect(),
        tabs_at,
        "the tabs moved"
    );
    harness.input_mut().focused = true;
    harness.run_steps(2);
    assert!(!shows(&harness, "the keyboard is another window's"));
}

#[test]
fn at_1280_by_720_every_panel_reaches_its_last_line() {
    let _one = crate::one_at_a_time();
    // The simulated robot's window: modes on the left, the simulated robot on the right,
    // the Status tab in the middle, each scrolling where it must.
    let mut gui = gui_harness::gui_with(None);
    gui.harness.set_size(egui::vec2(1280.0, 720.0));
    gui.harness.run_steps(3);
    let screen = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 720.0));
    for last in [
        "HALT (top, or Space) stops in every mode",
        "truth: x ",
        "Bus",
    ] {
        let node = gui.harness.get_by_label_contains(last);
        node.scroll_to_me();
        gui.harness.run_steps(3);
        let rect = gui.harness.get_by_label_contains(last).rect();
        assert!(
            screen.contains_rect(rect),
            "'{last}' at {rect:?}, outside the 1280x720 window"
        );
    }
}

/// A bare X server (Xvfb, no window manager) on a display of its own, or None where
/// the machine has no Xvfb. Killed when dropped.
struct BareX {
    server: std::process::Child,
    display: String,
}

impl Drop for BareX {
    fn drop(&mut self) {
        let _ = self.server.kill();
        let _ = self.server.wait();
    }
}

fn bare_x() -> Option<BareX> {
    let number = (100..200)
        .map(|n| n + std::process::id() % 100)
        .find(|n| !std::path::Path::new(&format!("/tmp/.X{n}-lock")).exists())?;
    let display = format!(":{number}");
    // Larger than the window, so that the pointer can rest outside it.
    let server = std::process::Command::new("Xvfb")
        .args([
            display.as_str(),
            "-screen",
            "0",
            "1920x1080x24",
            "-nolisten",
            "tcp",
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .ok()?;
    let socket = format!("/tmp/.X11-unix/X{number}");
    let end = std::time::Instant::now() + Duration::from_secs(10);
    while !std::path::Path::new(&socket).exists() {
        if std::time::Instant::now() > end {
            return None;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    Some(BareX { server, display })
}

/// Press and release Space through the X server's test extension, as a keyboard does;
/// the pointer put first where no window of ours is.
fn press_space_away_from_the_window(display: &str) {
    use x11rb::connection::Connection;
    use x11rb::protocol::xproto::{ConnectionExt as _, KEY_PRESS_EVENT, KEY_RELEASE_EVENT};
    use x11rb::protocol::xtest::ConnectionExt as _;
    let (conn, screen) = x11rb::connect(Some(display)).unwrap();
    let root = conn.setup().roots[screen].root;
    conn.warp_pointer(x11rb::NONE, root, 0, 0, 0, 0, 1900, 1060)
        .unwrap();
    let (first, last) = (conn.setup().min_keycode, conn.setup().max_keycode);
    let map = conn
        .get_keyboard_mapping(first, last - first + 1)
        .unwrap()
        .reply()
        .unwrap();
    let per = usize::from(map.keysyms_per_keycode).max(1);
    let space = (map.keysyms.chunks(per))
        .position(|syms| syms.contains(&0x20))
        .map(|k| first + k as u8)
        .unwrap();
    for kind in [KEY_PRESS_EVENT, KEY_RELEASE_EVENT] {
        conn.xtest_fake_input(kind, space, x11rb::CURRENT_TIME, root, 0, 0, 0)
            .unwrap();
    }
    conn.flush().unwrap();
}

#[test]
fn space_halts_a_window_nobody_clicked_on_a_bare_x_server() {
    let _one = crate::one_at_a_time();
    // The robot computer's case: no window manager gives the new window the keyboard,
    // and Space did nothing until someone clicked the window.
    let Some(x) = bare_x() else {
        eprintln!("skipped: no Xvfb on this machine (apt-get install xvfb) to run the window on");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // The operator script powers up and drives at once; Space comes well after.
    let run = mechweed_command()
        .args(["run", "--mode", "autonomous", "--duration", "16"])
        .args(test_run_settings(dir.path()))
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(10));
    // Three presses 0.3 s apart, as a person presses again when the robot goes on: a
    // single one did not always reach the new window here, with the keyboard its own.
    for _ in 0..3 {
        press_space_away_from_the_window(&x.display);
        std::thread::sleep(Duration::from_millis(300));
    }
    let out = run.wait_with_output().unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}{stderr}");
    let distance_m: f64 = (stdout.lines())
        .find_map(|l| l.split("final mode: halt, distance ").nth(1))
        .and_then(|rest| rest.split(' ').next())
        .and_then(|m| m.parse().ok())
        .unwrap_or_else(|| panic!("not halted at the end: {stdout}{stderr}"));
    assert!(distance_m > 1.0, "it never drove: {stdout}");
}

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
use mechweed::modes::{Mode, Request};

mod watch_harness;
use watch_harness::{fed, sent, shows, watching, window};

#[allow(dead_code)]
mod gui_harness;

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
fn no_text_style_is_smaller_than_12_px() {
    // The reasons under the mode buttons were about 9 px, grey on dark.
    let harness = watching(Duration::from_millis(100), |_, _| {});
    for (style, font) in &harness.ctx.global_style().text_styles {
        assert!(font.size >= 12.0, "{style:?}: {} px", font.size);
    }
    // The weak text (the reasons, the hints) is dark on the light ground.
    let weak = harness.ctx.global_style().visuals.weak_text_color();
    assert!(
        weak.r() < 100 && weak.g() < 100 && weak.b() < 100,
        "{weak:?}"
    );
}

#[test]
fn a_pressed_estop_is_drawn_in_the_fault_colour() {
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
fn the_layout_does_not_move_when_the_first_answer_comes() {
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
    let remote = fed(Duration::ZERO, |_, _| {});
    let mut harness = window(remote, Settings::shipped(), [1280.0, 720.0]);
    // Asked at the first frame, before anyone clicked.
    assert!(harness.state().focus_asked(), "no focus asked for");
    // Another window has the keyboard: the header says Space is not ours.
    harness.input_mut().focused = false;
    harness.run_steps(2);
    assert!(shows(&harness, "the keyboard is another window's"));
    harness.input_mut().focused = true;
    harness.run_steps(2);
    assert!(!shows(&harness, "the keyboard is another window's"));
}

#[test]
fn at_1280_by_720_every_panel_reaches_its_last_line() {
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

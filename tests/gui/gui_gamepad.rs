//! The gamepad in the operator GUI, through egui_kittest: over the real controller with
//! `[joystick] source = gamepad` and no pad there, and the Status tab's words for a pad
//! from a `View` made by hand.

use std::time::Instant;

use eframe::egui;
use eframe::egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use evdev::{AbsoluteAxisCode, EventType, KeyCode};
use mechweed::config::{GamepadDevice, JoystickSource, Settings};
use mechweed::gamepad::mapping::{AxisRange, Opened};
use mechweed::gamepad::{Label, PadMap, PadState};
use mechweed::gui::status;
use mechweed::gui::view::{GamepadView, View};
use mechweed::state::modes::Mode;

#[allow(dead_code)]
use crate::gui_harness;
use gui_harness::gui_from;

#[test]
fn with_no_gamepad_the_status_tab_says_why_and_joystick_mode_stands() {
    let _one = crate::one_at_a_time();
    let mut settings = Settings::shipped();
    settings.joystick.source = JoystickSource::Gamepad;
    settings.gamepad.device = GamepadDevice::Path("/nonexistent/event0".into());
    let mut gui = gui_from(settings, None, |_| {});
    gui.wait_until("the gamepad looked for", |app| {
        app.view
            .gamepad
            .is_some_and(|pad| pad.state.problem.as_str().contains("/nonexistent"))
    });
    assert!(gui.shows("not connected: /nonexistent/event0: No such file"));
    // The simulated robot's on-screen joystick is not what drives.
    assert!(gui.shows("the gamepad drives"));
    gui.power_up();
    // "Joystick" is also the inputs' row: the mode's button.
    gui.harness
        .get_by_role_and_label(Role::Button, "Joystick")
        .click();
    gui.harness.step();
    gui.look();
    gui.wait_until("joystick mode", |app| {
        app.view.status.mode == Mode::Joystick
    });
    let joystick = gui.harness.state().view.status.inputs;
    assert!(
        !joystick.joystick_enable && joystick.joystick_speed_v == 0.0,
        "{joystick:?}"
    );
    gui.finish();
}

fn pad_view(held_at_connect: bool) -> View {
    let s = Settings::shipped();
    let mut state = PadState::new(PadMap::new(&s.gamepad, &s.joystick));
    let range = AxisRange {
        min: -32768,
        max: 32767,
    };
    let now = Instant::now();
    let opened = Opened {
        speed: (range, 0),
        steer: (range, 0),
        deadman_held: held_at_connect,
    };
    state.pad.connect(opened, now);
    // Full forward and half right.
    state
        .pad
        .event(EventType::ABSOLUTE, AbsoluteAxisCode::ABS_Y.0, -32768, now);
    state
        .pad
        .event(EventType::ABSOLUTE, AbsoluteAxisCode::ABS_X.0, 16384, now);
    if !held_at_connect {
        state
            .pad
            .event(EventType::KEY, KeyCode::BTN_TL.code(), 1, now);
    }
    state.name = Label::new("Logitech Gamepad F310");
    state.place = Label::new("/dev/input/event5");
    View {
        gamepad: Some(GamepadView {
            state,
            joystick: state.pad.joystick(now),
        }),
        ..View::default()
    }
}

fn inputs(view: View) -> Harness<'static, View> {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1000.0, 600.0))
        .build_ui_state(|ui, view: &mut View| status::inputs_grid(ui, view), view);
    harness.run();
    harness
}

#[test]
fn the_status_tab_names_the_pad_its_sticks_and_its_dead_man() {
    let _one = crate::one_at_a_time();
    let harness = inputs(pad_view(false));
    let shown =
        "Logitech Gamepad F310 (/dev/input/event5)  steer +50 %  speed +100 %  dead-man held";
    harness.get_by_label(shown);
    let harness = inputs(pad_view(true));
    harness.get_by_label_contains("dead-man held, but must be released and pressed again");
    // Without a gamepad as the joystick there is no such line.
    let harness = inputs(View::default());
    assert!(harness.query_by_label_contains("Gamepad").is_none());
}

//! The test panel's commissioning steps over the real controller on the simulated
//! robot: a step runs only while Hold to run is held, and the panel shows what the
//! encoder saw and what it means.

use mechweed::state::modes::Mode;
use mechweed::state::status::{Notice, PowerState};

use crate::gui_harness::gui_with;

#[test]
fn the_left_drive_s_step_runs_while_held_and_the_panel_says_it_turned_the_right_way() {
    let _one = crate::one_at_a_time();
    let mut gui = gui_with(None);
    gui.wait_until("the first status", |app| app.view.status.tick > 0);
    gui.click("Test panel");
    gui.click("Enter Test");
    gui.wait_until("test", |app| app.view.status.mode == Mode::Test);
    // Not held: the step is let go of at once, and says so.
    gui.click("Main power relay");
    gui.wait_until("power on", |app| app.view.status.power == PowerState::On);
    gui.click("Step left drive");
    gui.wait_until("the step let go of", |app| {
        matches!(app.view.status.notice, Some(Notice::StepDone { .. }))
    });
    assert!(gui.shows("Hold to run let go before the step ended"));
    // Held with the H key: it runs to its end.
    gui.harness.key_down(eframe::egui::Key::H);
    for _ in 0..5 {
        gui.look();
        gui.harness.step();
    }
    gui.click("Step left drive");
    gui.wait_until("the step's volts on the left amplifier", |app| {
        app.view.status.outputs.amp_left_v == 2.0
    });
    gui.wait_until("the step's result", |app| {
        app.view
            .status
            .notice
            .is_some_and(|n| n.to_string().contains("the right way"))
    });
    gui.harness.key_up(eframe::egui::Key::H);
    gui.harness.step();
    assert!(gui.shows("left drive step (+2.0 V for 0.2 s): the encoder counted +0.0"));
    gui.finish();
}

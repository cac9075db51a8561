//! The GUI's panels drawn from a `View` made by hand, with no controller running (as
//! egui's demo panels are tested), through egui_kittest (no window, no GPU). A test
//! supervisor stands behind the real request channel: it sees every request a panel
//! sends and answers as the test says, so each test checks what a panel shows, what it
//! sends, and how the answer comes back, one frame later. No clock is read.

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use mechweed::config::Settings;
use mechweed::gui::requests::Requests;
use mechweed::gui::test_panel::TestPanel;
use mechweed::gui::tuning::Tuning;
use mechweed::gui::view::{View, ViewSource};
use mechweed::gui::{header, modes, status};
use mechweed::state::fault_cause::FaultCause;
use mechweed::state::modes::{Mode, Refusal, Request};
use mechweed::state::request_channel::QUEUE_PLACES;
use mechweed::state::status::{FaultRecord, PowerState};
use mechweed_hw::Outputs;

use crate::test_supervisor;
use test_supervisor::{TestSupervisor, robot};

/// The panels a test draws, with what the app would give them.
struct Panels {
    supervisor: TestSupervisor,
    view: View,
    requests: Requests,
    tuning: Tuning,
    test: TestPanel,
    draw: fn(&mut Panels, &mut egui::Ui),
}

/// The header (where the feedback line is) and the panel `draw` draws, in one frame
/// as the app's pass and frame run: answers, view, panels, then the requests sent.
fn panels(view: View, draw: fn(&mut Panels, &mut egui::Ui)) -> Harness<'static, Panels> {
    let state = Panels {
        supervisor: TestSupervisor::new(view),
        view: View::default(),
        requests: Requests::default(),
        tuning: Tuning::new(&Settings::shipped(), None),
        test: TestPanel::default(),
        draw,
    };
    Harness::builder()
        .with_size(egui::vec2(1000.0, 900.0))
        .build_ui_state(
            |ui, p: &mut Panels| {
                p.requests.take_answers();
                p.view = p.supervisor.view();
                header::show(ui, &p.view, &mut p.requests);
                (p.draw)(p, ui);
                p.requests.post(&p.supervisor, p.view.now_s);
            },
            state,
        )
}

fn draw_modes(p: &mut Panels, ui: &mut egui::Ui) {
    modes::show(ui, &p.view, &mut p.requests);
}

fn draw_status(p: &mut Panels, ui: &mut egui::Ui) {
    status::show(ui, &p.view, &mut p.requests);
}

fn draw_tuning(p: &mut Panels, ui: &mut egui::Ui) {
    p.tuning.show(ui, &p.view, &mut p.requests);
}

fn draw_test(p: &mut Panels, ui: &mut egui::Ui) {
    p.test.keep_sending(&p.view, &mut p.requests);
    p.test.show(ui, &p.view, &mut p.requests);
}

fn shows(h: &Harness<Panels>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}

fn enabled(h: &Harness<Panels>, label: &str) -> bool {
    !h.get_by_label(label).accesskit_node().is_disabled()
}

fn click(h: &mut Harness<Panels>, label: &str) {
    h.get_by_label(label).click();
    h.step();
}

#[test]
fn a_latched_fault_shows_its_cause_and_why_nothing_can_start() {
    let _one = crate::one_at_a_time();
    let mut view = robot(Mode::Fault, PowerState::Off);
    view.status.fault = Some(FaultRecord {
        cause: FaultCause::EstopFront,
        t_s: 10.0,
        tick_seen: 1000,
        tick_safe: 1000,
        came_back_after_s: None,
    });
    view.status.standing_cause = Some(FaultCause::EstopFront);
    view.status.inputs.estop_front_released = false;
    let mut h = panels(view, draw_modes);
    h.step();
    assert!(shows(
        &h,
        "FAULT: front emergency stop pressed (or its wire is broken)  (2.0 s ago)"
    ));
    assert!(!enabled(&h, "Power up"));
    assert!(shows(&h, "cannot power up: front emergency stop pressed"));
    assert!(!enabled(&h, "Autonomous"));
    assert!(shows(
        &h,
        "a fault is latched (front emergency stop pressed"
    ));
    // HALT in Fault: the outputs are already safe, so nothing is asked.
    click(&mut h, "HALT");
    assert_eq!(h.state().supervisor.waiting(), 0);
    h.step();
    assert!(shows(
        &h,
        "halt: the robot is in fault, its outputs are already safe"
    ));
}

#[test]
fn halt_is_sent_without_waiting_and_its_answer_shows_the_next_frame() {
    let _one = crate::one_at_a_time();
    let mut h = panels(robot(Mode::Autonomous, PowerState::On), draw_modes);
    h.step();
    click(&mut h, "HALT");
    // Sent in the frame of the click; no answer yet, so nothing is said.
    assert!(h.state().requests.feedback().is_none());
    let sent = h.state().supervisor.answer(|_| Ok(()));
    assert_eq!(sent, [Request::Mode(Mode::Halt)]);
    h.step();
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert_eq!(
        (feedback.text.as_str(), feedback.refused),
        ("halted", false)
    );
    assert_eq!(feedback.at_s, 12.0, "when the operator asked");
    assert!(shows(&h, "12.0 s  halted"));
}

#[test]
fn a_refusal_is_shown_in_the_supervisors_words() {
    let _one = crate::one_at_a_time();
    let mut h = panels(robot(Mode::Halt, PowerState::Off), draw_modes);
    h.step();
    assert!(enabled(&h, "Power up"));
    click(&mut h, "Power up");
    let sent = h
        .state()
        .supervisor
        .answer(|_| Err(Refusal::CauseStillActive(FaultCause::EstopBack)));
    assert_eq!(sent, [Request::PowerUp]);
    h.step();
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert!(feedback.refused);
    assert_eq!(
        feedback.text,
        "refused: cannot power up: back emergency stop pressed (or its wire is broken)"
    );
    assert!(shows(&h, "refused: cannot power up: back emergency stop"));
}

#[test]
fn a_request_that_cannot_be_queued_is_said_at_once() {
    let _one = crate::one_at_a_time();
    let mut h = panels(robot(Mode::Autonomous, PowerState::On), draw_modes);
    h.step();
    // Someone else has filled the supervisor's queue.
    let (other, _answers) = crossbeam_channel::bounded(QUEUE_PLACES);
    for _ in 0..QUEUE_PLACES {
        h.state()
            .supervisor
            .handle
            .send(Request::PowerUp, &other)
            .unwrap();
    }
    click(&mut h, "HALT");
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert!(feedback.refused);
    assert_eq!(
        feedback.text,
        "refused: the supervisor has too many requests waiting"
    );

    // A supervisor that has stopped takes nothing.
    h.state_mut().supervisor.inbox = None;
    click(&mut h, "HALT");
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert_eq!(
        feedback.text,
        "refused: the supervisor is not taking requests"
    );
    h.step();
    assert!(shows(&h, "refused: the supervisor is not taking requests"));
}

#[test]
fn the_test_panel_sends_what_it_shows_and_says_a_refusal() {
    let _one = crate::one_at_a_time();
    let mut view = robot(Mode::Test, PowerState::Off);
    view.status.inputs.battery_v = 24.3;
    let mut h = panels(view, draw_test);
    h.step();
    assert!(shows(&h, "24.30 V"), "the inputs under the switches");
    // Entering Test, the panel asks for the outputs it shows: safe ones.
    assert_eq!(
        h.state().supervisor.answer(|_| Ok(())),
        [Request::TestOutputs(Outputs::SAFE)]
    );
    click(&mut h, "Main power relay");
    h.step();
    let powered = Outputs {
        main_power_on: true,
        ..Outputs::SAFE
    };
    assert_eq!(
        h.state().supervisor.answer(|_| Ok(())),
        [Request::TestOutputs(powered)]
    );
    // The first "Fixed" is the left drive's: 1 V by default.
    h.get_all_by_label("Fixed").next().unwrap().click();
    h.step();
    h.step();
    let sent = h.state().supervisor.answer(|_| Err(Refusal::NotInTest));
    let left = Outputs {
        amp_left_v: 1.0,
        ..powered
    };
    assert_eq!(sent, [Request::TestOutputs(left)]);
    h.step();
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert_eq!(
        feedback.text,
        "test outputs refused: test outputs are only taken in test mode"
    );

    // Out of Test the panel forgets its switches and sends nothing.
    h.state_mut().supervisor.view.status.mode = Mode::Halt;
    h.step();
    h.step();
    assert_eq!(h.state().supervisor.waiting(), 0);
    assert_eq!(h.state().test.outputs, Outputs::SAFE);
    assert!(!enabled(&h, "Main power relay"));
}

#[test]
fn the_tuning_panel_applies_only_in_halt_and_only_values_in_range() {
    let _one = crate::one_at_a_time();
    let mut h = panels(robot(Mode::Autonomous, PowerState::On), draw_tuning);
    h.step();
    assert!(!enabled(&h, "Apply"));
    assert!(shows(
        &h,
        "gains and steering-law parameters are changed only in halt"
    ));

    h.state_mut().supervisor.view.status.mode = Mode::Halt;
    h.step();
    assert!(h.state_mut().tuning.set("pid.left", "kp", -1.0));
    click(&mut h, "Apply");
    assert_eq!(
        h.state().supervisor.waiting(),
        0,
        "nothing out of range is sent"
    );
    let feedback = h.state().requests.feedback().cloned().unwrap();
    assert!(
        feedback.refused && feedback.text.starts_with("not applied: "),
        "{}",
        feedback.text
    );

    h.state_mut().tuning.set("pid.left", "kp", 20.5);
    click(&mut h, "Apply");
    let sent = h.state().supervisor.answer(|_| Ok(()));
    match sent.as_slice() {
        [Request::Tuning(gains, _)] => assert_eq!(gains.left.kp, 20.5),
        other => panic!("sent {other:?}"),
    }
    h.step();
    assert!(shows(&h, "gains and steering law applied"));
}

#[test]
fn the_status_panel_shows_every_input_and_test_link_pings_the_camera() {
    let _one = crate::one_at_a_time();
    let mut view = robot(Mode::Halt, PowerState::Off);
    view.status.inputs.estop_back_released = false;
    view.status.inputs.battery_v = 23.75;
    view.status.inputs.enc_left_counts = 4321;
    let mut h = panels(view, draw_status);
    h.step();
    assert!(shows(&h, "PRESSED"), "the back e-stop");
    assert!(shows(&h, "23.75 V"));
    assert!(shows(&h, "4321 counts"));
    click(&mut h, "Test link");
    assert_eq!(h.state().supervisor.pings.get(), 1);
    assert_eq!(h.state().supervisor.waiting(), 0, "a ping is not a request");
}

#[test]
fn the_status_panel_shows_the_bus_its_endpoints_and_what_it_published_and_dropped() {
    let _one = crate::one_at_a_time();
    let mut view = robot(Mode::Halt, PowerState::Off);
    assert!({
        let mut h = panels(view.clone(), draw_status);
        h.step();
        shows(&h, "bus: off")
    });
    view.bus = mechweed::bus::BusFigures {
        state: mechweed::bus::BusState::Running,
        peers: 2,
        status_published: 321,
        ticks_dropped: 7,
        ..Default::default()
    };
    view.bus_endpoints = "listening on tcp/127.0.0.1:7510, connecting to nothing".into();
    let mut h = panels(view, draw_status);
    h.step();
    assert!(shows(&h, "321 status"));
    assert!(shows(&h, "7 ticks, 0 events dropped"));
    assert!(shows(&h, "2 other programs present"));
    assert!(shows(&h, "listening on tcp/127.0.0.1:7510"));
}

#[test]
fn the_status_tab_shows_the_fix_which_sensors_steer_and_the_filters_row() {
    let _one = crate::one_at_a_time();
    use mechweed::steer::{FilterFigures, RowFigures, Steering};
    let mut view = robot(Mode::Autonomous, PowerState::On);
    view.steer.sources.steering = Steering::FilterGnss;
    view.steer.row = RowFigures {
        gnss_quality: 5,
        gnss_satellites: 16,
        gnss_sd_m: Some(0.1),
        gnss_heard_s: Some(0.0),
        gnss_position: Some((52.0, 5.66)),
        filter: Some(FilterFigures {
            offset_m: 0.012,
            offset_sd_m: 0.004,
            heading_rad: 0.01,
            heading_sd_rad: 0.002,
            curvature_per_m: 0.0,
            map_bias_m: -0.008,
            camera_rejected: 21,
            gnss_rejected: 3,
        }),
    };
    let mut h = panels(view, draw_status);
    h.step();
    assert!(shows(&h, "GNSS alone"));
    assert!(shows(&h, "RTK float  16 satellites  s.d. 10.0 cm"));
    assert!(shows(&h, "row +1.2 cm +- 0.4 cm at the rear axle"));
    assert!(shows(&h, "map bias -0.8 cm"));
    assert!(shows(&h, "camera 21  GNSS 3"));

    // The camera steering alone: no filter, and no fix.
    let mut h = panels(robot(Mode::Autonomous, PowerState::On), draw_status);
    h.step();
    assert!(shows(&h, "not running ([steer] source = camera)"));
    assert!(shows(&h, "no fix received"));
}

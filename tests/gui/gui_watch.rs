//! `mechweed watch`: the operator GUI fed by the robot's flows, through egui_kittest
//! (no window). The flows are recorded from a real run (`tests/watch_flows.jsonl`, lines
//! of `mechweed bus echo`: a status and a tick, twice, of the simulated robot in
//! autonomous) and handed to the view as zenoh's callback would; one test reads the real
//! flows of a robot program on loopback.

use crate::common;

use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

use egui_kittest::kittest::{NodeT, Queryable};
use mechweed::config::Settings;
use mechweed::gui::pacer::Source;
use mechweed::gui::remote::{Flow, RemoteView};
use mechweed::gui::view::ViewSource;
use mechweed::state::modes::{Gains, Mode, Request};
use serde_json::Value;

use crate::watch_harness;
use watch_harness::{enabled, recorded, sent, shows, watching};

#[test]
fn the_same_panels_show_the_recorded_flows_and_the_header_names_the_robot() {
    let _one = crate::one_at_a_time();
    let harness = watching(Duration::from_millis(100), |_, _| {});
    assert!(shows(
        &harness,
        "watching mechweed at tcp/10.0.0.7:7510: status"
    ));
    assert!(shows(&harness, "requests: HALT only"));
    assert!(shows(&harness, "AUTONOMOUS"));
    let view = &harness.state().view;
    assert!(!view.remote.as_ref().unwrap().stale());
    // The newest tick's encoder and wheel speed, in the Status tab's words.
    let tick: Value = recorded()[3].1.clone();
    let counts = format!(
        "{:>10} counts  {:+.3} m/s",
        tick["enc_left_counts"].as_i64().unwrap(),
        tick["v_left_mps"].as_f64().unwrap()
    );
    assert!(shows(&harness, &counts), "{counts} not shown");
    assert!(shows(
        &harness,
        &format!("{:+.2} V", tick["amp_left_v"].as_f64().unwrap())
    ));
    // The newest status's tick number (the status flow carries the supervisor's).
    assert_eq!(Some(view.status.tick), recorded()[2].1["tick"].as_u64());
    assert!(view.simulated, "the simulated truth comes with the ticks");
}

#[test]
fn the_watched_robots_gnss_and_row_filter_are_shown_from_its_ticks() {
    let _one = crate::one_at_a_time();
    // A robot steering by the fused row: its fix, which sensors steer and the filter's
    // row come in the tick flow, as its own Status tab shows them.
    let harness = watching(Duration::from_millis(100), |flow, payload| {
        if flow == Flow::Tick {
            payload["steering"] = "gnss_alone".into();
            (payload["gnss_quality"], payload["gnss_satellites"]) = (4.into(), 17.into());
            payload["gnss_sd_m"] = 0.012.into();
            payload["filter_offset_m"] = 0.034.into();
            payload["filter_offset_sd_m"] = 0.008.into();
            payload["filter_gnss_rejected"] = 3.into();
        }
    });
    assert!(shows(&harness, "GNSS alone"));
    assert!(shows(&harness, "RTK fixed  17 satellites  s.d. 1.2 cm"));
    assert!(shows(&harness, "row +3.4 cm +- 0.8 cm at the rear axle"));
    assert!(shows(&harness, "camera 0  GNSS 3"));
}

#[test]
fn the_header_turns_red_with_the_age_when_the_status_is_older_than_a_second() {
    let _one = crate::one_at_a_time();
    let harness = watching(Duration::from_secs(3), |_, _| {});
    assert!(shows(
        &harness,
        "watching mechweed at tcp/10.0.0.7:7510: no status for 3."
    ));
    assert!(harness.state().view.remote.as_ref().unwrap().stale());
}

#[test]
fn a_view_that_never_got_a_status_shows_no_value_and_says_what_it_waits_for() {
    let _one = crate::one_at_a_time();
    // Nothing listening at the address: no status ever came. The window used to show
    // HALT, "E-stop front PRESSED", 0.00 V, "connected, idle", "schedulable" and a
    // claim about the robot's accept_requests, none of them received.
    let remote =
        RemoteView::offline("mechweed", "tcp/10.0.0.7:7510").opened_ago(Duration::from_secs(7));
    let harness = watch_harness::window(remote, Settings::shipped(), [1280.0, 1000.0]);
    assert!(shows(&harness, "NO DATA YET"));
    assert!(shows(
        &harness,
        "no data yet: waiting for mechweed's status at tcp/10.0.0.7:7510 (7 s)"
    ));
    for invented in [
        "PRESSED",
        "0.00 V",
        "connected, idle",
        "schedulable",
        "no fault",
        "requests: HALT only",
        "m/s   wheel",
    ] {
        assert!(
            !shows(&harness, invented),
            "shows '{invented}', never received"
        );
    }
    // "HALT" only on its button, not as a mode never received.
    assert_eq!(harness.query_all_by_label("HALT").count(), 1);
    // The mode buttons say why they wait; HALT is always there to press.
    assert!(!enabled(&harness, "Power up"));
    assert!(!enabled(&harness, "Autonomous"));
    assert!(shows(&harness, "waiting for the robot's first status"));
    assert!(enabled(&harness, "HALT"));
}

#[test]
fn a_robot_that_fell_silent_is_counted_up_each_second_then_greyed_then_unknown() {
    let _one = crate::one_at_a_time();
    use mechweed::gui::app::Tab;
    use mechweed::gui::pace::Pace;
    // The pacer asked for a frame only when the link went stale, so the header froze at
    // "no status for 1.0 s" while the robot was gone.
    let mut remote = watch_harness::fed(Duration::ZERO, |_, _| {});
    let heard = Instant::now();
    let mut pace = Pace::default();
    let mut passes = 0;
    let mut frames_at_s = Vec::new();
    for step in 0..40 {
        // 0.1 s steps of the pacer's clock, from 1.05 s of silence to 4.95 s.
        let silent_s = 1.05 + 0.1 * step as f64;
        let view = remote.view_at(heard + Duration::from_secs_f64(silent_s));
        if pace.look(&view, Tab::Status, passes, silent_s).draw {
            frames_at_s.push(silent_s);
            passes += 1; // the GUI thread drew it
        }
    }
    for second in 2..=4 {
        let s = second as f64;
        assert!(
            frames_at_s.iter().any(|&t| (s..s + 0.11).contains(&t)),
            "no frame at {second} s of silence: {frames_at_s:?}"
        );
    }

    // Stale: the values are greyed (disabled), the mode too; HALT stays.
    let harness = watching(Duration::from_secs(2), |_, _| {});
    assert!(shows(&harness, "AUTONOMOUS"));
    let values = harness.get_by_label_contains("m/s   wheel");
    assert!(
        values.accesskit_node().is_disabled(),
        "stale values not greyed"
    );
    let tick: Value = recorded()[3].1.clone();
    let counts = format!("{:>10} counts", tick["enc_left_counts"].as_i64().unwrap());
    let encoder = harness.get_by_label_contains(&counts);
    assert!(
        encoder.accesskit_node().is_disabled(),
        "stale status tab not greyed"
    );
    assert!(enabled(&harness, "HALT"));

    // Beyond [gui] remote_stale_s (5 s shipped): the mode is no longer claimed.
    let harness = watching(Duration::from_secs(6), |_, _| {});
    assert!(shows(&harness, "UNKNOWN"));
    assert!(!shows(&harness, "AUTONOMOUS"));
    assert!(shows(&harness, "no status for 6 s: its mode is not known"));
    assert!(!enabled(&harness, "Autonomous"));
}

#[test]
fn before_the_robot_says_whether_it_takes_requests_nothing_is_claimed_about_it() {
    let _one = crate::one_at_a_time();
    // The first status came; the answer to "accept_requests?" not yet.
    let remote = RemoteView::offline("mechweed", "tcp/10.0.0.7:7510");
    for (flow, payload) in recorded() {
        remote.feed(flow, payload.to_string().as_bytes(), Instant::now());
    }
    let harness = watch_harness::window(remote, Settings::shipped(), [1280.0, 1000.0]);
    assert!(shows(&harness, "requests: HALT; the rest not known yet"));
    assert!(!shows(&harness, "requests: HALT only"));
    assert!(shows(
        &harness,
        "asking the robot whether it takes requests"
    ));
    assert!(!enabled(&harness, "Power up"));
    assert!(enabled(&harness, "HALT"));
}

#[test]
fn a_fault_on_the_robot_is_shown_in_its_words() {
    let _one = crate::one_at_a_time();
    let harness = watching(Duration::from_millis(100), |flow, payload| {
        if flow == Flow::Status {
            payload["mode"] = "fault".into();
            payload["fault"] = "camera link lost: no row frame for 0.50 s".into();
        }
    });
    assert!(shows(
        &harness,
        "FAULT: camera link lost: no row frame for 0.50 s"
    ));
    assert!(shows(&harness, "FAULT"));
}

#[test]
fn halt_is_always_sent_and_the_rest_only_where_the_robot_takes_it_from_the_bus() {
    let _one = crate::one_at_a_time();
    // Standing in halt, powered: every mode is the robot's to allow.
    let mut harness = watching(Duration::from_millis(100), |_, payload| {
        payload["mode"] = "halt".into();
    });
    // The robot takes only HALT from the bus (its shipped settings).
    assert!(!enabled(&harness, "Power up"));
    assert!(!enabled(&harness, "Autonomous"));
    assert!(shows(
        &harness,
        "watching only: the robot takes only HALT from the bus"
    ));
    // The Space key is HALT, as the button is ("HALT" is also the mode's name here).
    harness.key_press(eframe::egui::Key::Space);
    harness.run_steps(2);
    assert_eq!(sent(&harness), [r#"{"request":"halt"}"#]);

    // With [bus] accept_requests = operator the modes are the robot's to decide.
    if let Source::Remote(remote) = &harness.state().shared.lock().source {
        remote.set_operator(true);
    }
    harness.run_steps(2);
    assert!(shows(&harness, "requests: HALT, power up and modes"));
    assert!(enabled(&harness, "Autonomous"));
    harness.get_by_label("Autonomous").click();
    harness.run_steps(2);
    assert_eq!(
        sent(&harness)[1],
        r#"{"mode":"autonomous","request":"mode"}"#
    );
    // Gains are not sent from another computer: said, not silently dropped.
    let request = Request::Gains(Gains::from_settings(&Settings::shipped()));
    let (reply, _) = crossbeam_channel::bounded(1);
    let refused = harness.state().shared.lock().source.send(request, &reply);
    assert!(
        refused
            .unwrap_err()
            .contains("only HALT, power up and modes")
    );
}

/// A robot program on loopback with its bus on `port`.
fn robot(port: u16, extra: &[&str]) -> (tempfile::TempDir, Child) {
    let folder = tempfile::tempdir().unwrap();
    let child = common::mechweed()
        .args(["run", "--headless", "--duration", "60"])
        .args(common::test_run_settings(folder.path()))
        .args(["--set", "bus.enabled=yes"])
        .args(["--set", &format!("bus.listen=tcp/127.0.0.1:{port}")])
        .args(extra)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    (folder, child)
}

#[test]
fn the_view_reads_a_real_robots_flows_and_its_halt_is_answered() {
    let _one = crate::one_at_a_time();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let (_folder, mut child) = robot(port, &["--set", "bus.accept_requests=operator"]);
    let mut remote =
        RemoteView::connect(&format!("tcp/127.0.0.1:{port}"), "mechweed", None).unwrap();
    let end = Instant::now() + Duration::from_secs(30);
    let view = loop {
        let view = remote.view();
        let link = view.remote.clone().unwrap();
        // The status flow and the tick flow come separately, either first: a tick has
        // come when the steering potentiometer reads (about 2.5 V at the centre).
        let ticked = view.status.inputs.pot_v > 0.0;
        if link.age_s.is_some() && link.operator == Some(true) && view.status.tick > 0 && ticked {
            break view;
        }
        assert!(
            Instant::now() < end,
            "no status, no tick, or operator never seen: {link:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    };
    assert_eq!(view.status.mode, Mode::Halt);
    assert!(view.status.inputs.estop_front_released, "the tick's inputs");
    let (reply, _) = crossbeam_channel::bounded(1);
    remote.send(Request::Mode(Mode::Joystick), &reply).unwrap();
    let answer = loop {
        if let Some(answer) = remote.answers_in_words().pop() {
            break answer;
        }
        assert!(Instant::now() < end, "no answer from the robot");
        std::thread::sleep(Duration::from_millis(50));
    };
    // Not powered: the supervisor's own refusal, in its words.
    assert_eq!(answer.0, Request::Mode(Mode::Joystick));
    assert!(
        answer.1.unwrap_err().contains("power"),
        "the refusal names power"
    );
    let _ = child.kill();
    let _ = child.wait();
}

#[test]
fn messages_that_are_not_the_robots_flows_are_counted_and_change_nothing() {
    let _one = crate::one_at_a_time();
    let mut remote = RemoteView::offline("mechweed", "tcp/10.0.0.7:7510");
    let now = Instant::now();
    for (flow, payload) in recorded() {
        remote.feed(flow, payload.to_string().as_bytes(), now);
    }
    let before = remote.view_at(now);
    let mut no_mode = recorded()[0].1.clone();
    no_mode["mode"] = "dancing".into();
    let mut short_tick = recorded()[1].1.clone();
    short_tick.as_object_mut().unwrap().remove("amp_left_v");
    for (flow, bytes) in [
        (Flow::Status, b"not json".to_vec()),
        (Flow::Status, no_mode.to_string().into_bytes()),
        (Flow::Tick, b"[1, 2]".to_vec()),
        (Flow::Tick, short_tick.to_string().into_bytes()),
        (Flow::Tick, vec![0xff, 0xfe]),
    ] {
        remote.feed(flow, &bytes, now);
    }
    let after = remote.view_at(now);
    assert_eq!(after.remote.as_ref().unwrap().refused, 5);
    assert_eq!(after.status, before.status);
    assert_eq!(after.steer, before.steer);
}

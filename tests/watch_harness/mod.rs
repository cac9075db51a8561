//! The whole operator window (`GuiApp`) over a view of a robot on the bus, fed by hand
//! with flows recorded from a real run (`tests/watch_flows.jsonl`, lines of `mechweed
//! bus echo`: a status and a tick, twice, of the simulated robot in autonomous), as
//! zenoh's callback would hand them over. No controller, no network, no clock read but
//! the view's own.
#![allow(dead_code)]

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use mechweed::config::Settings;
use mechweed::gui::pacer::Source;
use mechweed::gui::remote::{Flow, RemoteView};
use mechweed::gui::{Controller, GuiApp};
use mechweed::run::RunOptions;
use serde_json::Value;

const RECORDED: &str = include_str!("../watch_flows.jsonl");

/// The recorded messages: (flow, payload).
pub fn recorded() -> Vec<(Flow, Value)> {
    RECORDED
        .lines()
        .map(|line| {
            let line: Value = serde_json::from_str(line).unwrap();
            let flow = match line["key"].as_str().unwrap() {
                "mechweed/status" => Flow::Status,
                "mechweed/tick" => Flow::Tick,
                other => panic!("a flow the view does not read: {other}"),
            };
            (flow, line["payload"].clone())
        })
        .collect()
}

/// A view of robot "mechweed" at 10.0.0.7 that has answered "HALT only" (its shipped
/// `[bus] accept_requests`), fed the recorded flows `age` ago, each changed by `change`.
pub fn fed(age: Duration, change: impl Fn(Flow, &mut Value)) -> RemoteView {
    let remote = RemoteView::offline("mechweed", "tcp/10.0.0.7:7510");
    remote.set_operator(false);
    let at = Instant::now() - age;
    for (flow, mut payload) in recorded() {
        change(flow, &mut payload);
        remote.feed(flow, payload.to_string().as_bytes(), at);
    }
    remote
}

/// The window over `remote`, `size` points large, with these settings, after two passes.
pub fn window(remote: RemoteView, settings: Settings, size: [f32; 2]) -> Harness<'static, GuiApp> {
    let opts = RunOptions::in_halt(settings);
    let controller: Controller = Arc::new(Mutex::new(None));
    let stop = Arc::new(AtomicBool::new(false));
    let app = GuiApp::new(
        Source::Remote(Box::new(remote)),
        &opts,
        None,
        stop,
        controller,
    );
    let mut harness = Harness::builder()
        .with_size(eframe::egui::vec2(size[0], size[1]))
        .build_ui_state(
            |ui, app: &mut GuiApp| {
                app.pass(ui.ctx());
                app.show(ui);
            },
            app,
        );
    harness.run_steps(2);
    harness
}

/// The GUI over a view fed the recorded flows `age` ago.
pub fn watching(age: Duration, change: impl Fn(Flow, &mut Value)) -> Harness<'static, GuiApp> {
    window(fed(age, change), Settings::shipped(), [1280.0, 1000.0])
}

pub fn shows(harness: &Harness<'static, GuiApp>, text: &str) -> bool {
    harness.query_all_by_label_contains(text).next().is_some()
}

pub fn enabled(harness: &Harness<'static, GuiApp>, label: &str) -> bool {
    !harness.get_by_label(label).accesskit_node().is_disabled()
}

/// What the view would have sent to the robot.
pub fn sent(harness: &Harness<'static, GuiApp>) -> Vec<String> {
    match &harness.state().shared.lock().source {
        Source::Remote(remote) => remote.sent.lock().clone(),
        Source::Local(_) => panic!("not watching"),
    }
}

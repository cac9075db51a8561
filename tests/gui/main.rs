//! The operator GUI's tests, through egui_kittest (no window): over the real
//! controller, over a test supervisor, and as `watch` over recorded flows.

#[path = "../common/mod.rs"]
mod common;
#[path = "../gui_harness/mod.rs"]
mod gui_harness;
#[path = "../test_supervisor/mod.rs"]
mod test_supervisor;
#[path = "../watch_harness/mod.rs"]
mod watch_harness;

mod gui;
mod gui_field;
mod gui_gamepad;
mod gui_panels;
mod gui_requests;
mod gui_watch;

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
mod gui_commission;
mod gui_fault_advice;
mod gui_field;
mod gui_figures;
mod gui_gamepad;
mod gui_panels;
mod gui_requests;
mod gui_watch;

/// The GUI's tests draw with the processor, and some count seconds on the wall clock (a
/// view's "no data yet: ... (7 s)"): side by side, one made another's second late on two
/// CPUs when the tests ran six at a time. Each takes this lock first, so that they run
/// one at a time.
fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    static GUI: std::sync::Mutex<()> = std::sync::Mutex::new(());
    GUI.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

//! The GUI's requests and the scripted operator without a controller or a window: a
//! test supervisor behind the real request channel answers (or not) as the test says.
//! Time is passed in, never read from a clock.

use crate::test_supervisor;

use mechweed::gui::requests::Requests;
use mechweed::gui::script::GuiScript;
use mechweed::gui::view::{View, ViewSource};
use mechweed::state::modes::{Mode, Request};
use mechweed::state::status::PowerState;
use test_supervisor::{TestSupervisor, robot};

#[test]
fn an_answer_that_never_comes_is_said_after_a_second() {
    let _one = crate::one_at_a_time();
    let supervisor = TestSupervisor::new(View::default());
    let mut requests = Requests::default();
    let id = requests.ask(Request::Mode(Mode::Halt), "halted");
    requests.post(&supervisor, 5.0);
    requests.take_answers();
    requests.post(&supervisor, 5.9);
    assert!(requests.is_open(id) && requests.feedback().is_none());
    requests.take_answers();
    requests.post(&supervisor, 6.1);
    assert!(!requests.is_open(id));
    let feedback = requests.feedback().cloned().unwrap();
    // Not "refused": a HALT that nothing answered may well have been taken.
    assert_eq!(
        feedback.text,
        "HALT: no answer (the robot may have halted: look at its status)"
    );
    assert_eq!(feedback.at_s, 5.0);
}

#[test]
fn the_script_asks_once_then_waits_for_the_answer_and_a_newer_status() {
    let _one = crate::one_at_a_time();
    let mut supervisor = TestSupervisor::new(robot(Mode::Halt, PowerState::Off));
    let mut requests = Requests::default();
    let mut script = GuiScript::new(&[], Mode::Autonomous);
    // One pass of the app: answers, view, script, send.
    let mut pass = |supervisor: &mut TestSupervisor, requests: &mut Requests| {
        requests.take_answers();
        let view = supervisor.view();
        script.pass(&view, requests);
        requests.post(supervisor, view.now_s);
    };
    pass(&mut supervisor, &mut requests);
    pass(&mut supervisor, &mut requests);
    supervisor.view.status.tick += 1;
    pass(&mut supervisor, &mut requests);
    assert_eq!(
        supervisor.answer(|_| Ok(())),
        [Request::PowerUp],
        "asked once"
    );
    // The answer has come, but the status still says Off: it is from before the answer.
    pass(&mut supervisor, &mut requests);
    pass(&mut supervisor, &mut requests);
    assert_eq!(supervisor.waiting(), 0, "not asked again on an old status");
    supervisor.view.status.tick += 1;
    supervisor.view.status.power = PowerState::On;
    pass(&mut supervisor, &mut requests);
    assert_eq!(
        supervisor.answer(|_| Ok(())),
        [Request::Mode(Mode::Autonomous)]
    );
    assert_eq!(
        requests.feedback().map(|f| f.text.as_str()),
        Some("operator script: power up")
    );
}

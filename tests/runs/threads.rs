//! The real threads, made to fail on purpose: a thread that panics, a thread that
//! stalls, and a supervisor that overruns its deadlines each end in a fault naming it,
//! with safe outputs.

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use mechweed::config::Settings;
use mechweed::console::run;
use mechweed::rt::health::ThreadName;
use mechweed::rt::inject::{Fail, Injection};
use mechweed::run::{RunOptions, RunOutcome};
use mechweed::state::fault_cause::FaultCause;
use mechweed::state::modes::Mode;
use mechweed_hw::Outputs;

/// One run at a time: several real-time runs side by side on a small machine overrun
/// each other's deadlines, which is not what these tests are about.
static ONE_RUN_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Drive autonomously for `seconds` with one failure injected at 1.5 s.
fn run_with(thread: ThreadName, action: Fail, seconds: f64) -> RunOutcome {
    let _turn = ONE_RUN_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut settings = Settings::shipped();
    // Tests run side by side; the bus has tests of its own, on ports of their own.
    settings.bus.enabled = false;
    if !matches!(action, Fail::Slow { .. }) {
        // A busy test machine may overrun now and then; that fault has its own test.
        settings.rt.max_overruns = 1_000_000;
    }
    if !matches!(action, Fail::Pause { .. }) {
        // Nor is a single late tick, here.
        settings.rt.max_late_periods = 100.0;
    }
    let options = RunOptions {
        settings,
        start_mode: Mode::Autonomous,
        duration_s: Some(seconds),
        status_every_s: 0.0,
        inject: Some(Injection {
            thread,
            at_s: 1.5,
            action,
        }),
    };
    run(&options, Arc::new(AtomicBool::new(false))).expect("the run starts")
}

fn first_fault(outcome: &RunOutcome) -> (FaultCause, f64) {
    assert_eq!(
        outcome.final_status.mode,
        Mode::Fault,
        "no fault: {:?}",
        outcome.faults
    );
    assert_eq!(outcome.final_status.outputs, Outputs::SAFE);
    let f = outcome.faults[0];
    (f.cause, f.t_s)
}

#[test]
fn a_panicking_steer_thread_is_a_fault_naming_it() {
    let outcome = run_with(ThreadName::Steer, Fail::Panic, 3.0);
    let (cause, t_s) = first_fault(&outcome);
    assert_eq!(
        cause,
        FaultCause::ThreadPanicked {
            thread: ThreadName::Steer
        }
    );
    // Timing is the benchmarks' business; here only: after the failure, well before the end.
    assert!((1.5..2.5).contains(&t_s), "fault at {t_s}");
}

#[test]
fn a_panicking_camera_link_thread_is_a_fault_naming_it() {
    let outcome = run_with(ThreadName::CameraLink, Fail::Panic, 3.0);
    let (cause, t_s) = first_fault(&outcome);
    assert_eq!(
        cause,
        FaultCause::ThreadPanicked {
            thread: ThreadName::CameraLink
        }
    );
    // Timing is the benchmarks' business; here only: after the failure, well before the end.
    assert!((1.5..2.5).contains(&t_s), "fault at {t_s}");
}

#[test]
fn a_stalled_steer_thread_is_found_within_its_heartbeat_time() {
    let timeout = Settings::shipped().rt.heartbeat_timeout_s;
    let outcome = run_with(ThreadName::Steer, Fail::Stall, 3.5);
    let (cause, t_s) = first_fault(&outcome);
    assert!(
        matches!(
            cause,
            FaultCause::ThreadStopped {
                thread: ThreadName::Steer,
                ..
            }
        ),
        "{cause:?}"
    );
    // Its last beat came at most one steer period (0.1 s) before the stall.
    assert!(
        t_s > 1.5 + timeout - 0.1 && t_s < 1.5 + timeout + 0.5,
        "fault at {t_s}"
    );
}

#[test]
fn overruns_past_the_limit_are_a_fault() {
    let rt = Settings::shipped().rt;
    // Every supervisor tick now takes 15 ms of a 10 ms period.
    let outcome = run_with(ThreadName::Supervisor, Fail::Slow { ms: 15 }, 4.5);
    let (cause, t_s) = first_fault(&outcome);
    assert!(matches!(cause, FaultCause::Overruns { .. }), "{cause:?}");
    // How many overruns are tolerated is the check's unit test (src/faults.rs); on a
    // loaded test machine the loop may overrun before the injection too, so here only:
    // the slow loop ends in this fault soon.
    let ticks_to_fault = rt.max_overruns as f64 + 1.0;
    assert!(t_s < 1.5 + 0.02 * ticks_to_fault + 0.5, "fault at {t_s}");
}

#[test]
fn one_stalled_supervisor_tick_is_a_fault() {
    // A hung card read: one tick of 200 ms, far fewer overruns than their limit.
    let rt = Settings::shipped().rt;
    assert!(rt.max_overruns > 1);
    let outcome = run_with(ThreadName::Supervisor, Fail::Pause { ms: 200 }, 3.0);
    let (cause, t_s) = first_fault(&outcome);
    let FaultCause::LateTick {
        late_ms,
        limit_ms,
        load,
    } = cause
    else {
        panic!("{cause:?}");
    };
    assert!(late_ms >= 150.0 && limit_ms < late_ms, "{cause:?}");
    assert!((1.5..2.0).contains(&t_s), "fault at {t_s}");
    assert!(cause.to_string().contains("stalled"), "{cause}");
    // The run read this computer's load: the words say whether it was busy.
    let load = load.expect("the run reads the computer's load");
    assert!(
        cause
            .to_string()
            .contains(&format!("the computer's load was {:.1} on", load.load_1min)),
        "{cause}"
    );
}

//! Unit tests of the checks that look at the other threads: the steer thread's row
//! sources, the threads' heartbeats, and the supervisor's own timing.

use super::liveness::FIRST_BEAT_S;
use super::tests::healthy_inputs;
use super::*;
use crate::camlink::LinkStatus;
use crate::rt::health::{ThreadHealth, ThreadName};
use crate::rt::load::CpuLoad;
use crate::state::measure::Measured;
use crate::steer::{SourceHealth, SteerCommand};

/// A healthy robot driving autonomously by `source` since t = 0, every thread beating
/// at `now_s`; the tests change what they look at.
struct Given {
    checks: FaultChecks,
    settings: Settings,
    now_s: f64,
    mode: Mode,
    tick_gap_s: f64,
    steer: SteerCommand,
    link: LinkStatus,
    health: ThreadHealth,
}

impl Given {
    fn driving(source: SteerSource, now_s: f64) -> Given {
        let mut settings = Settings::shipped();
        settings.sources.source = source;
        let period_s = 1.0 / settings.supervisor.rate_hz;
        Given {
            checks: FaultChecks::new(&settings),
            settings,
            now_s,
            mode: Mode::Autonomous,
            tick_gap_s: period_s,
            steer: SteerCommand {
                t_s: now_s,
                mode: Mode::Autonomous,
                sources: SourceHealth {
                    steering: Steering::Fused,
                    camera_good_s: now_s,
                    gnss_good_s: now_s,
                    ..SourceHealth::default()
                },
                ..SteerCommand::default()
            },
            link: LinkStatus {
                beat_s: now_s,
                last_row_s: now_s,
                last_usable_s: now_s,
                ..LinkStatus::default()
            },
            health: ThreadHealth {
                gui_beat_s: Some(now_s),
                ..ThreadHealth::default()
            },
        }
    }

    /// The checks of one tick at `now_s` (the threads' beats as they are).
    fn check_at(&mut self, now_s: f64) -> Option<FaultCause> {
        self.now_s = now_s;
        let inputs = healthy_inputs();
        self.checks.check(&CheckContext {
            now_s,
            tick_gap_s: self.tick_gap_s,
            mode: self.mode,
            mode_since_s: 0.0,
            power: PowerState::On,
            inputs: &inputs,
            measured: &Measured::default(),
            driven_v: [0.0; 3],
            relay_closed: true,
            brakes_released: [false; 2],
            expected_mps: [0.0; 2],
            counts_moved: [false; 3],
            endswitch_hit: None,
            steer: &self.steer,
            link: &self.link,
            health: &self.health,
        })
    }
}

#[test]
fn losing_every_row_source_says_how_long_each_has_been_lost() {
    let mut given = Given::driving(SteerSource::Fused, 10.0);
    given.steer.sources = SourceHealth {
        steering: Steering::Nothing,
        camera_good_s: 9.0,
        gnss_good_s: 8.0,
        ..SourceHealth::default()
    };
    let timeout_s = given.settings.camera.link_timeout_s;
    assert_eq!(given.check_at(10.0), None);
    given.steer.t_s = 10.0 + timeout_s * 1.2;
    let now_s = given.steer.t_s;
    let Some(FaultCause::NoRowSource { camera_s, gnss_s }) = given.check_at(now_s) else {
        panic!(
            "no fault after {} s with nothing to steer by",
            timeout_s * 1.2
        );
    };
    assert!(
        (camera_s - (now_s - 9.0)).abs() < 1e-9,
        "camera lost {camera_s} s"
    );
    assert!(
        (gnss_s - (now_s - 8.0)).abs() < 1e-9,
        "GNSS lost {gnss_s} s"
    );
}

#[test]
fn a_person_who_took_the_joystick_from_a_robot_off_its_row_gets_no_off_the_row_fault() {
    // The operator switched to Joystick because the robot left the row; the steer
    // thread's last command is still the autonomous one for up to one steer period.
    let mut given = Given::driving(SteerSource::Fused, 10.0);
    let off_row_m = given.settings.faults.off_row_m;
    given.steer.sources.row_offset_m = 2.0 * off_row_m;
    assert_eq!(
        given.check_at(10.0),
        Some(FaultCause::OffTheRow {
            offset_m: 2.0 * off_row_m
        })
    );
    let mut given = Given::driving(SteerSource::Fused, 10.0);
    given.steer.sources.row_offset_m = 2.0 * off_row_m;
    given.mode = Mode::Joystick;
    assert_eq!(given.check_at(10.0), None);
}

#[test]
fn a_thread_that_stops_beating_is_a_fault_after_its_time_out_and_the_gui_gets_longer() {
    let rt = Settings::shipped().rt;
    for (thread, timeout_s) in [
        (ThreadName::Steer, rt.heartbeat_timeout_s),
        (ThreadName::CameraLink, rt.heartbeat_timeout_s),
        (ThreadName::Gui, rt.gui_heartbeat_timeout_s),
    ] {
        let mut given = Given::driving(SteerSource::Camera, 10.0);
        // The others go on beating; this one beat last at 10 s.
        let beating = |given: &mut Given, now_s: f64| {
            given.steer.t_s = now_s;
            given.link.beat_s = now_s;
            given.link.last_row_s = now_s;
            given.link.last_usable_s = now_s;
            given.steer.sources.camera_good_s = now_s;
            given.health.gui_beat_s = Some(now_s);
            match thread {
                ThreadName::Steer => given.steer.t_s = 10.0,
                ThreadName::CameraLink => given.link.beat_s = 10.0,
                _ => given.health.gui_beat_s = Some(10.0),
            }
        };
        let before_s = 10.0 + timeout_s * 0.9;
        beating(&mut given, before_s);
        assert_eq!(given.check_at(before_s), None, "{thread:?}");
        let after_s = 10.0 + timeout_s * 1.1;
        beating(&mut given, after_s);
        let cause = given.check_at(after_s);
        assert!(
            matches!(cause, Some(FaultCause::ThreadStopped { thread: t, for_s, started: true })
                if t == thread && (for_s - timeout_s * 1.1).abs() < 1e-9),
            "{thread:?}: {cause:?}"
        );
    }
}

#[test]
fn a_thread_slow_to_start_on_a_busy_computer_is_given_time_and_one_that_never_starts_is_a_fault() {
    let rt = Settings::shipped().rt;
    for thread in [ThreadName::Steer, ThreadName::CameraLink] {
        // The controller has just started: the others beat, this one has not yet.
        let mut given = Given::driving(SteerSource::Camera, 0.0);
        given.mode = Mode::Halt;
        let others_beat = |given: &mut Given, now_s: f64| {
            given.steer.t_s = now_s;
            given.link.beat_s = now_s;
            match thread {
                ThreadName::Steer => given.steer.t_s = 0.0,
                _ => given.link.beat_s = 0.0,
            }
        };
        let late_s = 2.0 * rt.heartbeat_timeout_s;
        others_beat(&mut given, late_s);
        assert_eq!(given.check_at(late_s), None, "{thread:?} at {late_s} s");
        let never_s = FIRST_BEAT_S + 0.1;
        others_beat(&mut given, never_s);
        let cause = given.check_at(never_s).expect("a fault");
        assert!(
            matches!(cause, FaultCause::ThreadStopped { thread: t, started: false, .. }
                if t == thread),
            "{thread:?}: {cause:?}"
        );
        let said = cause.to_string();
        assert!(said.contains("did not start"), "{said}");
    }
}

#[test]
fn a_panic_in_any_thread_is_a_fault_naming_it() {
    let mut given = Given::driving(SteerSource::Camera, 10.0);
    given.health.panicked = Some(ThreadName::Steer);
    assert_eq!(
        given.check_at(10.0),
        Some(FaultCause::ThreadPanicked {
            thread: ThreadName::Steer
        })
    );
}

#[test]
fn a_late_tick_says_how_late_the_limit_in_milliseconds_and_the_computers_load() {
    let mut given = Given::driving(SteerSource::Camera, 10.0);
    let period_s = 1.0 / given.settings.supervisor.rate_hz;
    let limit_s = given.settings.rt.max_late_periods * period_s;
    given.tick_gap_s = period_s + 2.0 * limit_s;
    // Three times the work the CPUs can do, as when a compiler runs beside the robot.
    given.health.cpu_load = Some(CpuLoad {
        load_1min: 6.0,
        cpus: 2,
    });
    let cause = given.check_at(10.0);
    let Some(FaultCause::LateTick {
        late_ms, limit_ms, ..
    }) = cause
    else {
        panic!("a tick {} ms late passed", 2.0 * limit_s * 1e3);
    };
    let words = cause.unwrap().to_string();
    assert!(
        words.contains("the computer's load was 6.0 on 2 CPUs: other programs took the CPU"),
        "{words}"
    );
    assert!(
        (late_ms - 2.0 * limit_s * 1e3).abs() < 1e-6,
        "late {late_ms} ms"
    );
    assert!(
        (limit_ms - limit_s * 1e3).abs() < 1e-6,
        "limit {limit_ms} ms"
    );
}

#[test]
fn a_burst_of_overruns_counted_in_one_tick_is_a_fault() {
    // The real-time thread can report many overruns at once (a stall of the computer).
    let mut given = Given::driving(SteerSource::Camera, 10.0);
    let limit = given.settings.rt.max_overruns as u64;
    given.health.supervisor_overruns = limit + 1;
    given.health.cpu_load = Some(CpuLoad {
        load_1min: 0.2,
        cpus: 2,
    });
    let cause = given.check_at(10.0);
    assert!(matches!(cause, Some(FaultCause::Overruns { .. })));
    // Not busy: the words must not blame other programs.
    let words = cause.unwrap().to_string();
    assert!(
        words.ends_with("load was 0.2 on 2 CPUs (not busy)"),
        "{words}"
    );
}

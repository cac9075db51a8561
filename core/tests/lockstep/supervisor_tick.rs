//! The supervisor's own tick, through the real supervisor on the simulated robot: a tick
//! that comes late, a card that fails, the row's end, and what it tells the operator
//! about the sensors that steer.

use crate::common;

use common::{autonomous, record, settings_with, tick_by_hand};
use mechweed_core::config::{CameraPort, GnssPort, SteerSource};
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::Mode;
use mechweed_core::state::status::Notice;
use mechweed_core::steer::Steering;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::Outputs;

#[test]
fn a_tick_that_comes_late_is_a_fault_naming_how_late() {
    // The computer stalled for 100 ms: for that long the amplifiers drove unwatched.
    let s = settings_with("", &[]);
    let period_s = 1.0 / s.supervisor.rate_hz;
    let limit_s = s.rt.max_late_periods * period_s;
    let mut sim = autonomous(&s);
    record(&mut sim, 3.0);
    assert!(sim.supervisor.faults().is_empty());
    let now_s = sim.now_s() + 0.1;
    let command = sim.steer_command;
    let outputs = tick_by_hand(&mut sim, now_s, &command, |_| {});
    assert_eq!(outputs, Outputs::SAFE);
    let log = sim.supervisor.faults();
    let Some(FaultCause::LateTick {
        late_ms, limit_ms, ..
    }) = log.first().map(|f| f.cause)
    else {
        panic!("{log:?}");
    };
    assert!(
        (late_ms - (100.0 - period_s * 1e3)).abs() < 1e-6,
        "{late_ms} ms"
    );
    assert!((limit_ms - limit_s * 1e3).abs() < 1e-6, "{limit_ms} ms");
}

#[test]
fn a_card_that_fails_is_a_fault_in_the_tick_that_counts_it() {
    let s = settings_with("", &[]);
    let mut sim = autonomous(&s);
    record(&mut sim, 1.0);
    let last_tick = sim.supervisor.status().tick;
    let now_s = sim.now_s() + 0.01;
    assert_eq!(
        sim.supervisor.hardware_failed(now_s, "PCI-DAS08"),
        Outputs::SAFE
    );
    let fault = sim.supervisor.faults()[0];
    assert_eq!(fault.cause, FaultCause::Hardware { card: "PCI-DAS08" });
    assert_eq!(fault.tick_seen, last_tick + 1);
    // It goes on failing: each tick is still counted, the first fault kept.
    sim.supervisor.hardware_failed(now_s + 0.01, "PCI-DAS08");
    assert_eq!(sim.supervisor.status().tick, last_tick + 2);
    assert_eq!(sim.supervisor.faults().len(), 1);
}

#[test]
fn at_the_rows_end_the_robot_stops_in_halt_and_says_how_far_it_drove() {
    let mut s = settings_with("", &[]);
    s.supervisor.row_length_m = 4.0;
    let end_m = 4.0 - s.robot.tool_offset_m;
    let mut sim = autonomous(&s);
    record(&mut sim, 20.0);
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    assert_eq!(sim.supervisor.mode(), Mode::Halt);
    let ended: Vec<f64> = sim
        .supervisor
        .notices()
        .iter()
        .filter_map(|n| match n {
            Notice::RowEnded { driven_m, .. } => Some(*driven_m),
            _ => None,
        })
        .collect();
    assert_eq!(ended.len(), 1, "{:?}", sim.supervisor.notices());
    assert!((ended[0] - end_m).abs() < 0.05, "drove {} m", ended[0]);
    assert!(sim.robot.truth().speed_mps.abs() < 0.02, "still moving");
}

#[test]
fn a_fused_run_tells_once_that_both_sensors_steer_and_never_names_a_stale_command() {
    // The first steer period in Autonomous still carries the command made in Halt: the
    // operator must not be told that nothing steers.
    let mut s = settings_with("", &[]);
    s.sources.source = SteerSource::Fused;
    s.gnss.port = GnssPort::Link(CameraPort::Sim);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    record(&mut sim, 8.0);
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    let said: Vec<Steering> = sim
        .supervisor
        .notices()
        .iter()
        .filter_map(|n| match n {
            Notice::Steering { steering, .. } => Some(*steering),
            _ => None,
        })
        .collect();
    assert_eq!(said, [Steering::Fused], "{:?}", sim.supervisor.notices());
}

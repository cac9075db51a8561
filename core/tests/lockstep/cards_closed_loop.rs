//! The controller on the simulated robot through emulated I/O cards: plant -> card
//! registers -> drivers -> wiring -> supervisor, and back. It must follow the row as
//! well as with the plant wired straight to the supervisor, and a card that stops
//! answering must be a fault naming it, with safe outputs on every card that answers,
//! in the supervisor tick that finds it.

use crate::common;

use common::settings_with;
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::Mode;
use mechweed_core::threads::lockstep::{Io, Lockstep};
use mechweed_hw::emulated::CardRig;
use mechweed_hw::sim::{CrossTrackSummary, RowShape, SimParams};
use mechweed_hw::{EncoderId, Outputs};

/// Drive the benchmark S-curve at 0.5 m/s to its end; the cross-track figures.
fn drive_row(io: fn(&mechweed_core::config::Settings) -> Io) -> (CrossTrackSummary, Vec<String>) {
    let mut s = settings_with("", &[]);
    s.sim = SimParams::benchmark(RowShape::SCurve, 1);
    s.steer.speed_mps = 0.5;
    let mut sim = Lockstep::with_io(&s, Mode::Autonomous, io(&s));
    while !sim.robot.truth().row_done && sim.now_s() < 200.0 {
        sim.tick();
    }
    let faults = sim
        .supervisor
        .faults()
        .iter()
        .map(|f| f.cause.to_string())
        .collect();
    (sim.robot.cross_track().summary(), faults)
}

#[test]
fn follows_the_row_through_the_cards_as_well_as_directly() {
    let (direct, direct_faults) = drive_row(|_| Io::Direct);
    let (cards, card_faults) = drive_row(|s| Io::cards(s).unwrap());
    eprintln!(
        "cross-track s.d. direct {:.3} cm, through the cards {:.3} cm, over {:.1} m",
        direct.sd_cm, cards.sd_cm, cards.distance_m
    );
    assert!(
        direct_faults.is_empty() && card_faults.is_empty(),
        "{card_faults:?}"
    );
    assert!(
        cards.distance_m > 50.0,
        "measured over {} m",
        cards.distance_m
    );
    assert!(
        (cards.sd_cm - direct.sd_cm).abs() < 0.2,
        "cross-track s.d. through the cards {:.3} cm, direct {:.3} cm",
        cards.sd_cm,
        direct.sd_cm
    );
    assert!(cards.sd_cm < 1.5, "{cards:?}");
}

/// Driving autonomously through the emulated cards for 5 s.
fn driving_through_cards() -> Lockstep {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::with_io(&s, Mode::Autonomous, Io::cards(&s).unwrap());
    sim.run_for(5.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    assert!(sim.robot.outputs().amp_left_v > 0.5, "driving");
    sim
}

fn rig(sim: &mut Lockstep) -> &mut CardRig {
    match &mut sim.io {
        Io::Cards(rig) => rig,
        Io::Direct => panic!("not through the cards"),
    }
}

/// Break a card, run one tick: the fault it causes and that tick's number.
fn break_and_tick(sim: &mut Lockstep, break_card: impl FnOnce(&mut CardRig)) -> (FaultCause, u64) {
    break_card(rig(sim));
    let outputs = sim.tick();
    assert_eq!(
        outputs,
        Outputs::SAFE,
        "the tick that found it wrote safe outputs"
    );
    let fault = sim
        .supervisor
        .status()
        .fault
        .expect("a fault in the same tick");
    assert_eq!(fault.tick_seen, fault.tick_safe);
    assert_eq!(fault.tick_seen, sim.supervisor.status().tick);
    (fault.cause, fault.tick_seen)
}

fn dacs_at_zero(rig: &CardRig) -> bool {
    (0..6).all(|n| rig.dda06.dac_code(n) == 0x8000)
}

#[test]
fn an_a_d_stuck_busy_is_a_fault_naming_the_das08_with_every_card_safe() {
    let mut sim = driving_through_cards();
    let (cause, _) = break_and_tick(&mut sim, |rig| rig.das08.set_eoc_stuck(true));
    assert_eq!(cause, FaultCause::Hardware { card: "PCI-DAS08" });
    assert_eq!(cause.to_string(), "I/O card PCI-DAS08 stopped answering");
    let rig = rig(&mut sim);
    assert!(dacs_at_zero(rig), "the DDA06 answered and got 0 V");
    assert!(
        (1..=4).all(|n| !rig.das08.output(n)),
        "its outputs still take writes"
    );
    assert_eq!(sim.robot.outputs(), Outputs::SAFE, "what reaches the robot");
}

#[test]
fn a_das08_that_reads_0xff_is_a_fault_naming_it_and_the_dda06_gets_0_volts() {
    let mut sim = driving_through_cards();
    let (cause, _) = break_and_tick(&mut sim, |rig| rig.das08.set_dead(true));
    assert_eq!(cause, FaultCause::Hardware { card: "PCI-DAS08" });
    assert!(dacs_at_zero(rig(&mut sim)));
    sim.run_for(0.5);
    assert_eq!(sim.supervisor.mode(), Mode::Fault, "stays latched");
}

#[test]
fn a_quad04_that_reads_0xff_is_a_fault_naming_it_with_every_other_card_safe() {
    let mut sim = driving_through_cards();
    let (cause, _) = break_and_tick(&mut sim, |rig| rig.quad04.set_dead(true));
    assert_eq!(cause, FaultCause::Hardware { card: "PCI-QUAD04" });
    let rig = rig(&mut sim);
    assert!(dacs_at_zero(rig) && (1..=4).all(|n| !rig.das08.output(n)));
}

#[test]
fn a_dda06_that_reads_0xff_shows_both_end_switches_and_the_das08_opens_the_contactor() {
    // Nothing documented reads back from the DDA06, so a dead one cannot be named;
    // with the robot's wiring it reads both end switches closed, itself a fault.
    let mut sim = driving_through_cards();
    let (cause, _) = break_and_tick(&mut sim, |rig| rig.dda06.set_dead(true));
    assert_eq!(cause, FaultCause::BothEndSwitches);
    let plant = sim.robot.outputs();
    assert!(!plant.main_power_on && !plant.brake_release_left && !plant.tool_on);
}

#[test]
fn a_counter_that_stops_is_the_encoder_fault_of_that_wheel() {
    let mut sim = driving_through_cards();
    rig(&mut sim).quad04.stop_counter(1);
    let t0 = sim.now_s();
    while sim.supervisor.status().fault.is_none() && sim.now_s() < t0 + 2.0 {
        sim.tick();
    }
    let fault = sim.supervisor.status().fault.expect("a fault");
    assert_eq!(fault.cause, FaultCause::EncoderStuck(EncoderId::Left));
    assert!(fault.t_s - t0 < 0.5, "after {:.2} s", fault.t_s - t0);
    assert_eq!(sim.robot.outputs(), Outputs::SAFE);
}

#[test]
fn a_welded_contactor_stops_the_watchdog_line_so_its_relay_can_cut_the_coil() {
    // Standing in Halt without power, the relay open; at 2 s the contacts weld and
    // motor power comes on. Only the watchdog relay can still cut the coil.
    let s = settings_with("2 contactor_welded", &[]);
    let mut sim = Lockstep::with_io(&s, Mode::Halt, Io::cards(&s).unwrap());
    let watchdog_line = |sim: &mut Lockstep| rig(sim).dda06.pin(1, 0);
    sim.run_for(1.0);
    let mut before = Vec::new();
    for _ in 0..6 {
        sim.tick();
        before.push(watchdog_line(&mut sim));
    }
    assert!(
        before.windows(2).all(|w| w[0] != w[1]),
        "toggling: {before:?}"
    );
    sim.run_for(1.5);
    assert_eq!(
        sim.supervisor.faults().first().map(|f| f.cause),
        Some(FaultCause::ContactorWelded)
    );
    let mut after = Vec::new();
    for _ in 0..20 {
        sim.tick();
        after.push(watchdog_line(&mut sim));
    }
    assert!(
        after.iter().all(|&level| !level),
        "still toggling: {after:?}"
    );
}

//! The watchdog output on the emulated DDA06 (robot.ini's `dda06 port b bit 0, active
//! high`): it changes on every write while every card answers, and stays at its
//! inactive level after the safe outputs, a failed write, a failed read, or drop.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::tests::{Breakable, driving, rig, settings};
use super::*;
use crate::cards::wiring::tests::robot;
use crate::emulated::{EmulatedDas08, EmulatedDda06, EmulatedQuad04};

/// The watchdog line's level on the DDA06's pins.
fn line(dda06: &EmulatedDda06) -> bool {
    dda06.pin(1, 0)
}

/// Levels of the watchdog line after each of `ticks` writes of `outputs`.
fn levels_over(
    hw: &mut CardsHw,
    dda06: &EmulatedDda06,
    outputs: &Outputs,
    ticks: usize,
) -> Vec<bool> {
    (0..ticks)
        .map(|_| {
            let _ = hw.write(outputs);
            line(dda06)
        })
        .collect()
}

fn alternating(from: bool, ticks: usize) -> Vec<bool> {
    (0..ticks).map(|k| from ^ (k % 2 == 1)).collect()
}

#[test]
fn the_watchdog_changes_on_every_write_and_reads_do_not_touch_it() {
    let mut rig = rig();
    assert!(!line(&rig.dda06), "stopped after open");
    let mut levels = Vec::new();
    for _ in 0..40 {
        rig.hw.read().unwrap();
        let before = line(&rig.dda06);
        rig.hw.write(&driving()).unwrap();
        levels.push(line(&rig.dda06));
        rig.hw.read().unwrap();
        assert_eq!(
            line(&rig.dda06),
            levels[levels.len() - 1],
            "a read leaves it"
        );
        assert_ne!(before, levels[levels.len() - 1]);
    }
    assert_eq!(
        levels,
        alternating(true, 40),
        "high, low, high ... : half the tick rate"
    );
    // Writing the safe outputs through `write` is the supervisor at work (in Halt or
    // Fault): it keeps changing.
    let safe = levels_over(&mut rig.hw, &rig.dda06, &Outputs::SAFE, 10);
    assert_eq!(safe, alternating(true, 10));
    assert_eq!(rig.plant_outputs(), Outputs::SAFE, "no other output moves");
}

#[test]
fn write_safe_and_drop_stop_the_watchdog_at_its_inactive_level() {
    let mut rig = rig();
    rig.hw.write(&driving()).unwrap();
    assert!(line(&rig.dda06), "active");
    rig.hw.write_safe().unwrap();
    assert!(!line(&rig.dda06), "held after write_safe");
    rig.hw.read().unwrap();
    assert!(!line(&rig.dda06));

    rig.hw.write(&driving()).unwrap();
    assert!(line(&rig.dda06), "the next write starts it again");
    let dda06 = rig.dda06.clone();
    drop(rig.hw);
    assert!(!line(&dda06), "held after drop");
    assert_eq!(dda06.dac_code(0), 0x8000);
}

/// Cards with a DAS08 that can be broken, opened by `CardsHw`.
fn breakable_das08() -> (CardsHw, EmulatedDda06, Arc<AtomicBool>) {
    let dda06 = EmulatedDda06::new(settings().dda06_ranges);
    let broken = Arc::new(AtomicBool::new(false));
    let ports = CardPorts {
        das08: Box::new(Breakable {
            inner: EmulatedDas08::new(),
            broken: broken.clone(),
        }),
        dda06: Box::new(dda06.clone()),
        quad04: Box::new(EmulatedQuad04::new()),
        descriptions: Default::default(),
    };
    let hw = CardsHw::open(ports, &settings(), &robot()).unwrap();
    (hw, dda06, broken)
}

#[test]
fn a_failed_write_stops_the_watchdog_while_the_card_fails() {
    let (mut hw, dda06, broken) = breakable_das08();
    assert_eq!(
        levels_over(&mut hw, &dda06, &driving(), 5),
        alternating(true, 5)
    );
    assert!(line(&dda06));
    broken.store(true, Ordering::Relaxed);
    let err = hw.write(&driving()).unwrap_err();
    assert!(
        err.to_string().starts_with("PCI-DAS08 stopped answering"),
        "{err}"
    );
    assert!(!line(&dda06), "held by the failed write");
    // The supervisor, now in Fault, writes the safe outputs every tick: they fail.
    let held = levels_over(&mut hw, &dda06, &Outputs::SAFE, 20);
    assert_eq!(held, vec![false; 20], "no change while the DAS08 fails");
    assert!(dda06.dac_code(0) == 0x8000);

    // Answering again (a read and a write that work): the supervisor vouches again.
    broken.store(false, Ordering::Relaxed);
    hw.read().unwrap();
    assert_eq!(
        levels_over(&mut hw, &dda06, &Outputs::SAFE, 4),
        alternating(true, 4)
    );
}

#[test]
fn a_card_that_stops_answering_a_read_stops_the_watchdog_though_writes_succeed() {
    // A dead DAS08 reads 0xFF and swallows writes without an error: its outputs may
    // still close the contactor, so only the watchdog relay can cut the power.
    let mut rig = rig();
    for _ in 0..6 {
        rig.hw.read().unwrap();
        rig.hw.write(&driving()).unwrap();
    }
    rig.das08.set_dead(true);
    rig.hw.write(&driving()).unwrap();
    assert!(line(&rig.dda06), "active before the failed read");
    let mut levels = Vec::new();
    for _ in 0..20 {
        assert!(rig.hw.read().is_err());
        rig.hw.write(&Outputs::SAFE).unwrap();
        levels.push(line(&rig.dda06));
    }
    assert_eq!(levels, vec![false; 20], "held while a card does not answer");
    rig.das08.set_dead(false);
    rig.hw.read().unwrap();
    rig.hw.write(&Outputs::SAFE).unwrap();
    assert!(line(&rig.dda06), "changes again once every card answers");
}

#[test]
fn with_watchdog_none_port_b_stays_an_input() {
    let wiring = Wiring {
        watchdog: None,
        ..robot()
    };
    let mut rig = crate::emulated::CardRig::new(&settings(), &wiring).unwrap();
    rig.dda06.set_pin(1, 0, true);
    for _ in 0..5 {
        rig.hw.write(&driving()).unwrap();
        assert!(
            line(&rig.dda06),
            "port b reads the outside wire, not a latch"
        );
    }
}

#[test]
fn motor_power_present_with_the_relay_open_stops_the_watchdog_until_it_is_gone() {
    // The unsafe state: the relay commanded open (the safe outputs, as in Fault), yet
    // motor power stays present: a welded contactor, a stuck relay driver. The watchdog
    // relay is then the one channel that can still cut the coil, so its line must stop.
    let mut rig = rig();
    let motor_power = 3; // das08 ip 3 in this wiring
    rig.das08.set_input(motor_power, true);
    let mut levels = Vec::new();
    for _ in 0..10 {
        assert!(rig.hw.read().unwrap().motor_power_present);
        rig.hw.write(&Outputs::SAFE).unwrap();
        levels.push(line(&rig.dda06));
    }
    assert_eq!(levels, vec![false; 10], "held at its inactive level");
    // With the relay closed, power present is what was asked: it toggles.
    let mut levels = Vec::new();
    for _ in 0..4 {
        rig.hw.read().unwrap();
        rig.hw.write(&driving()).unwrap();
        levels.push(line(&rig.dda06));
    }
    assert_eq!(levels, alternating(true, 4));
    // The contactor drops at last: the watchdog runs again with the relay open.
    rig.das08.set_input(motor_power, false);
    let mut levels = Vec::new();
    for _ in 0..4 {
        assert!(!rig.hw.read().unwrap().motor_power_present);
        rig.hw.write(&Outputs::SAFE).unwrap();
        levels.push(line(&rig.dda06));
    }
    assert_eq!(levels, alternating(true, 4));
}

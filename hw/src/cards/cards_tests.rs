//! CardsHw on the emulated cards: inputs through the wiring in physical units,
//! outputs onto the cards, the order at open, and safe outputs on every failure.

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::*;
use crate::cards::wiring::tests::robot;
use crate::emulated::{CardRig, EmulatedDas08, EmulatedDda06, EmulatedQuad04};
use DacRange::*;

pub(crate) fn settings() -> CardsSettings {
    CardsSettings {
        das08: CardLocation::PciAuto,
        dda06: CardLocation::PciAuto,
        quad04: CardLocation::PciAuto,
        dda06_ranges: [
            Bipolar10, Bipolar10, Bipolar10, Bipolar5, Bipolar5, Bipolar5,
        ],
        das08_eoc_timeout_us: 100.0,
    }
}

pub(super) fn rig() -> CardRig {
    CardRig::new(&settings(), &robot()).unwrap()
}

pub(super) fn driving() -> Outputs {
    Outputs {
        amp_left_v: 6.0,
        amp_right_v: 5.5,
        amp_steer_v: -2.0,
        main_power_on: true,
        brake_release_left: true,
        brake_release_right: true,
        tool_on: true,
    }
}

fn assert_cards_safe(rig: &CardRig) {
    assert!((1..=4).all(|n| !rig.das08.output(n)), "DAS08 outputs off");
    assert!(
        (0..6).all(|n| rig.dda06.dac_code(n) == 0x8000),
        "every DAC at 0x8000"
    );
    assert_eq!(rig.plant_outputs(), Outputs::SAFE);
}

#[test]
fn inputs_arrive_in_physical_units() {
    let mut rig = rig();
    rig.das08.set_ai_volts(0, 4.5);
    rig.das08.set_ai_volts(1, -4.0);
    rig.das08.set_ai_volts(2, 3.0);
    rig.das08.set_ai_volts(3, 2.4);
    rig.das08.set_input(1, true);
    rig.das08.set_input(3, true);
    rig.dda06.set_pin(0, 1, true);
    rig.quad04.set_encoder_edges(1, 1500);
    rig.quad04.set_encoder_edges(3, -40);
    let i = rig.hw.read().unwrap();
    let lsb = 10.0 / 4096.0;
    assert!((i.pot_v - 4.5).abs() <= lsb);
    assert!((i.joystick_steer_v + 4.0).abs() <= lsb);
    assert!((i.joystick_speed_v - 3.0).abs() <= lsb);
    assert!(
        (i.battery_v - 24.0).abs() <= 10.0 * lsb,
        "battery {} V",
        i.battery_v
    );
    assert!(i.estop_front_released && !i.estop_back_released && i.motor_power_present);
    assert!(!i.end_switch_left && i.end_switch_right && !i.joystick_enable);
    assert_eq!(
        (i.enc_left_counts, i.enc_right_counts, i.enc_steer_counts),
        (1500, 0, -40)
    );
}

#[test]
fn outputs_reach_the_cards() {
    let mut rig = rig();
    rig.hw.write(&driving()).unwrap();
    let out = rig.plant_outputs();
    assert!((out.amp_left_v - 6.0).abs() < 1e-3 && (out.amp_steer_v + 2.0).abs() < 1e-3);
    assert!(out.main_power_on && out.brake_release_left && out.brake_release_right && out.tool_on);
    rig.hw.write(&Outputs::SAFE).unwrap();
    assert_cards_safe(&rig);
}

/// Accesses of all three cards in one log, tagged with the card.
struct Tagged<P> {
    inner: P,
    card: &'static str,
    log: Arc<Mutex<Vec<(&'static str, bool)>>>,
}

impl<P: PortIo> PortIo for Tagged<P> {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        self.log.lock().unwrap().push((self.card, false));
        self.inner.read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        self.log.lock().unwrap().push((self.card, true));
        self.inner.write_u8(offset, value)
    }
}

#[test]
fn open_makes_the_outputs_safe_before_touching_the_counters() {
    let (das08, dda06, quad04) = (
        EmulatedDas08::new(),
        EmulatedDda06::new(settings().dda06_ranges),
        EmulatedQuad04::new(),
    );
    let log = Arc::new(Mutex::new(Vec::new()));
    let ports = CardPorts {
        das08: Box::new(Tagged {
            inner: das08.clone(),
            card: "das08",
            log: log.clone(),
        }),
        dda06: Box::new(Tagged {
            inner: dda06.clone(),
            card: "dda06",
            log: log.clone(),
        }),
        quad04: Box::new(Tagged {
            inner: quad04,
            card: "quad04",
            log: log.clone(),
        }),
        descriptions: Default::default(),
    };
    let _hw = CardsHw::open(ports, &settings(), &robot()).unwrap();
    let log = log.lock().unwrap();
    let first_quad = log.iter().position(|(card, _)| *card == "quad04").unwrap();
    assert_eq!(
        log[0],
        ("das08", true),
        "the DAS08 outputs are the very first write"
    );
    let dda06_writes = log[..first_quad]
        .iter()
        .filter(|a| **a == ("dda06", true))
        .count();
    assert!(
        dda06_writes >= 12,
        "all six DACs zeroed before the counters"
    );
    assert!((1..=4).all(|n| !das08.output(n)));
}

#[test]
fn an_a_d_that_never_finishes_names_the_das08_and_the_others_still_get_safe_outputs() {
    let mut rig = rig();
    rig.hw.write(&driving()).unwrap();
    rig.das08.set_eoc_stuck(true);
    let err = rig.hw.read().unwrap_err();
    assert!(
        matches!(
            err,
            HwError::CardNotAnswering {
                card: "PCI-DAS08",
                ..
            }
        ),
        "{err}"
    );
    rig.hw.write(&Outputs::SAFE).unwrap();
    assert_cards_safe(&rig);
}

#[test]
fn a_dead_das08_or_quad04_is_an_error_naming_it() {
    let mut rig = rig();
    rig.das08.set_dead(true);
    let err = rig.hw.read().unwrap_err();
    assert!(
        err.to_string().starts_with("PCI-DAS08 stopped answering"),
        "{err}"
    );
    let mut rig = self::rig();
    rig.quad04.set_dead(true);
    let err = rig.hw.read().unwrap_err();
    assert!(
        err.to_string().starts_with("PCI-QUAD04 stopped answering"),
        "{err}"
    );
}

/// A port whose accesses fail once `broken` is set (a card gone from the bus).
pub(super) struct Breakable<P> {
    pub(super) inner: P,
    pub(super) broken: Arc<AtomicBool>,
}

impl<P: PortIo> PortIo for Breakable<P> {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        if self.broken.load(Ordering::Relaxed) {
            return Err(io::Error::from(io::ErrorKind::NotConnected));
        }
        self.inner.read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        if self.broken.load(Ordering::Relaxed) {
            return Err(io::Error::from(io::ErrorKind::NotConnected));
        }
        self.inner.write_u8(offset, value)
    }
}

#[test]
fn a_failed_write_leaves_safe_outputs_on_the_cards_that_answer_and_so_does_drop() {
    let das08 = EmulatedDas08::new();
    let dda06 = EmulatedDda06::new(settings().dda06_ranges);
    let broken = Arc::new(AtomicBool::new(false));
    let ports = CardPorts {
        das08: Box::new(das08.clone()),
        dda06: Box::new(Breakable {
            inner: dda06.clone(),
            broken: broken.clone(),
        }),
        quad04: Box::new(EmulatedQuad04::new()),
        descriptions: Default::default(),
    };
    let mut hw = CardsHw::open(ports, &settings(), &robot()).unwrap();
    hw.write(&driving()).unwrap();
    assert!(das08.output(1) && das08.output(4));
    broken.store(true, Ordering::Relaxed);
    let err = hw.write(&driving()).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("PCIM-DDA06/16 stopped answering"),
        "{err}"
    );
    assert!(
        (1..=4).all(|n| !das08.output(n)),
        "the DAS08 was made safe in the same call"
    );

    broken.store(false, Ordering::Relaxed);
    hw.write(&driving()).unwrap();
    assert!(dda06.dac_volts(0) > 5.0);
    drop(hw);
    assert!(
        (1..=4).all(|n| !das08.output(n)) && dda06.dac_code(0) == 0x8000,
        "drop is safe"
    );
}

#[test]
fn a_card_missing_at_open_is_an_error_and_leaves_the_others_safe() {
    let das08 = EmulatedDas08::new();
    let dda06 = EmulatedDda06::new(settings().dda06_ranges);
    let quad04 = EmulatedQuad04::new();
    quad04.set_dead(true);
    let ports = CardPorts {
        das08: Box::new(das08.clone()),
        dda06: Box::new(dda06.clone()),
        quad04: Box::new(quad04),
        descriptions: Default::default(),
    };
    let Err(err) = CardsHw::open(ports, &settings(), &robot()) else {
        panic!("opened without a QUAD04")
    };
    assert!(err.to_string().starts_with("PCI-QUAD04"), "{err}");
    assert!((1..=4).all(|n| !das08.output(n)) && dda06.dac_code(2) == 0x8000);
}

#[test]
fn read_and_write_do_not_allocate() {
    use crate::sim::alloc_tests::allocations;
    let mut rig = rig();
    let inputs = Inputs {
        pot_v: 2.5,
        battery_v: 24.0,
        enc_left_counts: 10,
        ..Inputs::default()
    };
    rig.hw.write(&driving()).unwrap();
    let before = allocations();
    for k in 0..200 {
        rig.set_wires(&Inputs {
            enc_left_counts: k,
            ..inputs
        });
        let _ = rig.hw.read().unwrap();
        rig.hw.write(&driving()).unwrap();
        let _ = rig.plant_outputs();
    }
    assert_eq!(allocations() - before, 0);
}

#[test]
fn reads_and_writes_that_fail_do_not_allocate() {
    // Each way a card fails in a tick, and the safe outputs written after it.
    use crate::sim::alloc_tests::allocations;
    let breaks: [fn(&CardRig); 3] = [
        |rig| rig.das08.set_eoc_stuck(true),
        |rig| rig.das08.set_dead(true),
        |rig| rig.quad04.set_dead(true),
    ];
    for break_card in breaks {
        let mut rig = rig();
        rig.hw.write(&driving()).unwrap();
        break_card(&rig);
        let before = allocations();
        for _ in 0..20 {
            let failed = rig.hw.read().is_err();
            rig.hw.write(&Outputs::SAFE).unwrap();
            assert!(failed, "the card still fails");
        }
        assert_eq!(allocations() - before, 0);
    }
}

#[test]
fn cards_not_on_the_bus_are_all_reported_at_once() {
    let root = tempfile::tempdir().unwrap();
    let nowhere = Path::new("/nonexistent/port");
    let Err(err) = CardPorts::open(&settings(), &robot(), root.path(), nowhere) else {
        panic!("found cards in an empty directory")
    };
    let err = err.to_string();
    for name in ["PCI-DAS08", "PCIM-DDA06/16", "PCI-QUAD04"] {
        assert!(err.contains(&format!("no {name} (PCI id")), "{err}");
    }
}

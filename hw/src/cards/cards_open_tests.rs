//! Opening the cards when one of them cannot be opened, and several cards through one
//! /dev/port. Each test starts from the outputs a killed run leaves on the cards: the
//! contactor closed, the brakes released, the amplifiers driven, the watchdog line high.

use std::io;
use std::path::PathBuf;

use super::tests::settings;
use super::*;
use crate::cards::pci::VENDOR_MCC;
use crate::cards::pci::tests::{IO_BAR, device};
use crate::cards::port::kernel_locked_down;
use crate::cards::wiring::tests::robot;
use crate::emulated::{EmulatedDas08, EmulatedDda06};

/// A DAS08's control byte with all four outputs on: contactor, both brakes released, tool.
const DAS08_ALL_ON: u8 = 0xF0;
/// The DDA06 registers a killed run leaves: AO0..AO2 at +5 V (0xC000 on +-10 V), the
/// 8255 with port b an output and the watchdog line (port b bit 0) high.
fn dda06_killed_run() -> [u8; 16] {
    let mut regs = [0u8; 16];
    for n in 0..3 {
        regs[2 * n + 1] = 0xC0;
    }
    regs[0x0D] = 0x01;
    regs[0x0F] = 0x99;
    regs
}

/// An emulated DDA06 driving what a killed run left.
fn dda06_driving() -> EmulatedDda06 {
    let mut card = EmulatedDda06::new(settings().dda06_ranges);
    let regs = dda06_killed_run();
    // The control word first: it clears the output latches.
    card.write_u8(0x0F, regs[0x0F]).unwrap();
    for offset in 0..0x0F {
        card.write_u8(offset, regs[usize::from(offset)]).unwrap();
    }
    assert!(
        card.dac_volts(0) > 4.9 && card.pin(1, 0),
        "driving before the test"
    );
    card
}

fn opened(port: impl PortIo + 'static, name: &str) -> Result<OpenedCard, CardOpenError> {
    Ok(OpenedCard {
        port: Box::new(port),
        description: format!("emulated {name}"),
    })
}

#[test]
fn a_missing_quad04_still_leaves_the_das08_and_dda06_of_a_killed_run_safe() {
    let das08 = EmulatedDas08::new();
    let dda06 = dda06_driving();
    assert!(
        (1..=4).all(|n| das08.output(n)),
        "contactor closed, brakes released"
    );
    let missing = Err(CardOpenError::NotOnBus {
        card: CardKind::Quad04,
        root: "/sys/bus/pci/devices".into(),
    });
    let found = [
        opened(das08.clone(), "PCI-DAS08"),
        opened(dda06.clone(), "PCIM-DDA06/16"),
        missing,
    ];
    let Err(err) = CardPorts::all_or_safe(found, &settings(), &robot()) else {
        panic!("opened without a QUAD04")
    };
    let err = err.to_string();
    assert!(
        err.starts_with("no PCI-QUAD04 (PCI id 1307:004d) found"),
        "{err}"
    );
    assert!(
        err.ends_with(
            "(safe outputs written to the PCI-DAS08 and the PCIM-DDA06/16, which opened)"
        ),
        "{err}"
    );
    assert!(
        (1..=4).all(|n| !das08.output(n)),
        "contactor open, brakes on, tool off"
    );
    assert!(
        (0..6).all(|n| dda06.dac_code(n) == 0x8000),
        "every DAC at 0 V"
    );
    assert!(!dda06.pin(1, 0), "the watchdog line stopped");
}

#[test]
fn a_missing_das08_still_leaves_the_dda06_of_a_killed_run_at_0_v() {
    let dda06 = dda06_driving();
    let missing = Err(CardOpenError::CannotUse {
        card: CardKind::Das08,
        path: "/sys/bus/pci/devices/0000:03:00.0/resource2".into(),
        error: std::io::ErrorKind::NotFound,
        refusal: None,
    });
    let found = [
        missing,
        opened(dda06.clone(), "PCIM-DDA06/16"),
        opened(crate::emulated::EmulatedQuad04::new(), "PCI-QUAD04"),
    ];
    let err = CardPorts::all_or_safe(found, &settings(), &robot())
        .err()
        .unwrap()
        .to_string();
    assert!(err.starts_with("PCI-DAS08: cannot use"), "{err}");
    assert!(err.ends_with("(safe outputs written to the PCIM-DDA06/16, which opened)"));
    assert!((0..6).all(|n| dda06.dac_code(n) == 0x8000) && !dda06.pin(1, 0));
}

/// A fake /sys/bus/pci/devices with the cards `present` (DAS08, DDA06, QUAD04), their
/// BAR files holding a killed run's registers.
fn pci_tree(present: [bool; 3]) -> (tempfile::TempDir, [PathBuf; 3]) {
    let root = tempfile::tempdir().unwrap();
    let addresses = ["0000:03:00.0", "0000:04:00.0", "0000:05:00.0"];
    let bars = [
        root.path().join("0000:03:00.0/resource2"),
        root.path().join("0000:04:00.0/resource3"),
        root.path().join("0000:05:00.0/resource2"),
    ];
    for (k, kind) in CardKind::ALL.into_iter().enumerate() {
        if present[k] {
            device(
                root.path(),
                addresses[k],
                VENDOR_MCC,
                kind.device_id(),
                IO_BAR,
            );
        }
    }
    if present[0] {
        let mut das08 = [0u8; 16];
        das08[2] = DAS08_ALL_ON;
        std::fs::write(&bars[0], das08).unwrap();
    }
    if present[1] {
        std::fs::write(&bars[1], dda06_killed_run()).unwrap();
    }
    (root, bars)
}

/// The DDA06 registers after its safe outputs: DACs at 0x8000, 8255 port b an output
/// for the watchdog, held low.
fn dda06_safe(regs: &[u8]) -> bool {
    (0..6).all(|n| regs[2 * n] == 0x00 && regs[2 * n + 1] == 0x80)
        && regs[0x0F] == 0x99
        && regs[0x0D] & 0x01 == 0
}

#[test]
fn with_no_quad04_on_the_bus_the_das08_and_dda06_files_get_safe_outputs_before_the_error() {
    let (root, bars) = pci_tree([true, true, false]);
    let nowhere = Path::new("/nonexistent/port");
    let Err(err) = CardPorts::open(&settings(), &robot(), root.path(), nowhere) else {
        panic!("opened without a QUAD04")
    };
    let err = err.to_string();
    assert!(
        err.starts_with("no PCI-QUAD04 (PCI id 1307:004d) found"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&bars[0]).unwrap()[2],
        0x00,
        "DAS08 outputs off"
    );
    assert!(dda06_safe(&std::fs::read(&bars[1]).unwrap()));
}

#[test]
fn a_dda06_whose_bar_file_is_missing_is_named_and_the_das08_gets_safe_outputs() {
    let (root, bars) = pci_tree([true, true, true]);
    std::fs::remove_file(&bars[1]).unwrap();
    let nowhere = Path::new("/nonexistent/port");
    let Err(err) = CardPorts::open(&settings(), &robot(), root.path(), nowhere) else {
        panic!("opened without the DDA06's registers")
    };
    let err = err.to_string();
    assert!(
        err.starts_with("PCIM-DDA06/16: cannot use ") && err.contains("0000:04:00.0/resource3"),
        "{err}"
    );
    assert!(
        err.ends_with("(safe outputs written to the PCI-DAS08, which opened)"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&bars[0]).unwrap()[2],
        0x00,
        "DAS08 outputs off"
    );
}

/// A fake /dev/port: 0x400 ports, a killed run's DAS08 outputs at 0x100 + 2.
fn dev_port_file(dir: &Path) -> PathBuf {
    let path = dir.join("port");
    let mut ports = vec![0u8; 0x400];
    ports[0x102] = DAS08_ALL_ON;
    ports[0x200..0x210].copy_from_slice(&dda06_killed_run());
    std::fs::write(&path, ports).unwrap();
    path
}

#[test]
fn three_cards_through_one_dev_port_open_and_a_second_program_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let port = dev_port_file(dir.path());
    let s = CardsSettings {
        das08: CardLocation::PortBase(0x100),
        dda06: CardLocation::PortBase(0x200),
        quad04: CardLocation::PortBase(0x300),
        ..settings()
    };
    let ports = CardPorts::open(&s, &robot(), dir.path(), &port).unwrap();
    assert!(ports.descriptions[2].starts_with("PCI-QUAD04 at I/O port 0x0300 through"));
    let hw = CardsHw::open(ports, &s, &robot()).unwrap();
    let bytes = std::fs::read(&port).unwrap();
    assert_eq!(bytes[0x102], 0x00, "the DAS08 at its base, outputs off");
    assert!(
        dda06_safe(&bytes[0x200..0x210]),
        "the DDA06 at its base, safe"
    );
    assert_eq!(
        (bytes[0x308], bytes[0x309]),
        (0x0F, 0x00),
        "the QUAD04 at its base"
    );

    let Err(err) = CardPorts::open(&s, &robot(), dir.path(), &port) else {
        panic!("a second program took the cards beside the first")
    };
    let err = err.to_string();
    assert_eq!(
        err.matches("is in use by another program").count(),
        3,
        "{err}"
    );
    drop(hw);
    assert!(
        CardPorts::open(&s, &robot(), dir.path(), &port).is_ok(),
        "free again"
    );
}

#[test]
fn two_cards_through_dev_port_and_the_third_on_pci_open_together() {
    let (root, _) = pci_tree([false, false, true]);
    let port = dev_port_file(root.path());
    let s = CardsSettings {
        das08: CardLocation::PortBase(0x100),
        dda06: CardLocation::PortBase(0x200),
        ..settings()
    };
    let ports = CardPorts::open(&s, &robot(), root.path(), &port).unwrap();
    let _hw = CardsHw::open(ports, &s, &robot()).unwrap();
    let bytes = std::fs::read(&port).unwrap();
    assert_eq!(bytes[0x102], 0x00);
    assert!(dda06_safe(&bytes[0x200..0x210]));
}

/// A card's file that opened but whose every access is refused, as a kernel in
/// lockdown does with a sysfs BAR.
struct Refused;

impl PortIo for Refused {
    fn read_u8(&mut self, _offset: u16) -> io::Result<u8> {
        Err(io::ErrorKind::PermissionDenied.into())
    }
    fn write_u8(&mut self, _offset: u16, _value: u8) -> io::Result<()> {
        Err(io::ErrorKind::PermissionDenied.into())
    }
}

/// What a refused first access must explain.
fn why_refused() -> &'static str {
    if kernel_locked_down() {
        "The kernel is in lockdown (secure boot)"
    } else {
        "The kernel refused the port access"
    }
}

#[test]
fn a_first_access_refused_at_start_names_the_card_the_register_and_why() {
    let dda06 = dda06_driving();
    let ports = CardPorts {
        das08: Box::new(Refused),
        dda06: Box::new(dda06.clone()),
        quad04: Box::new(crate::emulated::EmulatedQuad04::new()),
        descriptions: Default::default(),
    };
    let Err(err) = CardsHw::open(ports, &settings(), &robot()) else {
        panic!("started a DAS08 whose every access is refused")
    };
    assert_eq!(
        err,
        HwError::CardNotAnswering {
            card: "PCI-DAS08",
            register: 2,
            fault: crate::CardFault::WriteFailed(io::ErrorKind::PermissionDenied),
        }
    );
    let text = OpenError::Starting(StartError::new(err)).to_string();
    assert!(
        text.starts_with("PCI-DAS08 stopped answering: writing register +2: permission denied. "),
        "{text}"
    );
    assert!(text.contains(why_refused()), "{text}");
    assert!(
        text.ends_with("(while starting the cards; the ones that answered have safe outputs)"),
        "{text}"
    );
    assert!(
        (0..6).all(|n| dda06.dac_code(n) == 0x8000) && !dda06.pin(1, 0),
        "the DDA06 answered and is safe"
    );
}

#[test]
fn a_refused_card_beside_a_missing_one_is_explained_and_the_other_made_safe() {
    let dda06 = dda06_driving();
    let missing = Err(CardOpenError::NotOnBus {
        card: CardKind::Quad04,
        root: "/sys/bus/pci/devices".into(),
    });
    let found = [
        opened(Refused, "PCI-DAS08"),
        opened(dda06.clone(), "PCIM-DDA06/16"),
        missing,
    ];
    let Err(err) = CardPorts::all_or_safe(found, &settings(), &robot()) else {
        panic!("opened without a QUAD04")
    };
    let OpenError::Cards {
        problems,
        made_safe,
    } = &err
    else {
        panic!("{err:?}")
    };
    assert_eq!(made_safe, &["PCIM-DDA06/16"]);
    assert!(
        matches!(problems[1], CardOpenError::NotAnswering(_)),
        "{problems:?}"
    );
    let lines: Vec<String> = err.to_string().lines().map(String::from).collect();
    assert!(
        lines[0].starts_with("no PCI-QUAD04 (PCI id 1307:004d) found"),
        "{lines:?}"
    );
    assert!(lines[1].starts_with("PCI-DAS08 stopped answering: writing register +2"));
    assert!(lines[1].contains(why_refused()), "{lines:?}");
    assert_eq!(
        lines[2],
        "(safe outputs written to the PCIM-DDA06/16, which opened)"
    );
    assert!((0..6).all(|n| dda06.dac_code(n) == 0x8000));
}

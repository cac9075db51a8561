//! Finding cards in a fake /sys/bus/pci/devices tree, with plain files for the BARs.

use super::*;

/// A fake PCI device directory as Linux shows it.
pub(crate) fn device(root: &Path, address: &str, vendor: u16, device: u16, bar_line: &str) {
    let dir = root.join(address);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("vendor"), format!("0x{vendor:04x}\n")).unwrap();
    std::fs::write(dir.join("device"), format!("0x{device:04x}\n")).unwrap();
    std::fs::write(dir.join("enable"), "0\n").unwrap();
    let none = "0x0000000000000000 0x0000000000000000 0x0000000000000000";
    let resource = format!("{none}\n{none}\n{bar_line}\n{bar_line}\n");
    std::fs::write(dir.join("resource"), resource).unwrap();
    std::fs::write(dir.join("resource2"), [0u8; 16]).unwrap();
    std::fs::write(dir.join("resource3"), [0u8; 16]).unwrap();
}

pub(crate) const IO_BAR: &str = "0x000000000000e000 0x000000000000e00f 0x0000000000040101";
const MEM_BAR: &str = "0x00000000fe000000 0x00000000fe00ffff 0x0000000000040200";

#[test]
fn finds_the_card_by_vendor_and_device_and_switches_it_on() {
    let root = tempfile::tempdir().unwrap();
    device(root.path(), "0000:00:1f.0", 0x8086, 0x0029, IO_BAR);
    device(root.path(), "0000:03:00.0", VENDOR_MCC, 0x0029, IO_BAR);
    device(root.path(), "0000:04:00.0", VENDOR_MCC, 0x004D, IO_BAR);
    let card = find(root.path(), CardKind::Das08, &CardLocation::PciAuto).unwrap();
    assert_eq!(card.address, "0000:03:00.0");
    assert_eq!(card.bar_ports, (0xe000, 0xe00f));

    let mut opened = open(
        root.path(),
        &mut DevPortFile::new(Path::new("/nonexistent")),
        CardKind::Das08,
        &CardLocation::PciAuto,
    )
    .unwrap();
    assert!(
        opened
            .description
            .contains("PCI-DAS08 at PCI 0000:03:00.0, BAR2"),
        "{}",
        opened.description
    );
    let enable = std::fs::read_to_string(root.path().join("0000:03:00.0/enable")).unwrap();
    assert_eq!(enable.trim(), "1");
    opened.port.write_u8(2, 0x40).unwrap();
    let bar = std::fs::read(root.path().join("0000:03:00.0/resource2")).unwrap();
    assert_eq!(bar[2], 0x40);
}

#[test]
fn a_missing_card_says_which_and_where_it_was_looked_for() {
    let root = tempfile::tempdir().unwrap();
    device(root.path(), "0000:00:1f.0", 0x8086, 0x1234, IO_BAR);
    let err = find(root.path(), CardKind::Quad04, &CardLocation::PciAuto)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no PCI-QUAD04 (PCI id 1307:004d) found"),
        "{err}"
    );
}

#[test]
fn two_cards_of_a_kind_ask_for_an_address() {
    let root = tempfile::tempdir().unwrap();
    device(root.path(), "0000:03:00.0", VENDOR_MCC, 0x0053, IO_BAR);
    device(root.path(), "0000:05:00.0", VENDOR_MCC, 0x0053, IO_BAR);
    let err = find(root.path(), CardKind::Dda06, &CardLocation::PciAuto)
        .unwrap_err()
        .to_string();
    assert!(err.contains("0000:03:00.0, 0000:05:00.0"), "{err}");
    let address = CardLocation::PciAddress("0000:05:00.0".into());
    let card = find(root.path(), CardKind::Dda06, &address).unwrap();
    assert_eq!(card.address, "0000:05:00.0");
}

#[test]
fn an_address_that_holds_another_device_is_refused() {
    let root = tempfile::tempdir().unwrap();
    device(root.path(), "0000:03:00.0", VENDOR_MCC, 0x0053, IO_BAR);
    let address = CardLocation::PciAddress("0000:03:00.0".into());
    let err = find(root.path(), CardKind::Das08, &address)
        .unwrap_err()
        .to_string();
    assert!(err.contains("is not a PCI-DAS08"), "{err}");
    let nowhere = CardLocation::PciAddress("0000:09:00.0".into());
    let err = find(root.path(), CardKind::Das08, &nowhere)
        .unwrap_err()
        .to_string();
    assert!(err.contains("no PCI device at 0000:09:00.0"), "{err}");
}

#[test]
fn a_memory_bar_is_not_taken_for_ports() {
    let root = tempfile::tempdir().unwrap();
    device(root.path(), "0000:03:00.0", VENDOR_MCC, 0x0029, MEM_BAR);
    let err = find(root.path(), CardKind::Das08, &CardLocation::PciAuto)
        .unwrap_err()
        .to_string();
    assert!(err.contains("not an I/O-port BAR"), "{err}");
}

#[test]
fn pci_addresses_are_checked() {
    assert_eq!(parse_pci_address("0000:03:00.0").unwrap(), "0000:03:00.0");
    assert_eq!(parse_pci_address("0000:0A:1f.7").unwrap(), "0000:0a:1f.7");
    for bad in ["03:00.0", "0000:03:00", "0000:3:00.0", "zzzz:03:00.0", ""] {
        assert!(parse_pci_address(bad).is_err(), "{bad}");
    }
}

#[test]
fn permission_errors_point_to_the_udev_rule_or_the_capability() {
    let denied = io::Error::from(io::ErrorKind::PermissionDenied);
    let sysfs = explain(
        CardKind::Das08,
        Path::new("/sys/bus/pci/devices/0000:03:00.0/resource2"),
        &denied,
    )
    .to_string();
    let devport = explain(CardKind::Dda06, Path::new("/dev/port"), &denied).to_string();
    if !kernel_locked_down() {
        assert!(sysfs.contains("udev rule"), "{sysfs}");
        assert!(devport.contains("CAP_SYS_RAWIO"), "{devport}");
    }
    assert!(sysfs.starts_with("PCI-DAS08: cannot use"), "{sysfs}");
}

//! Finding the three Measurement Computing cards and opening their register windows,
//! with no kernel driver (docs/function_spec.md section 4a).
//!
//! A card is found under /sys/bus/pci/devices by vendor 0x1307 and its device id, or
//! named by its PCI address in robot.ini; its I/O BAR is opened through sysfs after
//! switching decoding on (`enable`). Or robot.ini gives a base port for /dev/port.
//! Every failure says what to do about it: a missing card, a missing permission (the
//! udev rule or capability in docs/robot-pc.md), or a kernel in lockdown.

use std::io;
use std::path::{Path, PathBuf};

use crate::cards::port::{DevPortFile, PortIo, SysfsBar, kernel_locked_down};
use crate::{CardOpenError, Refusal};

/// Measurement Computing's PCI vendor id.
pub(crate) const VENDOR_MCC: u16 = 0x1307;

/// The three cards, with the facts needed to find and open them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CardKind {
    Das08,
    Dda06,
    Quad04,
}

impl CardKind {
    pub const ALL: [CardKind; 3] = [CardKind::Das08, CardKind::Dda06, CardKind::Quad04];

    /// The card's name, as printed on it and used in every message.
    pub fn name(self) -> &'static str {
        match self {
            CardKind::Das08 => "PCI-DAS08",
            CardKind::Dda06 => "PCIM-DDA06/16",
            CardKind::Quad04 => "PCI-QUAD04",
        }
    }

    pub(crate) fn device_id(self) -> u16 {
        match self {
            CardKind::Das08 => 0x0029,
            CardKind::Dda06 => 0x0053,
            CardKind::Quad04 => 0x004D,
        }
    }

    /// The BAR that holds the card's registers.
    pub fn bar(self) -> usize {
        match self {
            CardKind::Das08 | CardKind::Quad04 => 2,
            CardKind::Dda06 => 3,
        }
    }

    /// Bytes in the register window the drivers use.
    pub(crate) fn window_len(self) -> u16 {
        match self {
            CardKind::Das08 => 8,
            CardKind::Dda06 => 16,
            CardKind::Quad04 => 10,
        }
    }
}

/// Where robot.ini says a card is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CardLocation {
    /// The one card with this device id on the PCI bus.
    PciAuto,
    /// The card at this PCI address ("0000:03:00.0", as `lspci -D` shows it).
    PciAddress(String),
    /// Through /dev/port, from this base port.
    PortBase(u16),
}

/// Check a PCI address written as domain:bus:device.function in hex ("0000:03:00.0").
pub fn parse_pci_address(text: &str) -> Result<String, String> {
    let bad = || format!("'{text}' is not a PCI address like 0000:03:00.0 (see lspci -D)");
    let (domain, rest) = text.split_once(':').ok_or_else(bad)?;
    let (bus, rest) = rest.split_once(':').ok_or_else(bad)?;
    let (device, function) = rest.split_once('.').ok_or_else(bad)?;
    let hex =
        |s: &str, digits: usize| s.len() == digits && s.chars().all(|c| c.is_ascii_hexdigit());
    if hex(domain, 4) && hex(bus, 2) && hex(device, 2) && hex(function, 1) {
        Ok(text.to_ascii_lowercase())
    } else {
        Err(bad())
    }
}

/// One card as found on the bus: where it is and what its BAR spans.
#[derive(Debug, Clone, PartialEq)]
pub struct FoundCard {
    pub kind: CardKind,
    pub address: String,
    pub dir: PathBuf,
    /// First and last I/O port of the card's register BAR.
    pub bar_ports: (u64, u64),
}

/// An opened card: its register window and a line saying where it is.
pub struct OpenedCard {
    pub port: Box<dyn PortIo>,
    pub description: String,
}

fn read_hex(path: &Path) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let text = text.trim();
    u64::from_str_radix(text.trim_start_matches("0x"), 16).ok()
}

/// Every card of this kind under `root` (normally /sys/bus/pci/devices), sorted.
pub(crate) fn find_all(root: &Path, kind: CardKind) -> Result<Vec<String>, CardOpenError> {
    let entries = std::fs::read_dir(root).map_err(|e| CardOpenError::ListPciDevices {
        root: root.to_path_buf(),
        error: e.kind(),
    })?;
    let mut found: Vec<String> = entries
        .flatten()
        .filter(|entry| {
            let dir = entry.path();
            read_hex(&dir.join("vendor")) == Some(u64::from(VENDOR_MCC))
                && read_hex(&dir.join("device")) == Some(u64::from(kind.device_id()))
        })
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    found.sort();
    Ok(found)
}

/// The card's register BAR from the device's `resource` file; it must be I/O ports.
fn io_bar(dir: &Path, kind: CardKind) -> Result<(u64, u64), CardOpenError> {
    /// Linux's IORESOURCE_IO flag: the BAR is I/O ports, not memory.
    const IORESOURCE_IO: u64 = 0x100;
    let path = dir.join("resource");
    let text = std::fs::read_to_string(&path).map_err(|e| CardOpenError::ReadFile {
        error: e.kind(),
        path,
    })?;
    let line = text.lines().nth(kind.bar()).unwrap_or("");
    let fields: Vec<u64> = line
        .split_whitespace()
        .filter_map(|f| u64::from_str_radix(f.trim_start_matches("0x"), 16).ok())
        .collect();
    match fields[..] {
        [start, end, flags] if flags & IORESOURCE_IO != 0 && end >= start => Ok((start, end)),
        _ => Err(CardOpenError::NotIoBar {
            card: kind,
            dir: dir.to_path_buf(),
            line: line.to_string(),
        }),
    }
}

/// Find a card as robot.ini says (`location` must be a PCI one).
pub fn find(
    root: &Path,
    kind: CardKind,
    location: &CardLocation,
) -> Result<FoundCard, CardOpenError> {
    let address = match location {
        CardLocation::PciAddress(address) => {
            let dir = root.join(address);
            let address = address.clone();
            if !dir.exists() {
                return Err(CardOpenError::NoDeviceAt {
                    card: kind,
                    address,
                });
            }
            if read_hex(&dir.join("device")) != Some(u64::from(kind.device_id())) {
                return Err(CardOpenError::NotThisCard {
                    card: kind,
                    address,
                });
            }
            address
        }
        CardLocation::PciAuto => {
            let mut all = find_all(root, kind)?;
            match all.len() {
                1 => all.remove(0),
                0 => {
                    return Err(CardOpenError::NotOnBus {
                        card: kind,
                        root: root.to_path_buf(),
                    });
                }
                _ => {
                    return Err(CardOpenError::Several {
                        card: kind,
                        addresses: all,
                    });
                }
            }
        }
        CardLocation::PortBase(_) => return Err(CardOpenError::NotPci { card: kind }),
    };
    let dir = root.join(&address);
    let bar_ports = io_bar(&dir, kind)?;
    Ok(FoundCard {
        kind,
        address,
        dir,
        bar_ports,
    })
}

/// An open or access error as the card's problem, with advice a person can act on.
pub(crate) fn explain(kind: CardKind, path: &Path, e: &io::Error) -> CardOpenError {
    let path = path.to_path_buf();
    let refusal = match e.kind() {
        io::ErrorKind::ResourceBusy => return CardOpenError::InUse { card: kind, path },
        io::ErrorKind::PermissionDenied if kernel_locked_down() => Some(Refusal::Lockdown),
        io::ErrorKind::PermissionDenied if path.starts_with("/dev") => {
            Some(Refusal::DevPortCapability)
        }
        io::ErrorKind::PermissionDenied => Some(Refusal::UdevRule),
        _ => None,
    };
    CardOpenError::CannotUse {
        card: kind,
        path,
        error: e.kind(),
        refusal,
    }
}

/// Switch the device's I/O decoding on, unless it already is.
fn enable(card: &FoundCard) -> Result<(), CardOpenError> {
    let path = card.dir.join("enable");
    let on = std::fs::read_to_string(&path).is_ok_and(|t| t.trim() != "0");
    if on {
        return Ok(());
    }
    std::fs::write(&path, "1").map_err(|e| explain(card.kind, &path, &e))
}

/// Open a card's register window as robot.ini says: sysfs under `root`, or through
/// `dev_port` (the program's one handle of /dev/port, shared by its cards).
pub fn open(
    root: &Path,
    dev_port: &mut DevPortFile,
    kind: CardKind,
    location: &CardLocation,
) -> Result<OpenedCard, CardOpenError> {
    if let CardLocation::PortBase(base) = location {
        let port = dev_port
            .card(*base, kind.window_len())
            .map_err(|e| explain(kind, dev_port.path(), &e))?;
        return Ok(OpenedCard {
            port: Box::new(port),
            description: format!(
                "{} at I/O port {base:#06x} through {}",
                kind.name(),
                dev_port.path().display()
            ),
        });
    }
    let card = find(root, kind, location)?;
    enable(&card)?;
    let path = card.dir.join(format!("resource{}", kind.bar()));
    let (start, end) = card.bar_ports;
    if end - start + 1 < u64::from(kind.window_len()) {
        return Err(CardOpenError::BarTooSmall {
            card: kind,
            address: card.address,
            ports: end - start + 1,
        });
    }
    let port = SysfsBar::open(&path, kind.window_len()).map_err(|e| explain(kind, &path, &e))?;
    Ok(OpenedCard {
        port: Box::new(port),
        description: format!(
            "{} at PCI {}, BAR{} I/O ports {start:#06x}..{end:#06x}",
            kind.name(),
            card.address,
            kind.bar()
        ),
    })
}

#[cfg(test)]
#[path = "pci_tests.rs"]
pub(crate) mod tests;

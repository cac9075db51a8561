//! What goes wrong while the cards are found, opened and started, as values that name
//! the card, the file or PCI address, and the system's reason; each says what to do
//! about it (docs/function_spec.md section 4a).
//!
//! These happen once, before the robot can move, so they may hold paths and lists.
//! A card's problem is a [`CardOpenError`]; the cards together give an [`OpenError`],
//! which also says which cards got their safe outputs in spite of it.

use std::fmt;
use std::io::ErrorKind;
use std::path::PathBuf;

use crate::HwError;
use crate::cards::pci::{CardKind, VENDOR_MCC};
use crate::cards::port::kernel_locked_down;

/// Why the system refused a card's file or its ports, and so what to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// The kernel is in lockdown (secure boot): every I/O-port access is refused.
    Lockdown,
    /// /dev/port needs CAP_SYS_RAWIO and read-write access to the file.
    DevPortCapability,
    /// The sysfs files need the udev rule that gives them to the mechweed group.
    UdevRule,
    /// The file opened but the kernel refused the port access itself.
    PortAccess,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Refusal::Lockdown => {
                "The kernel is in lockdown (secure boot), which refuses all I/O-port access \
                 from programs: switch secure boot off in the firmware setup for this computer"
            }
            Refusal::DevPortCapability => {
                "/dev/port needs the capability CAP_SYS_RAWIO and read-write access to the \
                 file (docs/robot-pc.md), or run as root"
            }
            Refusal::UdevRule => {
                "Install the udev rule of docs/robot-pc.md (it gives the mechweed group the \
                 cards' files), or run as root"
            }
            Refusal::PortAccess => "The kernel refused the port access",
        })
    }
}

/// A card that was taken but did not answer while it was started (safe outputs
/// written, counters initialised); a refused access says why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StartError {
    pub error: HwError,
    pub refusal: Option<Refusal>,
}

impl StartError {
    /// A locked-down kernel lets a card's file open and refuses the first access: the
    /// reason is looked up here, once, not on every failing access.
    pub fn new(error: HwError) -> StartError {
        let refused = error.io_kind() == Some(ErrorKind::PermissionDenied);
        let refusal = refused.then(|| {
            if kernel_locked_down() {
                Refusal::Lockdown
            } else {
                Refusal::PortAccess
            }
        });
        StartError { error, refusal }
    }
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.error)?;
        match self.refusal {
            Some(refusal) => write!(f, ". {refusal}"),
            None => Ok(()),
        }
    }
}

impl std::error::Error for StartError {}

/// Why one card could not be found, opened or started.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CardOpenError {
    /// The directory of PCI devices could not be listed.
    ListPciDevices { root: PathBuf, error: ErrorKind },
    /// No card of this kind on the PCI bus.
    NotOnBus { card: CardKind, root: PathBuf },
    /// More than one card of this kind, and robot.ini does not say which.
    Several {
        card: CardKind,
        addresses: Vec<String>,
    },
    /// robot.ini's PCI address holds no device.
    NoDeviceAt { card: CardKind, address: String },
    /// robot.ini's PCI address holds another device.
    NotThisCard { card: CardKind, address: String },
    /// The card is set to /dev/port, so it is not looked for on the PCI bus.
    NotPci { card: CardKind },
    /// A file of the device's sysfs directory could not be read.
    ReadFile { path: PathBuf, error: ErrorKind },
    /// The card's register BAR is not I/O ports (`line` as the resource file gives it).
    NotIoBar {
        card: CardKind,
        dir: PathBuf,
        line: String,
    },
    /// The card's register BAR has fewer ports than the driver's registers.
    BarTooSmall {
        card: CardKind,
        address: String,
        ports: u64,
    },
    /// Another program holds the card's file.
    InUse { card: CardKind, path: PathBuf },
    /// The card's file could not be opened or written.
    CannotUse {
        card: CardKind,
        path: PathBuf,
        error: ErrorKind,
        refusal: Option<Refusal>,
    },
    /// The card was taken but did not answer while it got its safe outputs.
    NotAnswering(StartError),
}

/// The PCI id as `lspci -d` takes it: "1307:0029".
struct PciId(CardKind);

impl fmt::Display for PciId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{VENDOR_MCC:04x}:{:04x}", self.0.device_id())
    }
}

impl fmt::Display for CardOpenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CardOpenError::ListPciDevices { root, error } => {
                write!(
                    f,
                    "cannot list the PCI devices in {}: {error}",
                    root.display()
                )
            }
            CardOpenError::NotOnBus { card, root } => write!(
                f,
                "no {} (PCI id {}) found in {}: is the card in this computer?",
                card.name(),
                PciId(*card),
                root.display()
            ),
            CardOpenError::Several { card, addresses } => write!(
                f,
                "{} {} cards found ({}): set its PCI address in robot.ini [hw]",
                addresses.len(),
                card.name(),
                addresses.join(", ")
            ),
            CardOpenError::NoDeviceAt { card, address } => write!(
                f,
                "no PCI device at {address} (robot.ini [hw]): `lspci -D -d {}` lists the {}",
                PciId(*card),
                card.name()
            ),
            CardOpenError::NotThisCard { card, address } => write!(
                f,
                "the PCI device at {address} is not a {} ({}): check robot.ini [hw]",
                card.name(),
                PciId(*card)
            ),
            CardOpenError::NotPci { card } => {
                write!(f, "the {} is set to /dev/port, not PCI", card.name())
            }
            CardOpenError::ReadFile { path, error } => {
                write!(f, "cannot read {}: {error}", path.display())
            }
            CardOpenError::NotIoBar { card, dir, line } => write!(
                f,
                "BAR{} of the {} in {} is not an I/O-port BAR ('{line}'): is this the right card?",
                card.bar(),
                card.name(),
                dir.display()
            ),
            CardOpenError::BarTooSmall {
                card,
                address,
                ports,
            } => write!(
                f,
                "{}: BAR{} at {address} spans {ports} ports, fewer than its {} registers",
                card.name(),
                card.bar(),
                card.window_len()
            ),
            CardOpenError::InUse { card, path } => write!(
                f,
                "{}: cannot use {}: it is in use by another program (is mechweed already running?)",
                card.name(),
                path.display()
            ),
            CardOpenError::CannotUse {
                card,
                path,
                error,
                refusal,
            } => {
                write!(f, "{}: cannot use {}: {error}", card.name(), path.display())?;
                match refusal {
                    Some(refusal) => write!(f, ". {refusal}"),
                    None => Ok(()),
                }
            }
            CardOpenError::NotAnswering(start) => write!(f, "{start}"),
        }
    }
}

impl std::error::Error for CardOpenError {}

/// Why the robot's I/O cards cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OpenError {
    /// Cards that could not be found, opened or started, one problem a card; the cards
    /// named in `made_safe` opened and got their safe outputs all the same.
    #[error("{}", Lines { problems, made_safe })]
    Cards {
        problems: Vec<CardOpenError>,
        made_safe: Vec<&'static str>,
    },
    /// Every card was taken, but one did not answer while the cards were started.
    #[error("{0} (while starting the cards; the ones that answered have safe outputs)")]
    Starting(StartError),
}

/// Every card's problem on its own line, then which cards were made safe.
struct Lines<'a> {
    problems: &'a [CardOpenError],
    made_safe: &'a [&'static str],
}

impl fmt::Display for Lines<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, problem) in self.problems.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{problem}")?;
        }
        if !self.made_safe.is_empty() {
            write!(
                f,
                "\n(safe outputs written to the {}, which opened)",
                self.made_safe.join(" and the ")
            )?;
        }
        Ok(())
    }
}

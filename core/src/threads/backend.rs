//! Opening the hardware that robot.ini [hw] asks for. The simulated robot is built in
//! the program's src/run/robot.rs, as it comes with its camera computer and its
//! truth; here is the real one:
//! the three I/O cards, found on the PCI bus (or through /dev/port), started with safe
//! outputs, and joined by the wiring of [io]. If a card is missing, the others still
//! get their safe outputs before the run stops.

use std::path::Path;

use mechweed_hw::cards::wiring::Wiring;
use mechweed_hw::cards::{CardPorts, CardsHw, CardsSettings};
use mechweed_hw::{Hw, OpenError, StartError};

use crate::config::Settings;

/// Where Linux lists the PCI devices.
pub const PCI_DEVICES: &str = "/sys/bus/pci/devices";
/// Linux's file of every I/O port.
pub const DEV_PORT: &str = "/dev/port";

/// The robot's I/O cards as hardware, or why not (every card's problem, one per line).
pub fn open_hw(settings: &Settings) -> Result<Box<dyn Hw>, OpenError> {
    let (hw, found) = open_cards(settings, Path::new(PCI_DEVICES), Path::new(DEV_PORT))?;
    for line in found {
        tracing::info!("{line}");
    }
    Ok(Box::new(hw))
}

/// Find, open and start the cards; also says where each one was found.
pub fn open_cards(
    settings: &Settings,
    pci_root: &Path,
    dev_port: &Path,
) -> Result<(CardsHw, [String; 3]), OpenError> {
    open_cards_as(&settings.cards, &settings.io, pci_root, dev_port)
}

/// The same from [hw] and [io] alone (config/cards_only.rs): all that the safe
/// outputs need. Opening writes them; a card that is missing leaves the others safe.
pub fn open_cards_as(
    cards: &CardsSettings,
    io: &Wiring,
    pci_root: &Path,
    dev_port: &Path,
) -> Result<(CardsHw, [String; 3]), OpenError> {
    let ports = CardPorts::open(cards, io, pci_root, dev_port)?;
    let found = ports.descriptions.clone();
    let hw =
        CardsHw::open(ports, cards, io).map_err(|e| OpenError::Starting(StartError::new(e)))?;
    Ok((hw, found))
}

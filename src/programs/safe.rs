//! `mechweed safe [--config FILE]`: open the I/O cards and write the safe outputs
//! (amplifiers 0 V, motor contactor relay open, brakes on, tool off, watchdog line
//! stopped), nothing else. It reads only robot.ini's [hw] and [io], whatever the other
//! sections say, and says which card it could not reach.
//!
//! A killed run (SIGKILL, a crash) leaves the cards as they were: contactor closed,
//! brakes released, amplifiers driven. The service runs this when the controller stops
//! or fails (ExecStopPost=), and a person runs it after a killed run. A `run` or
//! `probe` that refuses robot.ini calls `after_refusal` for the same reason.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::config::{Backend, CardsOnly, ConfigError, DEFAULT_INI};
use mechweed_hw::OpenError;
use mechweed_hw::cards::{CardPorts, CardsHw};

use crate::programs::{print_errors, settings_file};
use crate::threads::backend::{DEV_PORT, PCI_DEVICES};

#[derive(clap::Args)]
pub struct SafeArgs {
    /// Settings file: only [hw] and [io] are read [default: config/robot.ini, or the built-in copy]
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// What the safe outputs are, for the lines that say they were written.
const SAFE: &str =
    "amplifiers 0 V, motor contactor relay open, brakes on, tool off, watchdog line stopped";

/// `mechweed safe`: exit 0 once all three cards have their safe outputs, 1 otherwise.
pub fn program(args: SafeArgs) -> ExitCode {
    let only = match cards_only(args.config.as_deref()) {
        Ok(only) => only,
        Err(errors) => {
            print_errors(&errors);
            eprintln!("no safe outputs written: [hw] or [io] is wrong (above)");
            return ExitCode::FAILURE;
        }
    };
    match write_safe(open_ports(&only), &only) {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

/// [hw] and [io] of the settings file: the one named, else config/robot.ini here, else
/// the built-in copy.
pub(crate) fn cards_only(file: Option<&Path>) -> Result<CardsOnly, Vec<ConfigError>> {
    match settings_file(file) {
        Some(path) => CardsOnly::load(&path),
        None => CardsOnly::parse("built-in robot.ini", DEFAULT_INI),
    }
}

/// The cards of this computer, found as [hw] says.
fn open_ports(only: &CardsOnly) -> Result<CardPorts, OpenError> {
    let (pci_root, dev_port) = (Path::new(PCI_DEVICES), Path::new(DEV_PORT));
    CardPorts::open(&only.cards, &only.io, pci_root, dev_port)
}

/// Start the cards that `ports` opened: starting writes their safe outputs, and a card
/// that did not open has left the others safe (the message says which).
pub(crate) fn write_safe(
    ports: Result<CardPorts, OpenError>,
    only: &CardsOnly,
) -> Result<String, String> {
    let ports = ports.map_err(|e| format!("{e}"))?;
    let found = ports.descriptions.join("; ");
    let hw = CardsHw::open(ports, &only.cards, &only.io)
        .map_err(|e| format!("the safe outputs could not be written: {e}"))?;
    // Dropping the cards writes the safe outputs once more, as every exit does.
    drop(hw);
    Ok(format!("safe outputs written ({SAFE}) on {found}"))
}

/// A `run` or `probe` that refuses the settings file `file` (already said why): its
/// [hw] and [io], where they themselves are valid, still get the cards' safe outputs,
/// so that a robot a killed run left driving stops. `run` asks only for
/// `[hw] backend = cards` (`cards_only`): a simulated robot has no cards to stop.
pub(crate) fn after_refusal(file: Option<&Path>, only_with_cards: bool) {
    let Ok(only) = cards_only(file) else {
        // The errors printed name [hw] and [io] too; a run does not know that it was
        // meant for the cards.
        if !only_with_cards {
            eprintln!("[hw] or [io] is wrong too: no safe outputs written");
        }
        return;
    };
    if only_with_cards && only.backend != Backend::Cards {
        return;
    }
    match write_safe(open_ports(&only), &only) {
        Ok(line) => eprintln!("{line}, although the settings are refused"),
        Err(why) => eprintln!("{why}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::cards::port::PortIo;
    use mechweed_hw::emulated::{EmulatedDas08, EmulatedDda06, EmulatedQuad04};

    #[test]
    fn writes_the_safe_outputs_on_emulated_cards_from_a_file_broken_outside_hw_and_io() {
        // The unsafe state a killed run leaves: every output on, amplifiers driven.
        let broken = DEFAULT_INI.replace("[pid.left]", "[pid.left]\nkp_typo = 3");
        let only = CardsOnly::parse("robot.ini", &broken).unwrap();
        // The DAS08 powers up with every output on; the killed run drove AO0 to +10 V.
        let das08 = EmulatedDas08::new();
        let mut dda06 = EmulatedDda06::new(only.cards.dda06_ranges);
        let quad04 = EmulatedQuad04::new();
        dda06.write_u8(0, 0xFF).unwrap();
        dda06.write_u8(1, 0xFF).unwrap();
        assert!(das08.output(1) && dda06.dac_code(0) == 0xFFFF);
        let ports = CardPorts {
            das08: Box::new(das08.clone()),
            dda06: Box::new(dda06.clone()),
            quad04: Box::new(quad04),
            descriptions: ["DAS08 here", "DDA06 here", "QUAD04 here"].map(String::from),
        };
        let line = write_safe(Ok(ports), &only).unwrap();
        assert!(line.starts_with("safe outputs written"), "{line}");
        assert!(
            (1..=4).all(|n| !das08.output(n)),
            "relay, brakes and tool off"
        );
        assert!(
            (0..3).all(|n| dda06.dac_code(n) == 0x8000),
            "amplifiers 0 V"
        );
    }
}

//! The robot's three I/O cards behind the [`Hw`] trait ("I/O cards"): the drivers of
//! each card, joined by the wiring of robot.ini [io].
//!
//! Safety first. At open, before anything else, every card that has outputs gets its
//! safe state (every DAC at 0 V, relay open, brakes on, tool off, watchdog stopped),
//! and only then are the counters initialised. A card that is missing or does not
//! answer is an error at open, never a half-started robot; and the cards that did open
//! get their safe outputs before that error is reported, because a run that was killed
//! left them as they were (contactor closed, brakes released, amplifiers driven). A
//! write that fails on one card writes the safe outputs to every card before it
//! returns the error, and so does dropping `CardsHw`. The watchdog output (watchdog.rs)
//! changes on every write while every card answers.
//! `read` and `write` do no heap allocation, not even when a card fails: the error
//! names the card and the register in numbers (error.rs).

pub mod das08;
pub mod dda06;
pub mod open_error;
pub mod pci;
pub mod port;
pub mod quad04;
pub mod watchdog;
pub mod wiring;

use std::path::Path;
use std::time::Duration;

use crate::cards::port::{DevPortFile, PortIo};
use crate::cards::quad04::Quad04;
use crate::cards::watchdog::Watchdog;
use crate::cards::wiring::{CardInputs, CardOutputs, Wiring};
use crate::{CardOpenError, Hw, HwError, Inputs, OpenError, Outputs, StartError};
use das08::Das08;
use dda06::{DACS, DacRange, Dda06};
use pci::{CardKind, CardLocation, OpenedCard};

/// The name of this hardware in messages.
pub const NAME: &str = "I/O cards";

/// The cards' settings other than the wiring (robot.ini [hw]).
#[derive(Debug, Clone, PartialEq)]
pub struct CardsSettings {
    pub das08: CardLocation,
    pub dda06: CardLocation,
    pub quad04: CardLocation,
    /// The range switch of each DDA06 output, AO0..AO5.
    pub dda06_ranges: [DacRange; DACS],
    /// Longest wait for a DAS08 conversion, us.
    pub das08_eoc_timeout_us: f64,
}

impl CardsSettings {
    pub fn location(&self, kind: CardKind) -> &CardLocation {
        match kind {
            CardKind::Das08 => &self.das08,
            CardKind::Dda06 => &self.dda06,
            CardKind::Quad04 => &self.quad04,
        }
    }

    fn das08_eoc_timeout(&self) -> Duration {
        Duration::from_secs_f64(self.das08_eoc_timeout_us.max(0.0) * 1e-6)
    }
}

/// The safe outputs in card values, the watchdog line stopped.
fn safe_outputs(wiring: &Wiring) -> CardOutputs {
    let mut safe = wiring.card_outputs(&Outputs::SAFE);
    Watchdog::new(wiring.watchdog).hold(&mut safe);
    safe
}

/// Take the DAS08: its safe outputs first, then whether it answers.
fn open_das08(
    port: Box<dyn PortIo>,
    settings: &CardsSettings,
    safe: &CardOutputs,
) -> Result<Das08, HwError> {
    Das08::open(port, safe.das08_op, settings.das08_eoc_timeout())
}

/// Take the DDA06: every DAC at 0 V, then the 8255 with its safe outputs.
fn open_dda06(
    port: Box<dyn PortIo>,
    settings: &CardsSettings,
    wiring: &Wiring,
    safe: &CardOutputs,
) -> Result<Dda06, HwError> {
    let directions = wiring.dda06_directions();
    Dda06::open(port, settings.dda06_ranges, directions, safe.dda06_ports)
}

/// The three cards' register windows, however they were reached.
pub struct CardPorts {
    pub das08: Box<dyn PortIo>,
    pub dda06: Box<dyn PortIo>,
    pub quad04: Box<dyn PortIo>,
    /// Where each card was found, one line each (DAS08, DDA06, QUAD04).
    pub descriptions: [String; 3],
}

impl CardPorts {
    /// Find and open all three cards as robot.ini says: through sysfs under `pci_root`
    /// (normally /sys/bus/pci/devices) or through `dev_port` (opened once for all the
    /// cards that use it). If one cannot be opened, see [`CardPorts::all_or_safe`].
    pub fn open(
        settings: &CardsSettings,
        wiring: &Wiring,
        pci_root: &Path,
        dev_port: &Path,
    ) -> Result<CardPorts, OpenError> {
        let mut dev_port = DevPortFile::new(dev_port);
        let found = CardKind::ALL
            .map(|kind| pci::open(pci_root, &mut dev_port, kind, settings.location(kind)));
        CardPorts::all_or_safe(found, settings, wiring)
    }

    /// The three cards (DAS08, DDA06, QUAD04) if all of them opened. Otherwise the
    /// DAS08 and the DDA06, whichever opened, get their safe outputs now, and the error
    /// gives every card's problem, then which cards were made safe.
    pub(crate) fn all_or_safe(
        found: [Result<OpenedCard, CardOpenError>; 3],
        settings: &CardsSettings,
        wiring: &Wiring,
    ) -> Result<CardPorts, OpenError> {
        let (das08, dda06, quad04) = match found {
            [Ok(das08), Ok(dda06), Ok(quad04)] => {
                return Ok(CardPorts {
                    descriptions: [das08.description, dda06.description, quad04.description],
                    das08: das08.port,
                    dda06: dda06.port,
                    quad04: quad04.port,
                });
            }
            [das08, dda06, quad04] => (das08, dda06, quad04),
        };
        let mut problems: Vec<CardOpenError> = [&das08, &dda06, &quad04]
            .into_iter()
            .filter_map(|card| card.as_ref().err().cloned())
            .collect();
        let safe = safe_outputs(wiring);
        let mut made_safe = Vec::new();
        if let Ok(card) = das08 {
            match open_das08(card.port, settings, &safe) {
                Ok(_) => made_safe.push(das08::NAME),
                Err(e) => problems.push(CardOpenError::NotAnswering(StartError::new(e))),
            }
        }
        if let Ok(card) = dda06 {
            match open_dda06(card.port, settings, wiring, &safe) {
                Ok(_) => made_safe.push(dda06::NAME),
                Err(e) => problems.push(CardOpenError::NotAnswering(StartError::new(e))),
            }
        }
        Err(OpenError::Cards {
            problems,
            made_safe,
        })
    }
}

pub struct CardsHw {
    das08: Das08,
    dda06: Dda06,
    quad04: Quad04,
    wiring: Wiring,
    /// What the safe outputs are on the cards, through the wiring.
    safe: CardOutputs,
    /// 8255 ports to read (switch inputs) and to write (switched outputs).
    dda06_reads: [bool; 3],
    dda06_writes: [bool; 3],
    reads_das08_inputs: bool,
    watchdog: Watchdog,
    /// The last read and write found every card answering; else the watchdog holds.
    answering: bool,
    /// The last read found motor power present.
    power_present: bool,
}

/// The first error of several attempts, so that every attempt is made.
fn first_error(results: [Result<(), HwError>; 3]) -> Result<(), HwError> {
    results.into_iter().find(Result::is_err).unwrap_or(Ok(()))
}

impl CardsHw {
    /// Take the cards: safe outputs on the DAS08 and the DDA06 first (both are tried,
    /// whichever fails), then the QUAD04's counters are initialised.
    pub fn open(
        ports: CardPorts,
        settings: &CardsSettings,
        wiring: &Wiring,
    ) -> Result<CardsHw, HwError> {
        let safe = safe_outputs(wiring);
        let das08 = open_das08(ports.das08, settings, &safe);
        let dda06 = open_dda06(ports.dda06, settings, wiring, &safe);
        let (das08, dda06) = (das08?, dda06?);
        let quad04 = Quad04::open(ports.quad04)?;
        Ok(CardsHw {
            das08,
            dda06,
            quad04,
            wiring: *wiring,
            safe,
            dda06_reads: wiring.dda06_input_ports(),
            dda06_writes: wiring.dda06_directions().output_bits.map(|bits| bits != 0),
            reads_das08_inputs: wiring.reads_das08_inputs(),
            watchdog: Watchdog::new(wiring.watchdog),
            answering: true,
            power_present: false,
        })
    }

    /// Every card's raw values for the wired inputs.
    pub(crate) fn read_cards(&mut self) -> Result<CardInputs, HwError> {
        let mut c = CardInputs::default();
        for a in self.wiring.analog_inputs() {
            c.das08_ai_v[usize::from(a.channel % 8)] = self.das08.read_volts(a.channel)?;
        }
        if self.reads_das08_inputs {
            c.das08_ip = self.das08.read_inputs()?;
        }
        for p in 0..3 {
            if self.dda06_reads[p] {
                c.dda06_ports[p] = self.dda06.read_port(p)?;
            }
        }
        for e in self.wiring.encoders() {
            let i = usize::from(e.channel.clamp(1, 4) - 1);
            c.quad04_counts[i] = self.quad04.read_counts(usize::from(e.channel))?;
        }
        Ok(c)
    }

    /// Card values out: the DAS08's outputs, the wired DACs, the 8255's output ports.
    fn write_cards(&mut self, c: &CardOutputs) -> Result<(), HwError> {
        self.das08.write_outputs(c.das08_op)?;
        for a in self.wiring.analog_outputs() {
            let n = usize::from(a.channel % 6);
            self.dda06.write_volts(n, c.dda06_ao_v[n])?;
        }
        for p in 0..3 {
            if self.dda06_writes[p] {
                self.dda06.write_port(p, c.dda06_ports[p])?;
            }
        }
        Ok(())
    }

    /// The safe outputs on every card, each tried even if another fails: every DAC at
    /// 0 V (wired or not), switched outputs off, the watchdog stopped.
    pub(crate) fn write_safe(&mut self) -> Result<(), HwError> {
        self.watchdog.hold(&mut self.safe);
        let das08 = self.das08.write_outputs(self.safe.das08_op);
        let dacs = self.dda06.write_all_zero();
        let mut ports = Ok(());
        for p in 0..3 {
            if self.dda06_writes[p] {
                ports = ports.and(self.dda06.write_port(p, self.safe.dda06_ports[p]));
            }
        }
        first_error([das08, dacs, ports])
    }

    /// The drivers, for `mechweed probe --raw`.
    pub fn drivers(&mut self) -> (&mut Das08, &mut Dda06, &mut Quad04) {
        (&mut self.das08, &mut self.dda06, &mut self.quad04)
    }

    pub fn wiring(&self) -> &Wiring {
        &self.wiring
    }
}

impl Hw for CardsHw {
    fn read(&mut self) -> Result<Inputs, HwError> {
        let cards = self.read_cards();
        // A card that stopped answering may still hold its last outputs: only the
        // watchdog relay can then cut the motor power, so it holds until all answer.
        self.answering = cards.is_ok();
        let inputs = self.wiring.inputs(&cards?);
        self.power_present = inputs.motor_power_present;
        Ok(inputs)
    }

    /// Called once per supervisor tick: the watchdog changes with every write, but for
    /// while motor power is present with the relay commanded open (a welded contactor,
    /// a stuck relay driver): then the watchdog relay is the one channel left that can
    /// cut the contactor's coil, and it holds until the power is gone.
    fn write(&mut self, outputs: &Outputs) -> Result<(), HwError> {
        let mut cards = self.wiring.card_outputs(outputs);
        let power_unasked = self.power_present && !outputs.main_power_on;
        if self.answering && !power_unasked {
            self.watchdog.toggle(&mut cards);
        } else {
            self.watchdog.hold(&mut cards);
        }
        let result = self.write_cards(&cards);
        if result.is_err() {
            self.answering = false;
            // Whatever answers gets the safe outputs now, not a tick later.
            let _ = self.write_safe();
        }
        result
    }

    fn name(&self) -> &'static str {
        NAME
    }
}

impl Drop for CardsHw {
    fn drop(&mut self) {
        let _ = self.write_safe();
    }
}

#[cfg(test)]
#[path = "cards_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "cards_open_tests.rs"]
mod open_tests;

#[cfg(test)]
#[path = "cards_watchdog_tests.rs"]
mod watchdog_tests;

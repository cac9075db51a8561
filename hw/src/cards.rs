//! The robot's three I/O cards behind the [`Hw`] trait ("I/O cards"): the drivers of
//! each card, joined by the wiring of robot.ini [io].
//!
//! Safety first. At open, before anything else, every card that has outputs gets its
//! safe state (every DAC at 0 V, relay open, brakes on, tool off), and only then are
//! the counters initialised; a card that is missing or does not answer is an error at
//! open, never a half-started robot. A write that fails on one card writes the safe
//! outputs to every card before it returns the error, and so does dropping `CardsHw`.
//! `read` and `write` do no heap allocation (only an error message allocates).

use std::path::Path;
use std::time::Duration;

use crate::das08::Das08;
use crate::dda06::{DACS, DacRange, Dda06};
use crate::pci::{self, CardKind, CardLocation};
use crate::port::PortIo;
use crate::quad04::Quad04;
use crate::wiring::{CardInputs, CardOutputs, Wiring};
use crate::{Hw, HwError, Inputs, Outputs};

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
    /// (normally /sys/bus/pci/devices) or through `dev_port`. Every card's problem is
    /// reported, not just the first.
    pub fn open(
        settings: &CardsSettings,
        pci_root: &Path,
        dev_port: &Path,
    ) -> Result<CardPorts, String> {
        let [das08, dda06, quad04] =
            CardKind::ALL.map(|kind| pci::open(pci_root, dev_port, kind, settings.location(kind)));
        match (das08, dda06, quad04) {
            (Ok(das08), Ok(dda06), Ok(quad04)) => Ok(CardPorts {
                descriptions: [das08.description, dda06.description, quad04.description],
                das08: das08.port,
                dda06: dda06.port,
                quad04: quad04.port,
            }),
            (das08, dda06, quad04) => {
                let errors: Vec<String> = [das08.err(), dda06.err(), quad04.err()]
                    .into_iter()
                    .flatten()
                    .collect();
                Err(errors.join("\n"))
            }
        }
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
        let safe = wiring.card_outputs(&Outputs::SAFE);
        let timeout = Duration::from_secs_f64(settings.das08_eoc_timeout_us.max(0.0) * 1e-6);
        let directions = wiring.dda06_directions();
        let das08 = Das08::open(ports.das08, safe.das08_op, timeout);
        let dda06 = Dda06::open(
            ports.dda06,
            settings.dda06_ranges,
            directions,
            safe.dda06_ports,
        );
        let (das08, dda06) = (das08?, dda06?);
        let quad04 = Quad04::open(ports.quad04)?;
        Ok(CardsHw {
            das08,
            dda06,
            quad04,
            wiring: *wiring,
            safe,
            dda06_reads: wiring.dda06_input_ports(),
            dda06_writes: directions.output_bits.map(|bits| bits != 0),
            reads_das08_inputs: wiring.reads_das08_inputs(),
        })
    }

    /// Every card's raw values for the wired inputs.
    pub fn read_cards(&mut self) -> Result<CardInputs, HwError> {
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
    /// 0 V (wired or not), switched outputs off.
    pub fn write_safe(&mut self) -> Result<(), HwError> {
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
        let cards = self.read_cards()?;
        Ok(self.wiring.inputs(&cards))
    }

    fn write(&mut self, outputs: &Outputs) -> Result<(), HwError> {
        let cards = self.wiring.card_outputs(outputs);
        let result = self.write_cards(&cards);
        if result.is_err() {
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

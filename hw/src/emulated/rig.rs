//! The three emulated cards wired to a robot, with the real [`CardsHw`] over them: the
//! whole path from the robot's signals to `Inputs` and from `Outputs` back, except
//! the wires. A simulated plant (or a test) puts its sensor signals on the wires with
//! [`CardRig::set_wires`] and takes what the cards drive with [`CardRig::plant_outputs`].

use super::{EmulatedDas08, EmulatedDda06, EmulatedQuad04};
use crate::cards::dda06::{DACS, DacRange};
use crate::cards::port::{AccessCount, CountingPort, PortIo};
use crate::cards::wiring::{CardOutputs, Wiring};
use crate::cards::{CardPorts, CardsHw, CardsSettings};
use crate::{HwError, Inputs, Outputs};

pub struct CardRig {
    pub das08: EmulatedDas08,
    pub dda06: EmulatedDda06,
    pub quad04: EmulatedQuad04,
    /// The real driver stack over the emulated cards.
    pub hw: CardsHw,
    wiring: Wiring,
    /// The DDA06's range switches as robot.ini says they are set.
    ranges_in_ini: [DacRange; DACS],
}

impl CardRig {
    /// Emulated cards just powered up, with the DDA06's range switches as `settings`
    /// says, wired as `wiring`, opened by `CardsHw`.
    pub fn new(settings: &CardsSettings, wiring: &Wiring) -> Result<CardRig, HwError> {
        CardRig::build(settings, wiring, None)
    }

    /// The same, counting every port access into `count`.
    pub fn counting(
        settings: &CardsSettings,
        wiring: &Wiring,
        count: &AccessCount,
    ) -> Result<CardRig, HwError> {
        CardRig::build(settings, wiring, Some(count))
    }

    fn build(
        settings: &CardsSettings,
        wiring: &Wiring,
        count: Option<&AccessCount>,
    ) -> Result<CardRig, HwError> {
        let das08 = EmulatedDas08::new();
        let dda06 = EmulatedDda06::new(settings.dda06_ranges);
        let quad04 = EmulatedQuad04::new();
        let wrap = |port: Box<dyn PortIo>| -> Box<dyn PortIo> {
            match count {
                Some(count) => Box::new(CountingPort::new(port, count.clone())),
                None => port,
            }
        };
        let ports = CardPorts {
            das08: wrap(Box::new(das08.clone())),
            dda06: wrap(Box::new(dda06.clone())),
            quad04: wrap(Box::new(quad04.clone())),
            descriptions: [
                "emulated PCI-DAS08",
                "emulated PCIM-DDA06/16",
                "emulated PCI-QUAD04",
            ]
            .map(String::from),
        };
        let hw = CardsHw::open(ports, settings, wiring)?;
        Ok(CardRig {
            das08,
            dda06,
            quad04,
            hw,
            wiring: *wiring,
            ranges_in_ini: settings.dda06_ranges,
        })
    }

    /// Someone sets the amplifiers' range switches (AO0..AO2) at the unipolar range of
    /// the full scale robot.ini gives (`unipolar`), or back as robot.ini says.
    pub fn set_amplifier_switches_unipolar(&self, unipolar: bool) {
        for n in 0..3 {
            let range = self.ranges_in_ini[n];
            let switch = if unipolar { range.unipolar() } else { range };
            self.dda06.set_range_switch(n, switch);
        }
    }

    /// The robot's sensor signals onto the cards' wires.
    pub fn set_wires(&self, inputs: &Inputs) {
        let c = self.wiring.wires_for(inputs);
        for (channel, &volts) in c.das08_ai_v.iter().enumerate() {
            self.das08.set_ai_volts(channel, volts);
        }
        for n in 1..=3 {
            self.das08.set_input(n, c.das08_ip >> (n - 1) & 1 != 0);
        }
        for (port, &levels) in c.dda06_ports.iter().enumerate() {
            for bit in 0..8 {
                self.dda06.set_pin(port, bit, levels >> bit & 1 != 0);
            }
        }
        for (i, &counts) in c.quad04_counts.iter().enumerate() {
            self.quad04.set_encoder_edges(i + 1, counts);
        }
    }

    /// What the cards drive now, as the robot's outputs.
    pub fn plant_outputs(&self) -> Outputs {
        let mut c = CardOutputs::default();
        for (n, volts) in c.dda06_ao_v.iter_mut().enumerate() {
            *volts = self.dda06.dac_volts(n);
        }
        for n in 1..=4 {
            if self.das08.output(n) {
                c.das08_op |= 1 << (n - 1);
            }
        }
        for (port, levels) in c.dda06_ports.iter_mut().enumerate() {
            for bit in 0..8 {
                if self.dda06.pin(port, bit) {
                    *levels |= 1 << bit;
                }
            }
        }
        self.wiring.outputs_from(&c)
    }
}

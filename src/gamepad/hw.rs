//! The robot's hardware with the gamepad in place of the wired joystick: every input as
//! the cards (or the simulated robot) read it, but the joystick's axes and dead-man from
//! the pad, judged at this very read, so that a pad gone silent stops the robot even if
//! the gamepad thread has stopped publishing.

use std::time::Instant;

use mechweed_hw::{Hw, HwError, Inputs, Outputs};

use super::{DeadMan, PadState};
use crate::state::{Latest, Reader};

pub struct PadHw {
    inner: Box<dyn Hw>,
    pad: Latest<PadState>,
    /// This read judged the pad silent: the dead-man stays released here until the pad
    /// shows it released, even if the thread then publishes an event it took just
    /// before the silence was judged.
    silent_seen: bool,
    /// Reads that found the gamepad's object locked and used the copy from last time.
    pub busy: u64,
}

impl PadHw {
    pub fn new(inner: Box<dyn Hw>, pad: Reader<PadState>) -> PadHw {
        PadHw {
            inner,
            pad: Latest::new(pad),
            silent_seen: false,
            busy: 0,
        }
    }
}

impl Hw for PadHw {
    fn read(&mut self) -> Result<Inputs, HwError> {
        let mut inputs = self.inner.read()?;
        // Never waits for the gamepad thread (it runs at normal priority).
        let pad = self.pad.get(&mut self.busy).pad;
        let joystick = pad.joystick(Instant::now());
        self.silent_seen |= matches!(joystick.dead_man, DeadMan::Silent(_));
        self.silent_seen &= pad.deadman_down();
        inputs.joystick_steer_v = joystick.steer_v;
        inputs.joystick_speed_v = joystick.speed_v;
        inputs.joystick_enable = joystick.enable && !self.silent_seen;
        Ok(inputs)
    }

    fn write(&mut self, outputs: &Outputs) -> Result<(), HwError> {
        self.inner.write(outputs)
    }

    fn name(&self) -> &'static str {
        self.inner.name()
    }
}

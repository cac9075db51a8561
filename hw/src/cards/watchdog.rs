//! The watchdog output (robot.ini `[io] watchdog`): a square wave for an external
//! charge-pump relay in the e-stop chain, which holds motor power only while the line
//! keeps changing.
//!
//! The cards keep whatever was last written to them, so a program that is killed or
//! hangs leaves the contactor closed and the amplifiers driven. The watchdog covers
//! that: the cards' backend changes the line on every write of the outputs (once per
//! supervisor tick, so half the supervisor rate: 50 Hz at 100 Hz, in Fault too: the
//! line says the program is alive, not that the robot may move), and holds it at its
//! inactive level at start, at exit, after a write that failed and while a card does
//! not answer. A dead or hung program stops changing it by itself. docs/robot-pc.md
//! says how to wire the relay.

use crate::cards::wiring::{CardOutputs, Switch};

pub(crate) struct Watchdog {
    /// The line, or None when robot.ini says `watchdog = none`.
    line: Option<Switch>,
    /// The level of the last half-period: true = active.
    active: bool,
}

impl Watchdog {
    /// Stopped, at the inactive level.
    pub fn new(line: Option<Switch>) -> Watchdog {
        Watchdog {
            line,
            active: false,
        }
    }

    /// The next half-period: the line to its other level in `c`.
    pub(crate) fn toggle(&mut self, c: &mut CardOutputs) {
        if let Some(line) = self.line {
            self.active = !self.active;
            c.set_line(line.bit, line.level(self.active));
        }
    }

    /// Stopped: the line at its inactive level in `c`, so the relay drops; the next
    /// toggle starts again from there.
    pub fn hold(&mut self, c: &mut CardOutputs) {
        self.active = false;
        if let Some(line) = self.line {
            c.set_line(line.bit, line.level(false));
        }
    }
}

//! The scripted operator: what a person at the GUI would do, from the command line's
//! `--mode` and the operator actions of [sim] events (power_up, mode MODE). Both the
//! real-time run and the lockstep simulation ask it, every tick, what to request.

use mechweed_hw::sim::{EventAction, OperatorMode, SimEvent};

use crate::faults::PowerState;
use crate::modes::{Mode, Request};
use crate::supervisor::Status;

pub struct OperatorScript {
    events: Vec<SimEvent>,
    next: usize,
    /// The mode asked for at start, pursued until reached or a fault intervenes.
    goal: Option<Mode>,
}

pub fn mode_of(m: OperatorMode) -> Mode {
    match m {
        OperatorMode::Halt => Mode::Halt,
        OperatorMode::Joystick => Mode::Joystick,
        OperatorMode::Autonomous => Mode::Autonomous,
        OperatorMode::Test => Mode::Test,
    }
}

impl OperatorScript {
    pub fn new(events: &[SimEvent], start_mode: Mode) -> OperatorScript {
        OperatorScript {
            events: events
                .iter()
                .copied()
                .filter(|e| e.action.is_operator())
                .collect(),
            next: 0,
            goal: (start_mode != Mode::Halt).then_some(start_mode),
        }
    }

    /// The request to send now, if any.
    pub fn due(&mut self, now_s: f64, status: &Status) -> Option<Request> {
        if status.tick == 0 {
            return None; // nothing is known about the robot before the supervisor's first tick
        }
        if let Some(event) = self.events.get(self.next)
            && event.t_s <= now_s
        {
            self.next += 1;
            return match event.action {
                EventAction::PowerUp => Some(Request::PowerUp),
                EventAction::Mode(m) => Some(Request::Mode(mode_of(m))),
                _ => None,
            };
        }
        let goal = self.goal?;
        match status.mode {
            m if m == goal => {
                self.goal = None;
                None
            }
            Mode::Fault => {
                self.goal = None;
                None
            }
            _ if status.power == PowerState::Off => Some(Request::PowerUp),
            _ if status.power == PowerState::On && status.measured.calibrated => {
                Some(Request::Mode(goal))
            }
            _ => None,
        }
    }
}

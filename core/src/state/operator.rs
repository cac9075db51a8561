//! The scripted operator: what a person at the GUI would do, from the command line's
//! `--mode` and the operator actions of [sim] events (power_up, mode MODE). Both the
//! real-time run and the lockstep simulation ask it, every tick, what to request.

use std::io::{BufRead, Write};

use mechweed_hw::sim::{EventAction, OperatorMode, SimEvent, action_list};

use crate::config::Backend;
use crate::state::modes::{Mode, Request};
use crate::state::status::PowerState;
use crate::state::status::Status;

pub struct OperatorScript {
    events: Vec<SimEvent>,
    next: usize,
    /// The mode asked for at start, pursued until reached or a fault intervenes.
    goal: Option<Mode>,
    /// The goal was asked for once while a sensor it needs was down: its refusal said
    /// why, and it is asked again only once the sensor is back, not in every tick.
    asked_while_down: bool,
}

pub(crate) fn mode_of(m: OperatorMode) -> Mode {
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
            asked_while_down: false,
        }
    }

    /// When the next operator action of `[sim] events` is due, s (None: none left). The
    /// start mode needs no time of its own: the script asks for it when the status
    /// changes (power on, calibrated).
    pub fn next_action_s(&self) -> Option<f64> {
        self.events.get(self.next).map(|e| e.t_s)
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
                let down = goal == Mode::Autonomous && status.sensor_down.is_some();
                if down && self.asked_while_down {
                    return None;
                }
                self.asked_while_down = down;
                Some(Request::Mode(goal))
            }
            _ => None,
        }
    }
}

/// `mechweed run --list-events`: every action of [sim] events with its argument and an
/// example, from the parser's own list.
pub fn events_help() -> String {
    use std::fmt::Write;
    let mut out = String::from(
        "[sim] events: a comma-separated list of TIME_S ACTION [ARGUMENT], times in seconds from the start,\n\
         e.g. --set \"sim.events=4 estop_front, 6 estop_release, 7 power_up, 8 mode autonomous\"\n\
         (operator actions, power_up and mode, only on the simulated robot)\n\n",
    );
    for help in action_list() {
        let argument = help.argument.as_deref().unwrap_or("no argument");
        let _ = writeln!(
            out,
            "{:<17} {:<35} {}\n{:<17} example: {}",
            help.name, argument, help.what, "", help.example
        );
    }
    out
}

/// On the real robot nobody is assumed to stand by: a start mode other than Halt powers
/// the robot up and may drive it, so it waits for a person's yes.
pub fn needs_confirmation(backend: Backend, start_mode: Mode) -> bool {
    backend == Backend::Cards && start_mode != Mode::Halt
}

/// Ask at the console whether to power up the real robot and enter `mode`; only the
/// answer "yes" confirms (end of input, as with no terminal, is a no).
pub fn confirm_on_console(mode: Mode, input: &mut impl BufRead, out: &mut impl Write) -> bool {
    let _ = write!(
        out,
        "--mode {mode} will power up the REAL robot{}. Is the area clear and a person at an \
         emergency stop? Type yes and Enter to go on (anything else starts in halt): ",
        if mode.drives() { " and drive it" } else { "" }
    );
    let _ = out.flush();
    let mut answer = String::new();
    let confirmed = input.read_line(&mut answer).is_ok() && answer.trim() == "yes";
    if !confirmed {
        let _ = writeln!(out, "\nnot confirmed: starting in halt");
    }
    confirmed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_cards_backend_and_a_moving_start_ask() {
        assert!(needs_confirmation(Backend::Cards, Mode::Autonomous));
        assert!(needs_confirmation(Backend::Cards, Mode::Joystick));
        assert!(needs_confirmation(Backend::Cards, Mode::Test));
        assert!(!needs_confirmation(Backend::Cards, Mode::Halt));
        assert!(!needs_confirmation(Backend::Sim, Mode::Autonomous));
    }

    #[test]
    fn only_yes_confirms() {
        for (typed, confirmed) in [
            ("yes\n", true),
            ("y\n", false),
            ("", false),
            ("no\n", false),
        ] {
            let mut out = Vec::new();
            let answer = confirm_on_console(Mode::Autonomous, &mut typed.as_bytes(), &mut out);
            assert_eq!(answer, confirmed, "{typed:?}");
            let said = String::from_utf8(out).unwrap();
            assert!(said.contains("REAL robot and drive it"), "{said}");
            assert_eq!(said.contains("starting in halt"), !confirmed, "{said}");
        }
    }
}

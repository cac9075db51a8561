//! What each scripted event does, in words, for `mechweed run --list-events`.

use super::*;

impl EventAction {
    /// What the action does, in a few words (for `mechweed run --list-events`).
    pub fn describe(&self) -> &'static str {
        match self {
            EventAction::EstopFront => "press the front emergency stop (it stays pressed)",
            EventAction::EstopBack => "press the back emergency stop (it stays pressed)",
            EventAction::EstopRelease => "release both emergency stops (power stays off)",
            EventAction::PowerUp => "operator: power the robot up",
            EventAction::Mode(_) => "operator: ask for a mode",
            EventAction::PowerLoss => "main power lost: contactor opens, battery reads 0 V",
            EventAction::PowerRestore => "main power back",
            EventAction::EncoderStuck(_) => "that encoder stops counting; the wheel still moves",
            EventAction::LinkSilent(_) => "the camera link is silent this many seconds",
            EventAction::CameraReboot => "the camera computer reboots, then waits for START",
            EventAction::EndSwitch(_) => "a stone kicks the steered wheel past that end switch",
            EventAction::Battery(_) => "the battery reads this many volts from now on",
            EventAction::PotBroken => "the potentiometer's wire breaks: it reads 0 V",
            EventAction::ContactorWelded => "the motor contactor welds shut",
            EventAction::SteerSlip(_) => {
                "the steering encoder's coupling slips this many degrees (+ = reads further left)"
            }
            EventAction::Miswire(_) => {
                "from now on the robot is wired with this mistake ([sim] miswire's names; none undoes it)"
            }
            EventAction::Joystick { .. } => {
                "the joystick's axes move to these volts and stay (steer + = right, speed + = forward)"
            }
            EventAction::Deadman(_) => {
                "the joystick's dead-man button is held (on) or let go (off)"
            }
            EventAction::Gnss(GnssState::Fixed) => "the GNSS receiver has an RTK fixed solution",
            EventAction::Gnss(GnssState::Float) => {
                "the GNSS receiver loses its corrections' fix: RTK float (10 cm)"
            }
            EventAction::Gnss(GnssState::Dgps) => {
                "the GNSS receiver loses its corrections: DGPS (40 cm)"
            }
            EventAction::Gnss(GnssState::Lost) => "the GNSS receiver has no position at all",
        }
    }
}

/// One action as `mechweed run --list-events` shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct ActionHelp {
    pub name: &'static str,
    /// What the argument must be (None: the action takes none).
    pub argument: Option<String>,
    /// A whole item, e.g. "4 link_silent 2".
    pub example: String,
    pub what: &'static str,
}

/// An argument that `parse_action` accepts, for the examples.
fn example_argument(name: &str) -> Option<&'static str> {
    match name {
        "mode" => Some("autonomous"),
        "encoder_stuck" | "endswitch" => Some("left"),
        "link_silent" => Some("2"),
        "battery" => Some("21.5"),
        "steer_slip" => Some("-3"),
        "joystick" => Some("0 2"),
        "deadman" => Some("on"),
        "miswire" => Some("steer_amp_reversed"),
        _ => None,
    }
}

/// Every action with its argument and an example, read from the parser itself so that
/// the list cannot drift from what [sim] events accepts.
pub fn action_list() -> Vec<ActionHelp> {
    ACTIONS
        .iter()
        .enumerate()
        .map(|(k, &name)| {
            let arg = example_argument(name);
            let action = parse_action(name, arg).expect("every example parses");
            let argument = takes_argument(name).then(|| {
                let missing = parse_action(name, None).expect_err("its argument is required");
                missing.trim_start_matches("missing argument: ").to_string()
            });
            // Spread the examples' times out, as a script would.
            let example = match arg {
                Some(arg) => format!("{} {name} {arg}", 2 * k + 2),
                None => format!("{} {name}", 2 * k + 2),
            };
            ActionHelp {
                name,
                argument,
                example,
                what: action.describe(),
            }
        })
        .collect()
}

//! Scheduled events: what happens to the simulated robot, and when.
//!
//! The text form, as in robot.ini `[sim] events`, is a comma-separated list of items
//! `TIME_S ACTION [ARG]`, for example `2.0 estop_front, 3.5 estop_release, 10 link_silent 2`.
//! Plant events are applied by the simulated robot; operator events (`power_up`, `mode`)
//! are for the controller, which reads the same list.

use std::fmt;

use super::gnss_model::GnssState;
use super::miswire::Miswire;
use crate::{EncoderId, Side};

#[path = "events_help.rs"]
mod help;
pub use help::{ActionHelp, action_list};

/// One action at one time (seconds since the start of the run).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimEvent {
    pub t_s: f64,
    pub action: EventAction,
}

/// The operator's mode request (the controller's modes without Fault).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OperatorMode {
    Halt,
    Joystick,
    Autonomous,
    Test,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventAction {
    /// Press the front emergency stop.
    EstopFront,
    /// Press the back emergency stop.
    EstopBack,
    /// Release both emergency stops.
    EstopRelease,
    /// Operator: power the robot up (for the controller; the plant ignores it).
    PowerUp,
    /// Operator: request a mode (for the controller; the plant ignores it).
    Mode(OperatorMode),
    /// Main power lost: the contactor opens and the battery reads 0 V.
    PowerLoss,
    /// Main power back (the contactor closes again while the relay asks for it).
    PowerRestore,
    /// That encoder stops counting; the wheel or steering still moves.
    EncoderStuck(EncoderId),
    /// The camera link is silent for this many seconds.
    LinkSilent(f64),
    /// The camera computer reboots: silent, then waits for START.
    CameraReboot,
    /// A stone kicks the steered wheel past that side's end switch.
    EndSwitch(Side),
    /// The battery voltage becomes this many volts.
    Battery(f64),
    /// The potentiometer's wire breaks: it reads 0 V.
    PotBroken,
    /// The motor contactor's contacts weld shut: motor power stays on whatever the
    /// relay and the e-stop chain ask.
    ContactorWelded,
    /// The steering encoder's coupling slips by this many degrees (positive: the
    /// encoder reads that much further left than the wheel is).
    SteerSlip(f64),
    /// From now on the robot is wired with this mistake (miswire.rs; `none` undoes it).
    Miswire(Miswire),
    /// The operator's joystick axes move to these voltages (as wired: steer + = right,
    /// speed + = forward); they stay there until the next joystick event.
    Joystick { steer_v: f64, speed_v: f64 },
    /// The operator holds (true) or lets go of (false) the joystick's dead-man button.
    Deadman(bool),
    /// The GNSS receiver's solution becomes this: RTK fixed, RTK float, DGPS or none
    /// (it stays so until the next GNSS event).
    Gnss(GnssState),
}

impl EventAction {
    /// True for the operator's actions, which the plant ignores.
    pub fn is_operator(&self) -> bool {
        matches!(self, EventAction::PowerUp | EventAction::Mode(_))
    }
}

/// Every action's name, in the order the error message lists them.
const ACTIONS: &[&str] = &[
    "estop_front",
    "estop_back",
    "estop_release",
    "power_up",
    "mode",
    "power_loss",
    "power_restore",
    "encoder_stuck",
    "link_silent",
    "camera_reboot",
    "endswitch",
    "battery",
    "pot_broken",
    "contactor_welded",
    "steer_slip",
    "miswire",
    "joystick",
    "deadman",
    "gnss_fixed",
    "gnss_float",
    "gnss_dgps",
    "gnss_lost",
];

impl fmt::Display for EventAction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventAction::EstopFront => write!(f, "estop_front"),
            EventAction::EstopBack => write!(f, "estop_back"),
            EventAction::EstopRelease => write!(f, "estop_release"),
            EventAction::PowerUp => write!(f, "power_up"),
            EventAction::Mode(mode) => write!(f, "mode {}", mode_name(*mode)),
            EventAction::PowerLoss => write!(f, "power_loss"),
            EventAction::PowerRestore => write!(f, "power_restore"),
            EventAction::EncoderStuck(id) => write!(f, "encoder_stuck {}", encoder_name(*id)),
            EventAction::LinkSilent(s) => write!(f, "link_silent {s}"),
            EventAction::CameraReboot => write!(f, "camera_reboot"),
            EventAction::EndSwitch(Side::Left) => write!(f, "endswitch left"),
            EventAction::EndSwitch(Side::Right) => write!(f, "endswitch right"),
            EventAction::Battery(v) => write!(f, "battery {v}"),
            EventAction::PotBroken => write!(f, "pot_broken"),
            EventAction::ContactorWelded => write!(f, "contactor_welded"),
            EventAction::SteerSlip(deg) => write!(f, "steer_slip {deg}"),
            EventAction::Miswire(m) => write!(f, "miswire {m}"),
            EventAction::Joystick { steer_v, speed_v } => write!(f, "joystick {steer_v} {speed_v}"),
            EventAction::Deadman(held) => write!(f, "deadman {}", if *held { "on" } else { "off" }),
            EventAction::Gnss(state) => write!(f, "{}", gnss_name(*state)),
        }
    }
}

impl fmt::Display for SimEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.t_s, self.action)
    }
}

fn gnss_name(state: GnssState) -> &'static str {
    match state {
        GnssState::Fixed => "gnss_fixed",
        GnssState::Float => "gnss_float",
        GnssState::Dgps => "gnss_dgps",
        GnssState::Lost => "gnss_lost",
    }
}

fn mode_name(mode: OperatorMode) -> &'static str {
    match mode {
        OperatorMode::Halt => "halt",
        OperatorMode::Joystick => "joystick",
        OperatorMode::Autonomous => "autonomous",
        OperatorMode::Test => "test",
    }
}

fn encoder_name(id: EncoderId) -> &'static str {
    match id {
        EncoderId::Left => "left",
        EncoderId::Right => "right",
        EncoderId::Steer => "steer",
    }
}

/// Parse the text form into events sorted by time (stable: equal times keep their order).
/// Errors name the item (counted from 1) and what is wrong with it.
pub fn parse_events(text: &str) -> Result<Vec<SimEvent>, String> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    let mut events = Vec::new();
    for (index, item) in text.split(',').enumerate() {
        let item = item.trim();
        let event = parse_item(item)
            .map_err(|what| format!("sim.events item {} \"{item}\": {what}", index + 1))?;
        events.push(event);
    }
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    Ok(events)
}

fn parse_item(item: &str) -> Result<SimEvent, String> {
    let mut words = item.split_whitespace();
    let time_word = words
        .next()
        .ok_or("empty item (two commas in a row, or one at the end?)")?;
    let t_s: f64 = time_word
        .parse()
        .map_err(|_| format!("time \"{time_word}\" is not a number"))?;
    if !t_s.is_finite() || t_s < 0.0 {
        return Err(format!(
            "time \"{time_word}\" must be a number of seconds, 0 or more"
        ));
    }
    let name = words.next().ok_or("missing action after the time")?;
    let rest: Vec<&str> = words.collect();
    // joystick takes two words, steer then speed: given to its parser as one argument.
    let words_taken = if name == "joystick" { 2 } else { 1 };
    if let Some(extra) = rest.get(words_taken) {
        return Err(format!("unexpected word \"{extra}\" after the argument"));
    }
    let joined = rest.join(" ");
    let arg = (!rest.is_empty()).then_some(joined.as_str());
    let action = parse_action(name, arg)?;
    if arg.is_some() && !takes_argument(name) {
        return Err(format!("action \"{name}\" takes no argument"));
    }
    Ok(SimEvent { t_s, action })
}

fn takes_argument(name: &str) -> bool {
    matches!(
        name,
        "mode"
            | "encoder_stuck"
            | "link_silent"
            | "endswitch"
            | "battery"
            | "steer_slip"
            | "miswire"
            | "joystick"
            | "deadman"
    )
}

fn parse_action(name: &str, arg: Option<&str>) -> Result<EventAction, String> {
    let action = match name {
        "estop_front" => EventAction::EstopFront,
        "estop_back" => EventAction::EstopBack,
        "estop_release" => EventAction::EstopRelease,
        "power_up" => EventAction::PowerUp,
        "power_loss" => EventAction::PowerLoss,
        "power_restore" => EventAction::PowerRestore,
        "camera_reboot" => EventAction::CameraReboot,
        "pot_broken" => EventAction::PotBroken,
        "contactor_welded" => EventAction::ContactorWelded,
        "gnss_fixed" => EventAction::Gnss(GnssState::Fixed),
        "gnss_float" => EventAction::Gnss(GnssState::Float),
        "gnss_dgps" => EventAction::Gnss(GnssState::Dgps),
        "gnss_lost" => EventAction::Gnss(GnssState::Lost),
        "mode" => EventAction::Mode(
            match choice(arg, &["halt", "joystick", "autonomous", "test"])? {
                "halt" => OperatorMode::Halt,
                "joystick" => OperatorMode::Joystick,
                "autonomous" => OperatorMode::Autonomous,
                _ => OperatorMode::Test,
            },
        ),
        "encoder_stuck" => {
            EventAction::EncoderStuck(match choice(arg, &["left", "right", "steer"])? {
                "left" => EncoderId::Left,
                "right" => EncoderId::Right,
                _ => EncoderId::Steer,
            })
        }
        "endswitch" => EventAction::EndSwitch(match choice(arg, &["left", "right"])? {
            "left" => Side::Left,
            _ => Side::Right,
        }),
        "link_silent" => EventAction::LinkSilent(number(arg, "a duration in seconds")?),
        "battery" => EventAction::Battery(number(arg, "a voltage in volts")?),
        "steer_slip" => EventAction::SteerSlip(signed(arg, "an angle in degrees")?),
        "joystick" => {
            const WHAT: &str = "STEER_V SPEED_V, two voltages (+ = right, + = forward)";
            let words = arg.ok_or_else(|| format!("missing argument: {WHAT}"))?;
            let mut volts = words.split_whitespace();
            let (Some(steer), Some(speed)) = (volts.next(), volts.next()) else {
                return Err(format!("argument \"{words}\" is not {WHAT}"));
            };
            EventAction::Joystick {
                steer_v: signed(Some(steer), WHAT)?,
                speed_v: signed(Some(speed), WHAT)?,
            }
        }
        "deadman" => EventAction::Deadman(choice(arg, &["on", "off"])? == "on"),
        "miswire" => {
            let word = choice(arg, &super::miswire::miswire_names())?;
            EventAction::Miswire(Miswire::parse(word).unwrap_or_default())
        }
        _ => {
            return Err(format!(
                "unknown action \"{name}\" (known: {})",
                ACTIONS.join(", ")
            ));
        }
    };
    Ok(action)
}

/// The argument, which must be one of `options`.
fn choice<'a>(arg: Option<&'a str>, options: &[&'static str]) -> Result<&'a str, String> {
    let listed = list_with_or(options);
    match arg {
        None => Err(format!("missing argument: {listed}")),
        Some(word) if options.contains(&word) => Ok(word),
        Some(word) => Err(format!("argument \"{word}\" is not one of {listed}")),
    }
}

/// The argument as a finite number, 0 or more.
fn number(arg: Option<&str>, what: &str) -> Result<f64, String> {
    let word = arg.ok_or_else(|| format!("missing argument: {what}"))?;
    match word.parse::<f64>() {
        Ok(value) if value.is_finite() && value >= 0.0 => Ok(value),
        _ => Err(format!("argument \"{word}\" is not {what}, 0 or more")),
    }
}

/// The argument as a finite number of either sign.
fn signed(arg: Option<&str>, what: &str) -> Result<f64, String> {
    let word = arg.ok_or_else(|| format!("missing argument: {what}"))?;
    match word.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        _ => Err(format!("argument \"{word}\" is not {what}")),
    }
}

/// "a, b or c"
fn list_with_or(options: &[&str]) -> String {
    match options.split_last() {
        Some((last, [])) => (*last).to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
#[path = "events_tests.rs"]
mod tests;

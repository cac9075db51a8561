//! Answers to what other programs ask on the bus: requests (`ROBOT/request`) and the
//! configuration ports (`ROBOT/config/SECTION/KEY`). The supervisor decides, with the
//! same rules and the same words as for the GUI; the bus only adds who may ask what
//! (`[bus] accept_requests`). Every answer is JSON; bad input is answered with what is
//! wrong and changes nothing.

use serde_json::{Value, json};

use crate::config::{AcceptRequests, Settings};
use crate::modes::{Gains, Mode, Request};
use crate::request_channel::SupervisorHandle;

use super::payload::{parse_request, parse_set};

/// Settings a running robot takes (the GUI's Tuning tab); the others are read at start.
const LIVE_SECTIONS: [&str; 4] = ["pid.left", "pid.right", "pid.steer", "steer"];

/// An answer: a JSON reply, or an error reply (bad input, or not allowed).
pub type Answer = Result<Value, String>;

pub struct Queries {
    settings: Settings,
    supervisor: SupervisorHandle,
}

impl Queries {
    pub fn new(settings: &Settings, supervisor: SupervisorHandle) -> Queries {
        Queries {
            settings: settings.clone(),
            supervisor,
        }
    }

    fn refused(reason: String) -> Answer {
        Ok(json!({ "accepted": false, "reason": reason }))
    }

    /// `ROBOT/request` with `payload`.
    pub fn request(&self, payload: &[u8]) -> Answer {
        let request = parse_request(payload)?;
        let what = match request {
            Request::Mode(Mode::Halt) => "halt".to_string(),
            Request::Mode(mode) => format!("mode {mode}"),
            _ => "power up".to_string(),
        };
        // Said on the robot's console: the operator there sees who stopped or moved it.
        if request != Request::Mode(Mode::Halt)
            && self.settings.bus.accept_requests == AcceptRequests::Halt
        {
            tracing::warn!(
                "bus: {what} requested by another program: refused (accept_requests = halt)"
            );
            return Self::refused(
                "the bus may only ask for halt here ([bus] accept_requests = halt)".to_string(),
            );
        }
        match self.supervisor.request(request) {
            Ok(()) => {
                tracing::info!("bus: {what} requested by another program: accepted");
                Ok(json!({ "accepted": true }))
            }
            Err(reason) => {
                tracing::info!("bus: {what} requested by another program: refused ({reason})");
                Self::refused(reason)
            }
        }
    }

    /// `ROBOT/config/SECTION/KEY`: `path` is SECTION/KEY; no payload gets the setting,
    /// `{"set": VALUE}` sets it.
    pub fn config(&mut self, path: &str, payload: Option<&[u8]>) -> Answer {
        let Some((section, key)) = path.rsplit_once('/') else {
            return Err(format!(
                "'{path}' is not SECTION/KEY (for example config/pid.left/kp)"
            ));
        };
        let name = format!("[{section}] {key}");
        let source = &self.settings.source;
        let Some((value, comment)) = source.setting(section, key) else {
            return Err(format!("{name} is not a setting in {}", source.label));
        };
        let Some(payload) = payload.filter(|p| !p.is_empty()) else {
            return Ok(json!({
                "setting": format!("{section}.{key}"),
                "value": value,
                "unit": unit_of(key),
                "comment": comment,
            }));
        };
        let new_value = parse_set(payload)?;
        if self.settings.bus.accept_requests == AcceptRequests::Halt {
            return Self::refused(format!(
                "the bus may not change settings here ([bus] accept_requests = halt): {name} stays {value}"
            ));
        }
        if !LIVE_SECTIONS.contains(&section) {
            return Self::refused(format!(
                "{name} is read when the program starts: set it in {} or with --set and start again (a running robot takes only [pid.left], [pid.right], [pid.steer] and [steer])",
                source.label
            ));
        }
        let mut overrides = source.overrides.clone();
        overrides.push(format!("{section}.{key}={new_value}"));
        let checked =
            Settings::parse(&source.label, &source.text, &overrides).map_err(|errors| {
                let lines: Vec<String> = errors.iter().map(ToString::to_string).collect();
                format!("{name} = {new_value} refused: {}", lines.join("; "))
            })?;
        let gains = Gains {
            left: checked.pid_left,
            right: checked.pid_right,
            steer: checked.pid_steer,
        };
        match self
            .supervisor
            .request(Request::Tuning(gains, checked.steer))
        {
            Ok(()) => {
                self.settings = checked;
                Ok(
                    json!({ "accepted": true, "setting": format!("{section}.{key}"), "value": new_value }),
                )
            }
            Err(reason) => Self::refused(reason),
        }
    }
}

/// The unit a setting's name ends with (the project names values with their units).
pub fn unit_of(key: &str) -> &'static str {
    const SUFFIXES: [(&str, &str); 12] = [
        ("_per_m2", "1/m^2"),
        ("_mps2", "m/s^2"),
        ("_mps", "m/s"),
        ("_dps", "deg/s"),
        ("_deg", "deg"),
        ("_rad", "rad"),
        ("_hz", "Hz"),
        ("_us", "us"),
        ("_ms", "ms"),
        ("_s", "s"),
        ("_m", "m"),
        ("_v", "V"),
    ];
    SUFFIXES
        .iter()
        .find(|(suffix, _)| key.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

#[cfg(test)]
mod tests {
    use super::unit_of;

    #[test]
    fn units_come_from_the_names() {
        assert_eq!(unit_of("speed_mps"), "m/s");
        assert_eq!(unit_of("accel_mps2"), "m/s^2");
        assert_eq!(unit_of("ki_per_m2"), "1/m^2");
        assert_eq!(unit_of("link_timeout_s"), "s");
        assert_eq!(unit_of("kp"), "");
    }
}

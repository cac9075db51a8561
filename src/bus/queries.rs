//! Answers to what other programs ask on the bus: requests (`ROBOT/request`, HALT;
//! `ROBOT/request/operator`, every request) and the settings ports
//! (`ROBOT/config/SECTION/KEY` reads, `ROBOT/set/SECTION/KEY` changes). The supervisor
//! decides, with the same rules and the same words as for the GUI; the bus adds who
//! may ask what (`[bus] accept_requests`, the access rules of a secured bus, and a
//! person at the robot first). Every answer is JSON; bad input is answered with what is
//! wrong and changes nothing; every refusal names the rule that refused.

use serde_json::{Value, json};

use crate::config::{AcceptRequests, Backend, PiSettings, Settings, SteerSettings};
use crate::state::Reader;
use crate::state::modes::{Gains, Mode, Request};
use crate::state::request_channel::SupervisorHandle;

use super::BusFigures;
use super::payload::{parse_request, parse_set};

/// Settings a running robot takes (the GUI's Tuning tab); the others are read at start.
const LIVE_SECTIONS: [&str; 4] = ["pid.left", "pid.right", "pid.steer", "steer"];
/// Of those sections, the settings read only when the threads start: the steer
/// thread's period, and the end-switch procedure's back-off.
const START_ONLY: [(&str, &str); 2] = [("steer", "rate_hz"), ("steer", "endswitch_back_deg")];

/// Where a query came in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Port {
    /// ROBOT/request: HALT for every identity that may stop the robot (and, on a bus
    /// that is not secured, every request, as before the keys were split).
    Halt,
    /// ROBOT/request/operator: every request; only an operator's identity may ask.
    Operator,
    /// ROBOT/config/SECTION/KEY: read a setting (and, not secured, set it).
    Get,
    /// ROBOT/set/SECTION/KEY: change a setting; only an operator's identity may ask.
    Set,
}

/// An answer: a JSON reply, or an error reply (bad input, or not allowed).
pub type Answer = Result<Value, String>;

pub(crate) struct Queries {
    settings: Settings,
    supervisor: SupervisorHandle,
    tuning: Reader<(Gains, SteerSettings)>,
    /// TLS and access rules: the old keys keep only what every role may do.
    secured: bool,
}

impl Queries {
    pub fn new(
        settings: &Settings,
        supervisor: SupervisorHandle,
        tuning: Reader<(Gains, SteerSettings)>,
    ) -> Queries {
        Queries {
            settings: settings.clone(),
            supervisor,
            tuning,
            secured: settings.bus.tls.is_some(),
        }
    }

    /// Answer what came in at `port` under `key`. Every answer is JSON; the bus
    /// process sends an error answer as `{"error": WHY}`.
    /// `asker`: the identity that asked, by the roster, where the bus tells it.
    pub fn answer(
        &mut self,
        key: &str,
        payload: Option<&[u8]>,
        port: Port,
        asker: Option<&str>,
    ) -> Answer {
        // Said on the robot's console: the operator there sees who stopped or moved it.
        let by = asker.map_or("another program".to_string(), |name| format!("'{name}'"));
        match port {
            Port::Halt | Port::Operator => self.request(payload.unwrap_or_default(), port, &by),
            Port::Get | Port::Set => {
                let prefix =
                    self.settings
                        .bus
                        .key(if port == Port::Get { "config/" } else { "set/" });
                let path = key.strip_prefix(&prefix).unwrap_or(key);
                self.config(path, payload, port, &by)
            }
        }
    }

    /// Count `answer` in `figures`; a refusal's words, for the console (bus/refusals.rs
    /// says them at most once a second).
    pub(crate) fn count(answer: &Answer, figures: &mut BusFigures) -> Option<String> {
        figures.queries_answered += 1;
        let refusal = match answer {
            Ok(reply) if reply.get("accepted") == Some(&Value::Bool(false)) => {
                Some(reply["reason"].as_str().unwrap_or("refused").to_string())
            }
            Ok(_) => None,
            Err(why) => Some(why.clone()),
        };
        figures.queries_refused += u64::from(refusal.is_some());
        refusal
    }

    pub(crate) fn refused(reason: String) -> Answer {
        Ok(json!({ "accepted": false, "reason": reason }))
    }

    /// A request with `payload`, which came in at `port`, asked `by` (in words).
    pub fn request(&self, payload: &[u8], port: Port, by: &str) -> Answer {
        let request = parse_request(payload)?;
        let what = match request {
            Request::Mode(Mode::Halt) => "halt".to_string(),
            Request::Mode(mode) => format!("mode {mode}"),
            Request::PowerUp => "power up".to_string(),
            // parse_request makes no other.
            _ => "a request".to_string(),
        };
        let halt = request == Request::Mode(Mode::Halt);
        if !halt && port == Port::Halt && self.secured {
            return Self::refused(format!(
                "{what}: on a secured bus {} takes HALT only; power up and modes go to {}, which only an operator's identity may ask (rule: HALT for everyone, the rest for operators)",
                self.settings.bus.key("request"),
                self.settings.bus.key("request/operator")
            ));
        }
        if !halt && self.settings.bus.accept_requests == AcceptRequests::Halt {
            return Self::refused(
                "the bus may only ask for halt here ([bus] accept_requests = halt)".to_string(),
            );
        }
        if request == Request::PowerUp
            && self.settings.backend == Backend::Cards
            && !self.settings.bus.remote_power_up
        {
            return Self::refused(
                "power up: on the real robot motor power comes on only from someone at it (rule: [bus] remote_power_up = no)"
                    .to_string(),
            );
        }
        match self.supervisor.request_from_bus(request) {
            Ok(()) => {
                tracing::info!("bus: {what} requested by {by}: accepted");
                Ok(json!({ "accepted": true }))
            }
            Err(reason) => Self::refused(reason),
        }
    }

    /// A settings port: `path` is SECTION/KEY; no payload gets the setting,
    /// `{"set": VALUE}` sets it (at `Port::Set`, or at `Port::Get` on a bus that is
    /// not secured).
    pub fn config(&mut self, path: &str, payload: Option<&[u8]>, port: Port, by: &str) -> Answer {
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
        let payload = payload.filter(|p| !p.is_empty());
        if payload.is_none() && port == Port::Set {
            return Err(format!(
                "a set of {name} needs a payload {{\"set\": VALUE}} (bus set {section}.{key} VALUE)"
            ));
        }
        let Some(payload) = payload else {
            // A gain or law parameter as in force now (the GUI or the bus may have
            // changed it since the start); any other setting as the program read it.
            let (mut gains, mut law) = self.tuning.snapshot();
            let value =
                live_field(&mut gains, &mut law, section, key).map_or(value, |v| v.to_string());
            return Ok(json!({
                "setting": format!("{section}.{key}"),
                "value": value,
                "unit": unit_of(key),
                "comment": comment,
            }));
        };
        let new_value = parse_set(payload)?;
        if let Some(refused) = self.refusal(&name, (section, key), &value, port) {
            return refused;
        }
        let mut overrides = source.overrides.clone();
        overrides.push(format!("{section}.{key}={new_value}"));
        let checked =
            Settings::parse(&source.label, &source.text, &overrides).map_err(|errors| {
                let lines: Vec<String> = errors.iter().map(ToString::to_string).collect();
                format!("{name} = {new_value} refused: {}", lines.join("; "))
            })?;
        // One value changes; every other gain and law parameter stays as it is in force
        // now (the GUI's Tuning tab may have changed them since the start).
        let (mut gains, mut law) = self.tuning.snapshot();
        let (mut new_gains, mut new_law) = (Gains::from_settings(&checked), checked.steer);
        let new = live_field(&mut new_gains, &mut new_law, section, key).map(|v| *v);
        let (Some(new), Some(in_force)) = (new, live_field(&mut gains, &mut law, section, key))
        else {
            return Self::refused(format!("{name} cannot be changed on a running robot"));
        };
        *in_force = new;
        match self.supervisor.request(Request::Tuning(gains, law)) {
            Ok(()) => {
                tracing::info!("bus: {name} set to {new_value} by {by}");
                self.settings = checked;
                Ok(
                    json!({ "accepted": true, "setting": format!("{section}.{key}"), "value": new_value }),
                )
            }
            Err(reason) => Self::refused(reason),
        }
    }

    /// Why `[section] key` may not be set over the bus here, if it may not: a secured
    /// bus's get port, a robot that takes no settings, a setting read only at start.
    fn refusal(
        &self,
        name: &str,
        (section, key): (&str, &str),
        value: &str,
        port: Port,
    ) -> Option<Answer> {
        let source = &self.settings.source;
        if port == Port::Get && self.secured {
            return Some(Self::refused(format!(
                "{name}: on a secured bus settings are changed on {}, which only an operator's identity may ask (rule: reading for every role, changing for operators)",
                self.settings.bus.key(&format!("set/{section}/{key}"))
            )));
        }
        if self.settings.bus.accept_requests == AcceptRequests::Halt {
            return Some(Self::refused(format!(
                "the bus may not change settings here ([bus] accept_requests = halt): {name} stays {value}"
            )));
        }
        if START_ONLY.contains(&(section, key)) {
            return Some(Self::refused(format!(
                "{name} is read when the threads start: set it in {} or with --set and start again; it stays {value}",
                source.label
            )));
        }
        if !LIVE_SECTIONS.contains(&section) {
            return Some(Self::refused(format!(
                "{name} is read when the program starts: set it in {} or with --set and start again (a running robot takes only [pid.left], [pid.right], [pid.steer] and [steer])",
                source.label
            )));
        }
        None
    }
}

/// The value of `[section] key` among the gains and the steering law, to read or set;
/// None if it is not one of them.
fn live_field<'a>(
    gains: &'a mut Gains,
    law: &'a mut SteerSettings,
    section: &str,
    key: &str,
) -> Option<&'a mut f64> {
    let pi = |p: &'a mut PiSettings| match key {
        "kp" => Some(&mut p.kp),
        "ki" => Some(&mut p.ki),
        "kff" => Some(&mut p.kff),
        "out_max_v" => Some(&mut p.out_max_v),
        _ => None,
    };
    let pd = &mut gains.steer;
    match (section, key) {
        ("pid.left", _) => pi(&mut gains.left),
        ("pid.right", _) => pi(&mut gains.right),
        ("pid.steer", "kp") => Some(&mut pd.kp),
        ("pid.steer", "kd") => Some(&mut pd.kd),
        ("pid.steer", "d_filter_s") => Some(&mut pd.d_filter_s),
        ("pid.steer", "out_max_v") => Some(&mut pd.out_max_v),
        ("steer", "rate_hz") => Some(&mut law.rate_hz),
        ("steer", "speed_mps") => Some(&mut law.speed_mps),
        ("steer", "lookahead_m") => Some(&mut law.lookahead_m),
        ("steer", "ki_per_m2") => Some(&mut law.ki_per_m2),
        ("steer", "integral_max_deg") => Some(&mut law.integral_max_deg),
        ("steer", "curvature_filter_m") => Some(&mut law.curvature_filter_m),
        ("steer", "latency_s") => Some(&mut law.latency_s),
        ("steer", "endswitch_back_deg") => Some(&mut law.endswitch_back_deg),
        _ => None,
    }
}

/// The unit a setting's name ends with (the project names values with their units).
pub(crate) fn unit_of(key: &str) -> &'static str {
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
    use super::*;
    use crate::state::shared;
    use crate::state::status::Status;

    /// The answers to a power-up over the bus, on `backend`, with `remote_power_up`, from
    /// a supervisor that takes every request it is given (so that a refusal is the bus's).
    fn power_up_over_the_bus(backend: Backend, remote_power_up: bool) -> Answer {
        let mut settings = Settings::shipped();
        settings.backend = backend;
        settings.bus.accept_requests = AcceptRequests::Operator;
        settings.bus.remote_power_up = remote_power_up;
        let (_, status) = shared(Status::default());
        let (handle, inbox) = crate::state::request_channel::channel(status);
        let answering = std::thread::spawn(move || {
            if let Ok(envelope) = inbox.recv_timeout(std::time::Duration::from_secs(2)) {
                let _ = envelope.reply.send((envelope.request, Ok(())));
            }
        });
        let (_, tuning) = shared((Gains::from_settings(&settings), settings.steer));
        let queries = Queries::new(&settings, handle, tuning);
        let answer = queries.request(br#"{"request": "power_up"}"#, Port::Operator, "a test");
        answering.join().unwrap();
        answer
    }

    #[test]
    fn a_remote_power_up_of_the_real_robot_needs_its_setting() {
        let refused = power_up_over_the_bus(Backend::Cards, false).unwrap();
        assert_eq!(refused["accepted"], false);
        let why = refused["reason"].as_str().unwrap();
        assert!(why.contains("[bus] remote_power_up = no"), "{why}");
        let allowed = power_up_over_the_bus(Backend::Cards, true).unwrap();
        assert_eq!(allowed["accepted"], true, "{allowed}");
        // The simulated robot takes it whatever the setting says.
        let sim = power_up_over_the_bus(Backend::Sim, false).unwrap();
        assert_eq!(sim["accepted"], true, "{sim}");
    }

    #[test]
    fn units_come_from_the_names() {
        assert_eq!(unit_of("speed_mps"), "m/s");
        assert_eq!(unit_of("accel_mps2"), "m/s^2");
        assert_eq!(unit_of("ki_per_m2"), "1/m^2");
        assert_eq!(unit_of("link_timeout_s"), "s");
        assert_eq!(unit_of("kp"), "");
    }
}

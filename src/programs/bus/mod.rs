//! `mechweed bus ...`: the command line of the bus tools (src/bus/tools.rs).

use std::process::ExitCode;

use clap::{Subcommand, ValueEnum};

pub mod record;
pub mod tools;

use tools::Tool;

/// SECTION.KEY as a settings port's key, `PORT/SECTION/KEY` (sections may hold dots):
/// `config` reads a setting, `set` changes it (only an operator may ask that one).
#[derive(clap::Args)]
pub struct BusArgs {
    #[command(subcommand)]
    pub command: BusCommand,
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, global = true, value_name = "ENDPOINT", default_value = crate::programs::bus::tools::DEFAULT_ENDPOINT)]
    pub connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(long, global = true, value_name = "NAME", default_value = "mechweed")]
    pub robot: String,
    /// This program's identity on a secured bus (--keys DIR --as operator).
    #[command(flatten)]
    pub identity: crate::programs::keys::IdentityArgs,
}

#[derive(Subcommand)]
pub enum BusCommand {
    /// Print a flow's messages as JSON lines: status, tick, event, camera/row, or any key.
    Echo {
        key: String,
        /// Stop after this many messages.
        #[arg(long, value_name = "N")]
        count: Option<u64>,
        /// Stop after this many seconds.
        #[arg(long, value_name = "SECONDS", value_parser = crate::config::parse_seconds)]
        seconds: Option<f64>,
        /// Take this long over each message: a slow receiver, for tests and measurements.
        #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = crate::config::parse_seconds)]
        slow: f64,
        /// At the end, print how old the messages were on arrival (p50, p99, max), from
        /// the time each was sent (status carries it; needs the same clock).
        #[arg(long)]
        latency: bool,
    },
    /// Send a request and print the robot's answer: halt, power_up, or mode MODE.
    Request {
        #[arg(value_enum)]
        request: BusRequest,
        /// For `mode`: halt, joystick, autonomous or test.
        mode: Option<String>,
    },
    /// Print one setting of the running robot, e.g. pid.left.kp.
    Get {
        #[arg(value_name = "SECTION.KEY")]
        setting: String,
    },
    /// Change one setting of the running robot (in halt, gains and [steer] only).
    Set {
        #[arg(value_name = "SECTION.KEY")]
        setting: String,
        value: String,
    },
    /// Who is on the bus, and which flows carry messages at what rate.
    List {
        /// How long to count messages.
        #[arg(long, default_value_t = 2.0, value_name = "SECONDS", value_parser = crate::config::parse_seconds)]
        seconds: f64,
    },
}

#[derive(Clone, Copy, ValueEnum)]
pub enum BusRequest {
    Halt,
    /// The same word as in the request's JSON (power-up is taken too).
    #[value(name = "power_up", alias = "power-up")]
    PowerUp,
    Mode,
}

fn config_key(port: &str, setting: &str) -> Result<String, String> {
    match setting.rsplit_once('.') {
        Some((section, key)) if !section.is_empty() && !key.is_empty() => {
            Ok(format!("{port}/{section}/{key}"))
        }
        _ => Err(format!(
            "'{setting}' is not SECTION.KEY (for example pid.left.kp)"
        )),
    }
}

/// The request's payload.
fn request_payload(request: BusRequest, mode: Option<String>) -> Result<String, String> {
    let json = match (request, mode) {
        (BusRequest::Mode, Some(mode)) => serde_json::json!({ "request": "mode", "mode": mode }),
        (BusRequest::Mode, None) => {
            return Err(
                "say which mode: bus request mode autonomous (or joystick, test, halt)".into(),
            );
        }
        (_, Some(extra)) => {
            return Err(format!(
                "'{extra}' goes only after mode (bus request mode {extra})"
            ));
        }
        (BusRequest::Halt, None) => serde_json::json!({ "request": "halt" }),
        (BusRequest::PowerUp, None) => serde_json::json!({ "request": "power_up" }),
    };
    Ok(json.to_string())
}

/// A request's or a set's answer: `accepted`, or `refused: REASON` (exit 1).
fn decided(answer: &str) -> Result<String, String> {
    if answer.trim().is_empty() {
        return Err(
            "the robot program answered with nothing: whether it took the request is not known; look at its status (bus echo status --count 1)"
                .to_string(),
        );
    }
    let value: serde_json::Value = serde_json::from_str(answer).unwrap_or_default();
    match value.get("accepted").and_then(serde_json::Value::as_bool) {
        Some(true) => Ok("accepted".to_string()),
        Some(false) => Err(format!(
            "refused: {}",
            value
                .get("reason")
                .and_then(|r| r.as_str())
                .unwrap_or(answer)
        )),
        None => Err(format!("an answer that is not a decision: {answer}")),
    }
}

/// A setting's answer: `SECTION.KEY = VALUE UNIT  ; comment`.
fn setting_line(answer: &str) -> String {
    let value: serde_json::Value = serde_json::from_str(answer).unwrap_or_default();
    let field = |name: &str| value.get(name).and_then(|v| v.as_str()).unwrap_or("");
    let unit = field("unit");
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    format!(
        "{} = {}{unit}  ; {}",
        field("setting"),
        field("value"),
        field("comment")
    )
}

/// `--latency`: how old the messages were on arrival.
fn latency_line(mut ages_s: Vec<f64>) -> String {
    if ages_s.is_empty() {
        return "latency: no message said when it was sent (only status carries wall_s)".into();
    }
    ages_s.sort_by(f64::total_cmp);
    let at = |q: f64| ages_s[((ages_s.len() - 1) as f64 * q).round() as usize] * 1e3;
    format!(
        "latency from publish to this receiver over {} messages: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
        ages_s.len(),
        at(0.5),
        at(0.99),
        at(1.0)
    )
}

pub fn bus(args: BusArgs) -> ExitCode {
    // A flow is waited for, as a subscriber does; a question needs the robot there now.
    let wait = matches!(args.command, BusCommand::Echo { .. });
    let tls = args.identity.files();
    // A flow the robot does not have would be waited for in silence: refused at once.
    if let BusCommand::Echo { key, .. } = &args.command
        && let Err(why) = crate::programs::bus::tools::check_flow(key)
    {
        eprintln!("{why}");
        return ExitCode::FAILURE;
    }
    let result = if let BusCommand::Request {
        request: BusRequest::Halt,
        mode: None,
    } = &args.command
    {
        halt_until_answered(&args.connect, &args.robot, tls.as_ref())
    } else {
        command(args, wait, tls.as_ref())
    };
    match result {
        Ok(text) => {
            if !text.is_empty() {
                println!("{}", text.trim_end());
            }
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

/// How long `bus request halt` keeps trying when no answer comes.
const HALT_TRIES_FOR: std::time::Duration = std::time::Duration::from_secs(10);

/// HALT is worth asking again: a link that cannot be made now (a flood of junk
/// connections at the robot's port, a gap in the field's Wi-Fi, a robot program still
/// starting) may be made a moment later. Each try is said; a decision ends it.
fn halt_until_answered(
    connect: &str,
    robot: &str,
    tls: Option<&crate::config::TlsFiles>,
) -> Result<String, String> {
    let until = std::time::Instant::now() + HALT_TRIES_FOR;
    let payload = request_payload(BusRequest::Halt, None)?;
    loop {
        let asked = Tool::connect(connect, robot, false, tls)
            .and_then(|tool| tool.ask("request", Some(payload.clone())));
        let why = match asked {
            Ok(answer) => return decided(&answer),
            Err(why) => why,
        };
        let left_s = until
            .saturating_duration_since(std::time::Instant::now())
            .as_secs_f64();
        if left_s <= 0.0 {
            return Err(format!(
                "{why}; HALT was asked for {} s and not answered",
                HALT_TRIES_FOR.as_secs()
            ));
        }
        eprintln!("HALT not answered yet ({why}); asking again, for {left_s:.0} s more");
        std::thread::sleep(std::time::Duration::from_millis(500));
    }
}

/// Every bus command but HALT, once.
fn command(
    args: BusArgs,
    wait: bool,
    tls: Option<&crate::config::TlsFiles>,
) -> Result<String, String> {
    Tool::connect(&args.connect, &args.robot, wait, tls).and_then(|tool| {
        match args.command {
            BusCommand::Echo {
                key,
                count,
                seconds,
                slow,
                latency,
            } => {
                let ages_s = tool.echo(&key, count, seconds, slow)?;
                Ok(if latency {
                    latency_line(ages_s)
                } else {
                    String::new()
                })
            }
            BusCommand::Request { request, mode } => {
                // HALT on the key every identity that may stop the robot may ask; the
                // others on the operator's own.
                let key = match request {
                    BusRequest::Halt => "request",
                    _ => "request/operator",
                };
                let payload = request_payload(request, mode)?;
                decided(&tool.ask(key, Some(payload))?)
            }
            BusCommand::Get { setting } => Ok(setting_line(
                &tool.ask(&config_key("config", &setting)?, None)?,
            )),
            BusCommand::Set { setting, value } => {
                let payload = serde_json::json!({ "set": value }).to_string();
                decided(&tool.ask(&config_key("set", &setting)?, Some(payload))?)
            }
            BusCommand::List { seconds } => tool.list(seconds),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::decided;

    #[test]
    fn the_tools_look_for_the_robot_where_the_shipped_robot_listens() {
        let listen = crate::config::Settings::shipped().bus.listen;
        assert_eq!(listen, [super::tools::DEFAULT_ENDPOINT]);
    }

    #[test]
    fn an_empty_answer_is_not_taken_for_a_decision() {
        assert_eq!(decided(r#"{"accepted": true}"#), Ok("accepted".to_string()));
        let why = decided("").unwrap_err();
        assert!(why.contains("answered with nothing"), "{why}");
        assert!(why.contains("not known"), "{why}");
        let why = decided(r#"{"accepted": false, "reason": "motor power is off"}"#).unwrap_err();
        assert_eq!(why, "refused: motor power is off");
    }
}

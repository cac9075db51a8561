//! robot.ini [io] text -> one signal's wiring, and the checks of the whole wiring.
//! Every message says what is wrong and what would be right; the caller adds the key.

use super::{AnalogIn, AnalogOut, Bit, Encoder, Place, Switch, Wiring};

/// What a signal is, which decides where it may be wired and which option it takes.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    AnalogIn,
    SwitchIn,
    Encoder,
    AnalogOut,
    SwitchOut,
}

enum Opt {
    Scale(f64),
    ActiveHigh(bool),
}

/// A channel number within `lo..=hi`, or a message naming the card's real channels.
fn channel(word: &str, lo: u8, hi: u8, what: &str) -> Result<u8, String> {
    match word.parse::<u8>() {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => Err(format!(
            "{what} {word} does not exist: the card has {lo}..{hi}"
        )),
    }
}

fn place(text: &str) -> Result<Place, String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    Ok(match words[..] {
        ["das08", "ai", n] => Place::Das08Ai(channel(n, 0, 7, "das08 analog input")?),
        ["das08", "ip", n] => Place::Bit(Bit::Das08In(channel(n, 1, 3, "das08 input ip")?)),
        ["das08", "op", n] => Place::Bit(Bit::Das08Out(channel(n, 1, 4, "das08 output op")?)),
        ["dda06", "ao", n] => Place::Dda06Ao(channel(n, 0, 5, "dda06 analog output")?),
        ["dda06", "port", x, "bit", n] => {
            let port = match x {
                "a" => 0,
                "b" => 1,
                "c" => 2,
                _ => {
                    return Err(format!(
                        "dda06 port {x} does not exist: the 8255 has a, b, c"
                    ));
                }
            };
            let bit = channel(n, 0, 7, "dda06 port bit")?;
            Place::Bit(Bit::Dda06 { port, bit })
        }
        ["quad04", "ch", n] => Place::Quad04(channel(n, 1, 4, "quad04 channel")?),
        _ => {
            return Err(format!(
                "'{text}' is not a card channel: write for example das08 ai 0, das08 ip 1, \
                 das08 op 1, dda06 ao 0, dda06 port a bit 0 or quad04 ch 1"
            ));
        }
    })
}

fn option(text: &str) -> Result<Opt, String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    match words[..] {
        ["active", "high"] => Ok(Opt::ActiveHigh(true)),
        ["active", "low"] => Ok(Opt::ActiveHigh(false)),
        ["scale", s] => match s.parse::<f64>() {
            Ok(v) if v.is_finite() && v != 0.0 && v.abs() <= 1000.0 => Ok(Opt::Scale(v)),
            _ => Err(format!(
                "scale {s} is not a number between -1000 and 1000, other than 0"
            )),
        },
        _ => Err(format!(
            "'{text}' is not an option: write scale NUMBER, active high or active low"
        )),
    }
}

/// Parse `CARD CHANNEL, OPTION` for a signal of this kind.
fn parse(text: &str, kind: Kind) -> Result<(Place, Opt), String> {
    let text = text.trim().to_ascii_lowercase();
    let mut parts = text.split(',').map(str::trim);
    let place = place(parts.next().unwrap_or(""))?;
    let opt = match (parts.next(), parts.next()) {
        (Some(one), None) => option(one)?,
        _ => {
            return Err(format!(
                "'{text}' needs its card channel and one option, for example \
                 das08 ai 0, scale 1 or das08 ip 1, active high"
            ));
        }
    };
    let fits = matches!(
        (kind, place),
        (Kind::AnalogIn, Place::Das08Ai(_))
            | (
                Kind::SwitchIn,
                Place::Bit(Bit::Das08In(_) | Bit::Dda06 { .. })
            )
            | (Kind::Encoder, Place::Quad04(_))
            | (Kind::AnalogOut, Place::Dda06Ao(_))
            | (
                Kind::SwitchOut,
                Place::Bit(Bit::Das08Out(_) | Bit::Dda06 { .. })
            )
    );
    if !fits {
        let wanted = match kind {
            Kind::AnalogIn => "an analog input goes on das08 ai 0..7",
            Kind::SwitchIn => "a switch input goes on das08 ip 1..3 or dda06 port a|b|c bit 0..7",
            Kind::Encoder => "an encoder goes on quad04 ch 1..4",
            Kind::AnalogOut => "an analog output goes on dda06 ao 0..5",
            Kind::SwitchOut => {
                "a switched output goes on das08 op 1..4 or dda06 port a|b|c bit 0..7"
            }
        };
        return Err(format!("{place} cannot carry this signal: {wanted}"));
    }
    let switch = matches!(kind, Kind::SwitchIn | Kind::SwitchOut);
    match opt {
        Opt::Scale(_) if switch => {
            Err("a switch takes active high or active low, not a scale".into())
        }
        Opt::ActiveHigh(_) if !switch => {
            Err("this signal takes a scale, not active high/low".into())
        }
        _ => Ok((place, opt)),
    }
}

fn scale(opt: Opt) -> f64 {
    match opt {
        Opt::Scale(s) => s,
        Opt::ActiveHigh(_) => 1.0,
    }
}

fn switch(place: Place, opt: Opt) -> Switch {
    let bit = match place {
        Place::Bit(bit) => bit,
        _ => Bit::Das08In(1),
    };
    let active_high = !matches!(opt, Opt::ActiveHigh(false));
    Switch { bit, active_high }
}

/// The channel number of a place (for the kinds with one number).
fn number(place: Place) -> u8 {
    match place {
        Place::Das08Ai(n) | Place::Dda06Ao(n) | Place::Quad04(n) => n,
        Place::Bit(_) => 0,
    }
}

pub fn parse_analog_in(text: &str) -> Result<AnalogIn, String> {
    let (place, opt) = parse(text, Kind::AnalogIn)?;
    Ok(AnalogIn {
        channel: number(place),
        scale: scale(opt),
    })
}

pub fn parse_analog_out(text: &str) -> Result<AnalogOut, String> {
    let (place, opt) = parse(text, Kind::AnalogOut)?;
    Ok(AnalogOut {
        channel: number(place),
        scale: scale(opt),
    })
}

pub fn parse_encoder(text: &str) -> Result<Encoder, String> {
    let (place, opt) = parse(text, Kind::Encoder)?;
    let sign = match scale(opt) {
        1.0 => 1,
        -1.0 => -1,
        other => {
            return Err(format!(
                "an encoder's scale is 1 or -1 (reversed), not {other}"
            ));
        }
    };
    Ok(Encoder {
        channel: number(place),
        sign,
    })
}

pub fn parse_switch_in(text: &str) -> Result<Switch, String> {
    let (place, opt) = parse(text, Kind::SwitchIn)?;
    Ok(switch(place, opt))
}

pub fn parse_switch_out(text: &str) -> Result<Switch, String> {
    let (place, opt) = parse(text, Kind::SwitchOut)?;
    Ok(switch(place, opt))
}

/// The dead-man's second contact: a switch input, or `none` for a one-contact button.
pub fn parse_second_contact(text: &str) -> Result<Option<Switch>, String> {
    if text.trim().eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    parse_switch_in(text)
        .map(Some)
        .map_err(|e| format!("{e}; or none for a dead-man with one contact"))
}

/// The watchdog line: a switched output, or `none` for no watchdog output.
pub fn parse_watchdog(text: &str) -> Result<Option<Switch>, String> {
    if text.trim().eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    parse_switch_out(text)
        .map(Some)
        .map_err(|e| format!("{e}; or none for no watchdog output"))
}

/// The 8255 group of a DDA06 line: A, B, upper C or lower C switch direction together.
fn group(bit: Bit) -> Option<(u8, bool)> {
    match bit {
        Bit::Dda06 { port: 2, bit } => Some((2, bit >= 4)),
        Bit::Dda06 { port, .. } => Some((port, false)),
        _ => None,
    }
}

/// Why an input and an output cannot share an 8255 group.
const ONE_DIRECTION: &str = "a group (port a, port b, port c bits 4..7, port c bits 0..3) is \
                             all inputs or all outputs";

/// Problems of the wiring as a whole, each with the key to blame: two signals on one
/// channel or bit, or an input in an 8255 group that also drives an output. The
/// watchdog, added last, is the key blamed for its clashes.
pub fn check(wiring: &Wiring) -> Vec<(&'static str, String)> {
    let mut places = wiring.places().to_vec();
    if let Some(s) = wiring.joystick_released {
        places.push(("joystick_released", Place::Bit(s.bit)));
    }
    if let Some(w) = wiring.watchdog {
        places.push(("watchdog", Place::Bit(w.bit)));
    }
    let mut problems = Vec::new();
    for (i, (key, place)) in places.iter().enumerate() {
        if let Some((other, _)) = places[..i].iter().find(|(_, p)| p == place) {
            problems.push((*key, format!("{place} is already wired to {other}")));
        }
    }
    for (key, input) in wiring.switch_inputs() {
        let same_group = |(_, out): &(&str, Switch)| {
            group(out.bit).is_some() && group(out.bit) == group(input.bit)
        };
        if let Some((out_key, _)) = wiring.switch_outputs().into_iter().find(same_group) {
            problems.push((
                key,
                format!(
                    "{} is in the same 8255 port group as the output {out_key}: {ONE_DIRECTION}",
                    Place::Bit(input.bit)
                ),
            ));
        }
    }
    if let Some(w) = wiring.watchdog {
        let same_group = |(_, input): &(&str, Switch)| {
            group(input.bit).is_some() && group(input.bit) == group(w.bit)
        };
        if let Some((in_key, _)) = wiring.switch_inputs().find(same_group) {
            let place = Place::Bit(w.bit);
            problems.push((
                "watchdog",
                format!(
                    "{place} is in the same 8255 port group as the input {in_key}: {ONE_DIRECTION}"
                ),
            ));
        }
    }
    problems
}

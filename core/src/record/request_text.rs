//! An operator's request and the supervisor's answer as one line of text in a record's
//! events ("mode autonomous => accepted"), written so that `mechweed replay` can read
//! the request back exactly (numbers in their shortest exact form) and give it again.

use std::collections::BTreeMap;

use mechweed_hw::Outputs;

use crate::config::{PdSettings, PiSettings, SteerLaw, SteerSettings};
use crate::state::commission::TestStep;
use crate::state::modes::{Gains, Mode, Refusal, Request};

/// "REQUEST => accepted" or "REQUEST => refused: WHY".
pub(crate) fn event_text(request: &Request, answer: &Result<(), Refusal>) -> String {
    format!("{} => {}", request_text(request), answer_text(answer))
}

pub fn answer_text(answer: &Result<(), Refusal>) -> String {
    match answer {
        Ok(()) => "accepted".into(),
        Err(why) => format!("refused: {why}"),
    }
}

pub fn request_text(request: &Request) -> String {
    match request {
        Request::Mode(m) => format!("mode {m}"),
        Request::PowerUp => "power_up".into(),
        Request::TestOutputs(o) => format!(
            "test_outputs amp_left_v={:?} amp_right_v={:?} amp_steer_v={:?} main_power_on={} brake_release_left={} brake_release_right={} tool_on={}",
            o.amp_left_v,
            o.amp_right_v,
            o.amp_steer_v,
            u8::from(o.main_power_on),
            u8::from(o.brake_release_left),
            u8::from(o.brake_release_right),
            u8::from(o.tool_on)
        ),
        Request::TestHold(held) => format!("test_hold held={}", u8::from(*held)),
        Request::TestStep(step) => format!("test_step step={}", step.name()),
        Request::Gains(g) => format!("gains {}", gains_text(g)),
        Request::Tuning(g, s) => format!("tuning {} {}", gains_text(g), steer_text(s)),
    }
}

fn pi_text(name: &str, p: &PiSettings) -> String {
    let (kp, ki, kff, max) = (p.kp, p.ki, p.kff, p.out_max_v);
    format!("{name}.kp={kp:?} {name}.ki={ki:?} {name}.kff={kff:?} {name}.out_max_v={max:?}")
}

fn gains_text(g: &Gains) -> String {
    let s = &g.steer;
    format!(
        "{} {} pid.steer.kp={:?} pid.steer.kd={:?} pid.steer.d_filter_s={:?} pid.steer.out_max_v={:?}",
        pi_text("pid.left", &g.left),
        pi_text("pid.right", &g.right),
        s.kp,
        s.kd,
        s.d_filter_s,
        s.out_max_v
    )
}

fn steer_text(s: &SteerSettings) -> String {
    format!(
        "steer.law={} steer.rate_hz={:?} steer.speed_mps={:?} steer.lookahead_m={:?} steer.ki_per_m2={:?} steer.integral_max_deg={:?} steer.curvature_filter_m={:?} steer.latency_s={:?} steer.endswitch_back_deg={:?}",
        s.law.name(),
        s.rate_hz,
        s.speed_mps,
        s.lookahead_m,
        s.ki_per_m2,
        s.integral_max_deg,
        s.curvature_filter_m,
        s.latency_s,
        s.endswitch_back_deg
    )
}

/// A request and its recorded answer back from an event's text; the error says what
/// in the text is not a request.
pub fn parse_event_text(text: &str) -> Result<(Request, String), String> {
    let (request, answer) = text
        .split_once(" => ")
        .ok_or_else(|| format!("'{text}' has no ' => ' between the request and its answer"))?;
    Ok((parse_request(request)?, answer.to_string()))
}

fn parse_request(text: &str) -> Result<Request, String> {
    let (word, rest) = text.split_once(' ').unwrap_or((text, ""));
    let mut values = Values::new(rest)?;
    let request = match word {
        "mode" => {
            Request::Mode(Mode::from_name(rest).ok_or_else(|| format!("'{rest}' is not a mode"))?)
        }
        "power_up" => Request::PowerUp,
        "test_outputs" => Request::TestOutputs(Outputs {
            amp_left_v: values.num("amp_left_v")?,
            amp_right_v: values.num("amp_right_v")?,
            amp_steer_v: values.num("amp_steer_v")?,
            main_power_on: values.flag("main_power_on")?,
            brake_release_left: values.flag("brake_release_left")?,
            brake_release_right: values.flag("brake_release_right")?,
            tool_on: values.flag("tool_on")?,
        }),
        "test_hold" => Request::TestHold(values.flag("held")?),
        "test_step" => {
            let name = values.0.remove("step").unwrap_or_default();
            Request::TestStep(
                TestStep::from_name(&name).ok_or_else(|| format!("step={name} is not a step"))?,
            )
        }
        "gains" => Request::Gains(values.gains()?),
        "tuning" => Request::Tuning(values.gains()?, values.steer()?),
        other => return Err(format!("'{other}' is not a request")),
    };
    if word != "mode" {
        values.all_used()?;
    }
    Ok(request)
}

/// The KEY=VALUE words of a request, each to be used once.
struct Values(BTreeMap<String, String>);

impl Values {
    fn new(text: &str) -> Result<Values, String> {
        let mut map = BTreeMap::new();
        for word in text.split_whitespace().filter(|w| w.contains('=')) {
            let (k, v) = word.split_once('=').unwrap_or_default();
            map.insert(k.to_string(), v.to_string());
        }
        Ok(Values(map))
    }

    fn num(&mut self, key: &str) -> Result<f64, String> {
        let text = self
            .0
            .remove(key)
            .ok_or_else(|| format!("{key} is missing"))?;
        text.parse()
            .map_err(|_| format!("{key}={text} is not a number"))
    }

    fn flag(&mut self, key: &str) -> Result<bool, String> {
        match self.num(key)? {
            0.0 => Ok(false),
            1.0 => Ok(true),
            _ => Err(format!("{key} is neither 0 nor 1")),
        }
    }

    fn pi(&mut self, name: &str) -> Result<PiSettings, String> {
        Ok(PiSettings {
            kp: self.num(&format!("{name}.kp"))?,
            ki: self.num(&format!("{name}.ki"))?,
            kff: self.num(&format!("{name}.kff"))?,
            out_max_v: self.num(&format!("{name}.out_max_v"))?,
        })
    }

    fn gains(&mut self) -> Result<Gains, String> {
        Ok(Gains {
            left: self.pi("pid.left")?,
            right: self.pi("pid.right")?,
            steer: PdSettings {
                kp: self.num("pid.steer.kp")?,
                kd: self.num("pid.steer.kd")?,
                d_filter_s: self.num("pid.steer.d_filter_s")?,
                out_max_v: self.num("pid.steer.out_max_v")?,
            },
        })
    }

    fn steer(&mut self) -> Result<SteerSettings, String> {
        // Records from before the choice of law were all steered by pure pursuit.
        let law = match self.0.remove("steer.law") {
            None => SteerLaw::Pursuit,
            Some(name) => SteerLaw::from_name(&name)
                .ok_or_else(|| format!("steer.law={name} is not a steering law"))?,
        };
        Ok(SteerSettings {
            law,
            rate_hz: self.num("steer.rate_hz")?,
            speed_mps: self.num("steer.speed_mps")?,
            lookahead_m: self.num("steer.lookahead_m")?,
            ki_per_m2: self.num("steer.ki_per_m2")?,
            integral_max_deg: self.num("steer.integral_max_deg")?,
            curvature_filter_m: self.num("steer.curvature_filter_m")?,
            latency_s: self.num("steer.latency_s")?,
            endswitch_back_deg: self.num("steer.endswitch_back_deg")?,
        })
    }

    fn all_used(&self) -> Result<(), String> {
        match self.0.keys().next() {
            None => Ok(()),
            Some(k) => Err(format!("{k} is not part of this request")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    #[test]
    fn every_kind_of_request_reads_back_exactly() {
        let s = Settings::shipped();
        let mut gains = Gains::from_settings(&s);
        gains.left.kp = 0.1 + 0.2; // a number with no short decimal form
        let outputs = Outputs {
            amp_left_v: -1.0 / 3.0,
            tool_on: true,
            ..Outputs::SAFE
        };
        let requests = [
            Request::Mode(Mode::Autonomous),
            Request::PowerUp,
            Request::TestOutputs(outputs),
            Request::TestHold(true),
            Request::TestHold(false),
            Request::TestStep(TestStep::Actuator(mechweed_hw::EncoderId::Steer)),
            Request::TestStep(TestStep::Voltmeter),
            Request::TestStep(TestStep::Stop),
            Request::Gains(gains),
            Request::Tuning(gains, s.steer),
        ];
        for request in requests {
            for answer in [Ok(()), Err(Refusal::NotPowered)] {
                let text = event_text(&request, &answer);
                let (back, said) = parse_event_text(&text).unwrap();
                assert_eq!(back, request, "{text}");
                assert_eq!(said, answer_text(&answer));
            }
        }
    }

    #[test]
    fn text_that_is_not_a_request_is_named() {
        let cases = [
            ("mode autonomous", "no ' => '"),
            ("mode flying => accepted", "'flying' is not a mode"),
            ("jump => accepted", "'jump' is not a request"),
            (
                "test_outputs amp_left_v=1 => accepted",
                "amp_right_v is missing",
            ),
            ("power_up extra=1 => accepted", "extra is not part"),
        ];
        for (text, why) in cases {
            let error = parse_event_text(text).unwrap_err();
            assert!(error.contains(why), "{text}: {error}");
        }
        let mut gains = request_text(&Request::Gains(Gains::from_settings(&Settings::shipped())));
        gains = gains.replace("pid.left.kp=", "pid.left.kp=x");
        let error = parse_event_text(&format!("{gains} => accepted")).unwrap_err();
        assert!(error.contains("is not a number"), "{error}");
    }
}

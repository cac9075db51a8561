//! Status: every input live, every output as commanded, the camera link, GNSS and the
//! row filter, and each loop's timing with the Liu-Layland check from measured
//! execution times.

use eframe::egui::{self, RichText};

use super::requests::Requests;
use super::theme;
use super::view::{GamepadView, View};
use crate::rt::liu_layland;
use crate::state::fault_cause::FaultCause;

fn on_off(on: bool) -> &'static str {
    if on { "on" } else { "off" }
}

fn row(ui: &mut egui::Ui, name: &str, value: String) {
    ui.label(name);
    ui.monospace(value);
    ui.end_row();
}

/// A row whose value is drawn in the fault colour while it is abnormal (an e-stop
/// pressed, an end switch closed, the camera link down), so that it stands out.
fn row_alarm(ui: &mut egui::Ui, name: &str, value: String, abnormal: bool) {
    ui.label(name);
    if abnormal {
        ui.label(
            RichText::new(value)
                .monospace()
                .strong()
                .color(theme::fault(ui)),
        );
    } else {
        ui.monospace(value);
    }
    ui.end_row();
}

/// The gamepad in place of the wired joystick: which, its sticks, its dead-man.
pub(crate) fn gamepad_words(pad: &GamepadView) -> String {
    let state = &pad.state;
    if !state.pad.connected {
        return format!("not connected: {}", state.problem.as_str());
    }
    let (right, forward) = state.pad.deflection();
    format!(
        "{} ({})  steer {:+.0} %  speed {:+.0} %  dead-man {}",
        state.name.as_str(),
        state.place.as_str(),
        100.0 * right,
        100.0 * forward,
        pad.joystick.dead_man.words()
    )
}

/// Every input, in the units at the connector and what they mean.
pub fn inputs_grid(ui: &mut egui::Ui, view: &View) {
    let i = &view.status.inputs;
    let m = &view.status.measured;
    egui::Grid::new("inputs").striped(true).show(ui, |ui| {
        let estop = |released: bool| if released { "released" } else { "PRESSED" };
        let front = i.estop_front_released;
        row_alarm(ui, "E-stop front", estop(front).into(), !front);
        let back = i.estop_back_released;
        row_alarm(ui, "E-stop back", estop(back).into(), !back);
        let left = i.end_switch_left;
        row_alarm(ui, "End switch left", on_off(left).into(), left);
        let right = i.end_switch_right;
        row_alarm(ui, "End switch right", on_off(right).into(), right);
        row(ui, "Motor power", on_off(i.motor_power_present).into());
        row(ui, "Battery", format!("{:.2} V", i.battery_v));
        row(
            ui,
            "Encoder left",
            format!("{:>10} counts  {:+.3} m/s", i.enc_left_counts, m.v_left_mps),
        );
        row(
            ui,
            "Encoder right",
            format!(
                "{:>10} counts  {:+.3} m/s",
                i.enc_right_counts, m.v_right_mps
            ),
        );
        row(
            ui,
            "Encoder steering",
            format!(
                "{:>10} counts  {:+.2} deg{}",
                i.enc_steer_counts,
                m.wheel_angle_rad.to_degrees(),
                if m.calibrated {
                    ""
                } else {
                    " (not calibrated)"
                }
            ),
        );
        row(
            ui,
            "Potentiometer",
            format!(
                "{:.3} V  {:+.2} deg (filtered)",
                i.pot_v,
                m.pot_angle_filtered_rad.to_degrees()
            ),
        );
        row(
            ui,
            "Joystick",
            format!(
                "steer {:+.2} V  speed {:+.2} V  dead-man {}",
                i.joystick_steer_v,
                i.joystick_speed_v,
                if i.joystick_enable {
                    "held"
                } else {
                    "released"
                }
            ),
        );
        if let Some(pad) = &view.gamepad {
            row(ui, "Gamepad", gamepad_words(pad));
        }
    });
}

/// Every output as the supervisor commanded it in its last tick.
pub(crate) fn outputs_grid(ui: &mut egui::Ui, view: &View) {
    let o = &view.status.outputs;
    egui::Grid::new("outputs").striped(true).show(ui, |ui| {
        row(ui, "Amplifier left", format!("{:+.2} V", o.amp_left_v));
        row(ui, "Amplifier right", format!("{:+.2} V", o.amp_right_v));
        row(ui, "Amplifier steering", format!("{:+.2} V", o.amp_steer_v));
        row(ui, "Main power relay", on_off(o.main_power_on).into());
        let brake = |released: bool| if released { "released" } else { "on" };
        row(ui, "Brake left", brake(o.brake_release_left).into());
        row(ui, "Brake right", brake(o.brake_release_right).into());
        row(ui, "Tool", on_off(o.tool_on).into());
    });
}

fn link_grid(ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
    let l = &view.link;
    let c = &l.counters;
    egui::Grid::new("link").striped(true).show(ui, |ui| {
        let state = match (l.problem, l.opening) {
            (Some(problem), _) => format!("DOWN: {problem}"),
            (None, Some(step)) => step.to_string(),
            (None, None) if l.streaming => "streaming".to_string(),
            (None, None) => "connected, idle".to_string(),
        };
        row_alarm(ui, "State", state, l.problem.is_some());
        let age_s = view.now_s - l.last_row_s;
        row(
            ui,
            "Last row",
            if age_s.is_finite() {
                format!(
                    "offset {:+.3} m  angle {:+.2} deg  quality {}  ({:.2} s ago)",
                    l.last_row.offset_m,
                    l.last_row.angle_rad.to_degrees(),
                    l.last_row.quality,
                    age_s
                )
            } else {
                "none yet".to_string()
            },
        );
        row(ui, "Frames", format!("{} good", c.frames_ok));
        row(
            ui,
            "Errors",
            format!(
                "{} CRC, {} bad values, {} unknown kinds, {} gaps, {} duplicates, {} resyncs",
                c.crc_errors, c.bad_values, c.unknown_kinds, c.seq_gaps, c.duplicates, c.resyncs
            ),
        );
        ui.label("Ping round trip");
        ui.horizontal(|ui| {
            if l.ping_rtt_ms.is_nan() {
                ui.monospace(format!("none yet ({} sent)", l.pings_sent));
            } else {
                ui.monospace(format!("{:.1} ms ({} sent)", l.ping_rtt_ms, l.pings_sent));
            }
            if ui.button("Test link").clicked() {
                requests.ping_link();
            }
        });
        ui.end_row();
    });
}

fn loops_grid(ui: &mut egui::Ui, view: &View) {
    egui::Grid::new("loops").striped(true).show(ui, |ui| {
        for text in [
            "loop", "rate", "late p50", "late p99", "late max", "exec p99", "exec max", "overruns",
        ] {
            ui.label(RichText::new(text).strong());
        }
        ui.end_row();
        for (k, (name, l)) in [("supervisor", view.loops[0]), ("steer", view.loops[1])]
            .into_iter()
            .enumerate()
        {
            let colour = match loop_tone(view, k) {
                Tone::Fault => Some(theme::fault(ui)),
                Tone::Warning => Some(theme::warning(ui)),
                Tone::Plain => None,
            };
            let cell = |ui: &mut egui::Ui, text: String| match colour {
                Some(c) => ui.label(RichText::new(text).monospace().strong().color(c)),
                None => ui.monospace(text),
            };
            cell(ui, name.to_string());
            cell(ui, format!("{:.0} Hz", l.rate_hz));
            for us in [
                l.late_us.p50,
                l.late_us.p99,
                l.late_us.max,
                l.exec_us.p99,
                l.exec_us.max,
            ] {
                cell(ui, format!("{us} us"));
            }
            cell(ui, l.overruns.to_string());
            ui.end_row();
        }
    });
    // The run summary's check on the same figures, in its words (rt/liu_layland.rs).
    let check = liu_layland(&view.loops);
    let text = format!("Liu-Layland: {}", check.words());
    if check.schedulable {
        ui.label(text);
    } else {
        ui.label(RichText::new(text).strong().color(theme::fault(ui)));
    }
}

#[derive(Debug, PartialEq)]
enum Tone {
    Plain,
    Warning,
    Fault,
}

/// How loop `k`'s row looks (0: the supervisor, 1: the steer thread): a stall or a burst
/// of overruns that faulted the robot in the fault's colour, overruns that did not in
/// the warning's, so that a busy computer shows where its figures are.
fn loop_tone(view: &View, k: usize) -> Tone {
    let timing_fault = view.status.fault.is_some_and(|f| {
        matches!(
            f.cause,
            FaultCause::LateTick { .. } | FaultCause::Overruns { .. }
        )
    });
    match (k, view.loops[k].overruns) {
        (0, _) if timing_fault => Tone::Fault,
        (_, 0) => Tone::Plain,
        _ => Tone::Warning,
    }
}

/// Which sensors steer, the GNSS fix and the row filter ([steer] source gnss or fused).
pub(crate) fn sources_grid(ui: &mut egui::Ui, view: &View) {
    let (sources, r) = (&view.steer.sources, &view.steer.row);
    let autonomous = view.status.mode == crate::state::modes::Mode::Autonomous;
    egui::Grid::new("sources").striped(true).show(ui, |ui| {
        let steering = if autonomous {
            sources.steering.words().to_string()
        } else {
            format!("{} (in autonomous mode)", sources.steering.words())
        };
        row(ui, "Steering by", steering);
        let quality = mechweed_hw::nmea::FixQuality::from_code(r.gnss_quality);
        let fix = if r.gnss_quality == 0 && r.gnss_satellites == 0 {
            "no fix received".to_string()
        } else {
            let sd = r
                .gnss_sd_m
                .map_or("no s.d. sent".to_string(), |m| format!("s.d. {:.1} cm", m * 100.0));
            format!(
                "{}  {} satellites  {sd}",
                quality.words(),
                r.gnss_satellites
            )
        };
        row(ui, "GNSS", fix);
        let filter = match &r.filter {
            Some(f) => format!(
                "row {:+.1} cm +- {:.1} cm at the rear axle  heading {:+.2} deg  curvature {:+.4} 1/m  map bias {:+.1} cm",
                f.offset_m * 100.0,
                f.offset_sd_m * 100.0,
                f.heading_rad.to_degrees(),
                f.curvature_per_m,
                f.map_bias_m * 100.0
            ),
            None => "not running ([steer] source = camera)".to_string(),
        };
        row(ui, "Row filter", filter);
        if let Some(f) = &r.filter {
            row(
                ui,
                "Gate rejections",
                format!("camera {}  GNSS {}", f.camera_rejected, f.gnss_rejected),
            );
        }
    });
}

pub fn show(ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
    ui.columns(2, |cols| {
        cols[0].heading("Inputs");
        inputs_grid(&mut cols[0], view);
        cols[1].heading("Outputs (as commanded)");
        outputs_grid(&mut cols[1], view);
    });
    ui.separator();
    ui.heading("Camera link");
    link_grid(ui, view, requests);
    ui.separator();
    ui.heading("GNSS and the row filter");
    sources_grid(ui, view);
    ui.separator();
    ui.heading("Loops");
    loops_grid(ui, view);
    ui.separator();
    ui.heading("Bus");
    match &view.remote {
        // This window watches the robot over the bus: its link, not the robot's bus.
        Some(link) => {
            ui.label(super::header::remote_line(link));
            ui.label(format!(
                "{}; messages that could not be read: {}, under the wrong key: {}; session opened again {} times",
                view.bus_endpoints, link.refused, link.wrong_key, link.reopened
            ));
        }
        None => {
            ui.label(view.bus.line());
            if view.bus.state != crate::bus::BusState::Off {
                ui.label(&view.bus_endpoints);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::status::FaultRecord;

    #[test]
    fn overruns_are_a_warning_and_a_stall_that_faulted_is_the_faults_colour() {
        let mut view = View::default();
        assert_eq!(loop_tone(&view, 0), Tone::Plain);
        view.loops[0].overruns = 12;
        assert_eq!(loop_tone(&view, 0), Tone::Warning);
        assert_eq!(loop_tone(&view, 1), Tone::Plain, "the steer loop had none");
        view.status.fault = Some(FaultRecord {
            cause: FaultCause::LateTick {
                late_ms: 97.0,
                limit_ms: 50.0,
                load: None,
            },
            t_s: 3.0,
            tick_seen: 300,
            tick_safe: 300,
            came_back_after_s: None,
        });
        assert_eq!(loop_tone(&view, 0), Tone::Fault);
    }
}

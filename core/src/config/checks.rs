//! Settings that must agree with each other. Each one is in range on its own, but
//! together they would make the robot unsafe or make a fault check blind: a speed the
//! supervisor would quietly cut, a back-off angle beyond the end switches, an amplifier
//! limit the card's range switch clips without notice. Each error names every key
//! involved with its value. A check is skipped when one of its keys could not be read
//! (that key has its own error already).

use mechweed_hw::cards::wiring::AnalogOut;

use super::reader::Reader;
use super::{FILTER_MAX_STEP_M, Settings};

/// `[section] key = value`, as the errors name a setting.
fn named(section: &str, key: &str, value: impl std::fmt::Display) -> String {
    format!("[{section}] {key} = {value}")
}

/// Record `what` unless `ok` holds or one of `keys` could not be read.
fn require(r: &mut Reader, ok: bool, keys: &[(&str, &str)], what: impl FnOnce() -> String) {
    if !ok && r.all_read(keys) {
        r.cross_error(keys, what());
    }
}

pub(super) fn across(s: &Settings, r: &mut Reader) {
    potentiometer(s, r);
    amplifiers(s, r);
    speeds(s, r);
    joystick(s, r);
    end_switches(s, r);
    threads(s, r);
    rows_need_the_bus(s, r);
    gnss_fix_age(s, r);
    bus_open_only_with_tls(s, r);
}

/// A bus beyond loopback without TLS lets anyone on that network drive the robot:
/// listening there, connecting there, or finding peers by multicast.
fn bus_open_only_with_tls(s: &Settings, r: &mut Reader) {
    let bus = &s.bus;
    if !bus.enabled {
        return;
    }
    let (tls, trusted) = (bus.tls.is_some(), bus.trusted_network);
    for (key, endpoints) in [("listen", &bus.listen), ("connect", &bus.connect)] {
        let setting = format!("[bus] {key}");
        if let Some(why) = super::listen_refusal(endpoints, tls, trusted, &setting) {
            require(r, false, &[("bus", key), ("bus", "tls_ca")], || why);
        }
    }
    if bus.multicast && !tls && !trusted {
        require(r, false, &[("bus", "multicast"), ("bus", "tls_ca")], || {
            "[bus] multicast = yes finds and answers peers on every network without TLS: anyone there could drive the robot. Use the cluster's keys (tls_ca, tls_cert, tls_key), or, only on a network you trust, set trusted_network = yes".to_string()
        });
    }
}

/// A GNSS fix reaches the row filter up to its latency and a steer period after it was
/// measured, and the filter relates it to the robot now over at most
/// FILTER_MAX_STEP_M of travel: at the top speed every fix would otherwise be refused.
fn gnss_fix_age(s: &Settings, r: &mut Reader) {
    let age_s = s.gnss.latency_s + 1.0 / s.steer.rate_hz;
    let travel_m = age_s * s.supervisor.max_speed_mps;
    let keys = [
        ("steer", "source"),
        ("gnss", "latency_s"),
        ("steer", "rate_hz"),
        ("supervisor", "max_speed_mps"),
    ];
    let ok = s.sources.source == super::SteerSource::Camera || travel_m < FILTER_MAX_STEP_M;
    require(r, ok, &keys, || {
        format!(
            "{} and a steer period of {} make a GNSS fix {age_s:.2} s old when the row \
             filter takes it: at {} that is {travel_m:.2} m of travel, beyond the \
             {FILTER_MAX_STEP_M} m the filter relates a fix over",
            named("gnss", "latency_s", s.gnss.latency_s),
            named("steer", "rate_hz", s.steer.rate_hz),
            named("supervisor", "max_speed_mps", s.supervisor.max_speed_mps)
        )
    });
}

/// Row estimates from the bus need the bus.
fn rows_need_the_bus(s: &Settings, r: &mut Reader) {
    let keys = [("camera", "port"), ("bus", "enabled")];
    require(
        r,
        s.camera_port != super::CameraPort::Bus || s.bus.enabled,
        &keys,
        || {
            format!(
                "{} takes the row estimates from the bus, but {}: set [bus] enabled = yes",
                named("camera", "port", "bus"),
                named("bus", "enabled", "no")
            )
        },
    );
}

/// The band of good potentiometer readings is not empty and holds the whole steering
/// range, or steering to the limit would be a fault.
fn potentiometer(s: &Settings, r: &mut Reader) {
    let (f, robot) = (&s.faults, &s.robot);
    let band = [("faults", "pot_min_v"), ("faults", "pot_max_v")];
    require(r, f.pot_min_v < f.pot_max_v, &band, || {
        format!(
            "{} must be below {}: no potentiometer reading would count as good",
            named("faults", "pot_min_v", f.pot_min_v),
            named("faults", "pot_max_v", f.pot_max_v)
        )
    });
    if f.pot_min_v >= f.pot_max_v {
        return;
    }
    let swing_v = robot.pot_v_per_deg * robot.max_wheel_angle_deg;
    let (low_v, high_v) = (robot.pot_centre_v - swing_v, robot.pot_centre_v + swing_v);
    let keys = [
        ("faults", "pot_min_v"),
        ("faults", "pot_max_v"),
        ("robot", "pot_centre_v"),
        ("robot", "pot_v_per_deg"),
        ("robot", "max_wheel_angle_deg"),
    ];
    require(
        r,
        f.pot_min_v < low_v && high_v < f.pot_max_v,
        &keys,
        || {
            format!(
                "the potentiometer reads {low_v:.2} to {high_v:.2} V over the steering range \
             ({}, {}, {}), not inside {} to {}: steering to the limit would be the fault \
             'potentiometer out of range'",
                named("robot", "pot_centre_v", robot.pot_centre_v),
                named("robot", "pot_v_per_deg", robot.pot_v_per_deg),
                named("robot", "max_wheel_angle_deg", robot.max_wheel_angle_deg),
                named("faults", "pot_min_v", f.pot_min_v),
                named("faults", "pot_max_v", f.pot_max_v)
            )
        },
    );
}

/// Each amplifier's DDA06 output has a bipolar range switch wide enough for the
/// regulator's limit (the card clips silently otherwise), and that limit is above the
/// voltage at which the encoder-stuck check starts looking (or it never looks).
fn amplifiers(s: &Settings, r: &mut Reader) {
    let amps: [(&str, AnalogOut, &str, f64, &str); 3] = [
        (
            "amp_left_v",
            s.io.amp_left_v,
            "pid.left",
            s.pid_left.out_max_v,
            "left wheel",
        ),
        (
            "amp_right_v",
            s.io.amp_right_v,
            "pid.right",
            s.pid_right.out_max_v,
            "right wheel",
        ),
        (
            "amp_steer_v",
            s.io.amp_steer_v,
            "pid.steer",
            s.pid_steer.out_max_v,
            "steering",
        ),
    ];
    for (key, out, pid, out_max_v, what) in amps {
        let Some(range) = s.cards.dda06_ranges.get(usize::from(out.channel)) else {
            continue;
        };
        let ao = out.channel;
        let keys = [("hw", "dda06_ranges_v"), ("io", key), (pid, "out_max_v")];
        let switch = format!("[hw] dda06_ranges_v sets AO{ao} to {} V", range.name());
        require(r, range.bipolar(), &keys, || {
            format!(
                "{switch}, but [io] {key} = dda06 ao {ao} drives the {what} amplifier, which \
                 needs negative volts too: set the card's switch and dda06_ranges_v to +-10"
            )
        });
        let card_v = out_max_v * out.scale.abs();
        let fits = card_v <= range.full_scale_v() + 1e-9;
        require(r, !range.bipolar() || fits, &keys, || {
            format!(
                "{switch}, but {} on [io] {key} = dda06 ao {ao}, scale {} needs +-{card_v} V: \
                 the card would clip the {what} amplifier without notice; set the switch and \
                 dda06_ranges_v to +-10, or lower out_max_v",
                named(pid, "out_max_v", out_max_v),
                out.scale
            )
        });
        let stuck_v = s.faults.encoder_stuck_v;
        let keys = [("faults", "encoder_stuck_v"), (pid, "out_max_v")];
        require(r, stuck_v < out_max_v, &keys, || {
            format!(
                "{} must be below {}: the amplifier never gets there, so a stuck {what} \
                 encoder would never be noticed",
                named("faults", "encoder_stuck_v", stuck_v),
                named(pid, "out_max_v", out_max_v)
            )
        });
    }
}

/// No mode asks for more speed than the supervisor allows.
fn speeds(s: &Settings, r: &mut Reader) {
    let max = s.supervisor.max_speed_mps;
    let asked = [
        ("steer", "speed_mps", s.steer.speed_mps),
        ("joystick", "max_speed_mps", s.joystick.max_speed_mps),
    ];
    for (section, key, speed) in asked {
        let keys = [(section, key), ("supervisor", "max_speed_mps")];
        require(r, speed <= max, &keys, || {
            format!(
                "{} is above {}, the highest speed any mode may ask for",
                named(section, key, speed),
                named("supervisor", "max_speed_mps", max)
            )
        });
    }
}

/// The joystick's dead band is smaller than its full scale (else the stick jumps from
/// standstill to full speed) and it asks for no angle the controller does not command.
fn joystick(s: &Settings, r: &mut Reader) {
    let j = &s.joystick;
    let keys = [("joystick", "deadband_v"), ("joystick", "full_scale_v")];
    require(r, j.deadband_v < j.full_scale_v, &keys, || {
        format!(
            "{} must be below {}: the stick would jump from standstill to full deflection",
            named("joystick", "deadband_v", j.deadband_v),
            named("joystick", "full_scale_v", j.full_scale_v)
        )
    });
    let max_deg = s.robot.max_wheel_angle_deg;
    let keys = [
        ("joystick", "max_angle_deg"),
        ("robot", "max_wheel_angle_deg"),
    ];
    require(r, j.max_angle_deg <= max_deg, &keys, || {
        format!(
            "{} is above {}, the largest wheel angle the controller commands",
            named("joystick", "max_angle_deg", j.max_angle_deg),
            named("robot", "max_wheel_angle_deg", max_deg)
        )
    });
    let keys = [("joystick", "axis_fault_v"), ("joystick", "full_scale_v")];
    require(r, j.axis_fault_v > j.full_scale_v, &keys, || {
        format!(
            "{} must be above {}: a joystick pushed fully would be a fault",
            named("joystick", "axis_fault_v", j.axis_fault_v),
            named("joystick", "full_scale_v", j.full_scale_v)
        )
    });
    let pad = &s.gamepad;
    let keys = [
        ("joystick", "gamepad_speed_axis"),
        ("joystick", "gamepad_steer_axis"),
    ];
    require(r, pad.speed_axis != pad.steer_axis, &keys, || {
        format!(
            "[joystick] gamepad_speed_axis and gamepad_steer_axis are both {:?}: steering would drive",
            pad.speed_axis
        )
    });
}

/// The end-switch procedure steers back off a switch towards the centre, so its angle
/// lies inside the commanded range, which lies inside the end switches ([robot] for the
/// real robot, [sim] for the simulated one), which close before the mechanical stop.
fn end_switches(s: &Settings, r: &mut Reader) {
    let back = ("steer", "endswitch_back_deg", s.steer.endswitch_back_deg);
    let max = ("robot", "max_wheel_angle_deg", s.robot.max_wheel_angle_deg);
    let robot_switch = ("robot", "end_switch_deg", s.robot.end_switch_deg);
    let switch = ("sim", "end_switch_deg", s.sim.end_switch_deg);
    let stop = ("sim", "steer_limit_deg", s.sim.steer_limit_deg);
    let why_back = "the end-switch procedure steers back off the switch towards the centre";
    let pairs = [
        (back, max, why_back),
        (back, robot_switch, why_back),
        (back, switch, why_back),
        (
            max,
            robot_switch,
            "the controller would steer into the end switches in normal driving",
        ),
        (
            max,
            switch,
            "the controller would steer into the end switches in normal driving",
        ),
        (
            switch,
            stop,
            "the end switches must close before the mechanical stop",
        ),
    ];
    for ((s1, k1, v1), (s2, k2, v2), why) in pairs {
        require(r, v1 < v2, &[(s1, k1), (s2, k2)], || {
            format!(
                "{} must be below {}: {why}",
                named(s1, k1, v1),
                named(s2, k2, v2)
            )
        });
    }
}

/// The supervisor runs before the threads it watches, and the steer thread beats often
/// enough not to be taken for stopped.
fn threads(s: &Settings, r: &mut Reader) {
    let rt = &s.rt;
    let others = [
        ("steer_priority", rt.steer_priority),
        ("camlink_priority", rt.camlink_priority),
    ];
    for (key, priority) in others {
        let ok = priority == 0 || priority < rt.supervisor_priority;
        let keys = [("rt", key), ("rt", "supervisor_priority")];
        require(r, ok, &keys, || {
            format!(
                "{} must be below {} (or 0, normal scheduling): the supervisor watches the \
                 other threads and must run first",
                named("rt", key, priority),
                named("rt", "supervisor_priority", rt.supervisor_priority)
            )
        });
    }
    let apart = rt.gui_cpu < 0 || rt.gui_cpu != rt.supervisor_cpu;
    let keys = [("rt", "gui_cpu"), ("rt", "supervisor_cpu")];
    require(r, apart, &keys, || {
        format!(
            "{} is the supervisor's own CPU: the GUI is pinned to keep its drawing away \
             from the supervisor, so give it another CPU (or -1, any)",
            named("rt", "gui_cpu", rt.gui_cpu)
        )
    });
    let periods_s = 2.0 / s.steer.rate_hz;
    let keys = [("rt", "heartbeat_timeout_s"), ("steer", "rate_hz")];
    require(r, rt.heartbeat_timeout_s >= periods_s, &keys, || {
        format!(
            "{} is shorter than two periods of the steer thread ({}: {periods_s} s), which \
             beats once a period: it would be taken for stopped",
            named("rt", "heartbeat_timeout_s", rt.heartbeat_timeout_s),
            named("steer", "rate_hz", s.steer.rate_hz)
        )
    });
    let stall_s = rt.max_late_periods / s.supervisor.rate_hz;
    let keys = [("rt", "max_late_periods"), ("supervisor", "rate_hz")];
    require(r, stall_s <= MAX_STALL_S, &keys, || {
        format!(
            "{} lets one stall of the supervisor last {stall_s:.3} s at {}: at most {MAX_STALL_S} s, as the amplifiers drive unwatched meanwhile",
            named("rt", "max_late_periods", rt.max_late_periods),
            named("supervisor", "rate_hz", s.supervisor.rate_hz)
        )
    });
}

/// The longest single stall of the supervisor a setting may allow, s: at 1 m/s the
/// robot drives 20 cm unwatched.
const MAX_STALL_S: f64 = 0.2;

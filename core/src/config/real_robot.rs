//! What the real robot must not have: with `[hw] backend = cards` the outputs go to the
//! real amplifiers, so nothing that steers or drives them may be simulated. A row from
//! the simulated camera, a fix from the simulated receiver or a line from the simulated
//! field's map would steer a real robot along a row that is not there; a scripted
//! operator would power it up with nobody there. Each is refused when the file is read,
//! so `check-config` and every start say the same, naming the key and its line.
//!
//! `check-config --real-robot` asks more: that the file is meant for the real robot at
//! all (`[hw] backend = cards`), so that a technician can check a file before taking
//! it to the robot.

use super::reader::Reader;
use super::{Backend, CameraPort, GnssPort, MapSource, Settings, SteerSource};

/// Every rule of this file, as a file is read.
pub(super) fn check(s: &Settings, r: &mut Reader) {
    if s.backend != Backend::Cards {
        return;
    }
    let cards = "with [hw] backend = cards the outputs go to the real robot";
    if s.camera_port == CameraPort::Sim {
        refuse(
            r,
            &[("camera", "port"), ("hw", "backend")],
            format!(
                "[camera] port = sim is the simulated camera computer, and {cards}: it would steer the real robot along a simulated row. Set [camera] port to the camera computer's serial device (e.g. /dev/ttyS0), tcp://HOST:PORT or bus"
            ),
        );
    }
    if s.gnss.port == GnssPort::Link(CameraPort::Sim) {
        refuse(
            r,
            &[("gnss", "port"), ("hw", "backend")],
            format!(
                "[gnss] port = sim is the simulated receiver, and {cards}: it would steer the real robot by simulated fixes. Set [gnss] port to the receiver's serial device (e.g. /dev/ttyACM0) or tcp://HOST:PORT, or to none with [steer] source = camera"
            ),
        );
    }
    // The map is read only where GNSS steers or a receiver is there to be placed on it.
    let map_used = s.gnss.port != GnssPort::None || s.sources.source != SteerSource::Camera;
    if map_used && s.gnss.map == MapSource::Sim {
        refuse(
            r,
            &[("gnss", "map"), ("hw", "backend")],
            format!(
                "[gnss] map = sim is the simulated field's map, and {cards}: the real field's rows are elsewhere. Set [gnss] map to the field's row map file (mechweed teach writes one)"
            ),
        );
    }
    no_script(s, r);
}

/// Nothing powers the real robot up without a person: the scripted operator of
/// [sim] events (power_up, mode) is for the simulated robot only.
fn no_script(s: &Settings, r: &mut Reader) {
    let scripted: Vec<String> = (s.sim.events.iter())
        .filter(|e| e.action.is_operator())
        .map(|e| e.to_string())
        .collect();
    if !scripted.is_empty() {
        refuse(
            r,
            &[("sim", "events"), ("hw", "backend")],
            format!(
                "[sim] events has {}, which would power up or drive the real robot with nobody there ([hw] backend = cards): remove the operator events (power_up, mode)",
                scripted.join(", ")
            ),
        );
    }
}

/// `check-config --real-robot`: the file must be meant for the real robot.
pub(super) fn require_cards(s: &Settings, r: &mut Reader) {
    if s.backend != Backend::Cards {
        refuse(
            r,
            &[("hw", "backend")],
            "[hw] backend = sim runs the simulated robot: for the real robot set [hw] backend = cards, then every setting the real robot needs (docs/robot-pc.md, \"Settings for the real robot\")".to_string(),
        );
    }
}

/// The error, at the first key's line, unless one of `keys` could not be read (a key
/// that could not be read has its own error, and its stand-in value is no setting).
fn refuse(r: &mut Reader, keys: &[(&str, &str)], what: String) {
    if r.all_read(keys) {
        r.cross_error(keys, what);
    }
}

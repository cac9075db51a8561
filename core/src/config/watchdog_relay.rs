//! [io] watchdog_relay: whether the real robot has the charge-pump relay in its e-stop
//! chain (docs/robot-pc.md, section 6). When the program is killed or hangs, or the
//! computer stops, the cards keep their last outputs (contactor closed, brakes
//! released, amplifiers driven); only that relay, fed by [io] watchdog, stops the
//! robot then. So with `[hw] backend = cards` a file without a watchdog line is refused,
//! unless it says in so many words that the robot has no relay and that this is accepted;
//! every start then says so.

use super::reader::Reader;
use super::{Backend, Settings};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchdogRelay {
    /// The relay is there, on the [io] watchdog line (shipped).
    Fitted,
    /// No relay: a killed or hung program leaves the cards' last outputs (accepted).
    NoneAccepted,
}

/// The words of the start line for a robot without the relay.
pub const NO_RELAY: &str = "no watchdog relay ([io] watchdog_relay = none_accepted): if this program is killed or hangs, or the computer stops, the cards keep their last outputs (contactor closed, brakes released, amplifiers driven) until someone presses an e-stop";

/// [io] watchdog_relay: optional; a file without it has the relay, as shipped.
pub(super) fn load(r: &mut Reader) -> WatchdogRelay {
    if r.optional("io", "watchdog_relay").is_none() {
        return WatchdogRelay::Fitted;
    }
    let choices = [WatchdogRelay::Fitted, WatchdogRelay::NoneAccepted];
    choices[r.choice("io", "watchdog_relay", &["fitted", "none_accepted"])]
}

/// On the cards, no watchdog line needs the relay's absence accepted.
pub(super) fn check(s: &Settings, r: &mut Reader) {
    let keys = [
        ("io", "watchdog"),
        ("hw", "backend"),
        ("io", "watchdog_relay"),
    ];
    let unwatched = s.backend == Backend::Cards && s.io.watchdog.is_none();
    // A file without watchdog_relay has it fitted: only the first two keys then.
    let keys = if r.written("io", "watchdog_relay").is_some() {
        &keys[..]
    } else {
        &keys[..2]
    };
    if unwatched && s.watchdog_relay == WatchdogRelay::Fitted && r.all_read(keys) {
        r.cross_error(
            keys,
            "[io] watchdog = none, and with [hw] backend = cards the charge-pump relay on that line is the only thing that stops the robot when this program is killed or hangs: set [io] watchdog to the relay's line (docs/robot-pc.md, section 6), or, on a robot without one, [io] watchdog_relay = none_accepted".to_string(),
        );
    }
}

//! `bench loop --gui --press-space S`: how long the operator's Space key (HALT) takes
//! from the X server to the supervisor. Every S seconds, while the robot drives
//! autonomously, it presses Space through the X server's test extension, as a keyboard
//! would, and takes the time from the press to the supervisor tick that went to Halt
//! (the first status in Halt carries that tick's time); then it puts the robot back in
//! Autonomous and waits for the next press.
//!
//! A bare X server such as Xvfb has no window manager to give the window focus: the
//! presser gives it, to the top-level window named "mechweed", before each press.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use x11rb::connection::Connection;
use x11rb::protocol::xproto::{ConnectionExt as _, InputFocus, KEY_PRESS_EVENT, KEY_RELEASE_EVENT};
use x11rb::protocol::xtest::ConnectionExt as _;
use x11rb::wrapper::ConnectionExt as _;

use crate::gui::x11_focus::{TITLE, window_named};
use crate::state::modes::Mode;
use crate::state::operator::OperatorScript;
use crate::state::request_channel::SupervisorHandle;

/// The keysym of the space bar.
const XK_SPACE: u32 = 0x20;

/// Press Space every `every_s` until `done`; gives each press's time from the key to the
/// supervisor's HALT, ms (a press the supervisor did not take within 2 s is left out
/// and said).
pub(crate) fn press_space(
    supervisor: SupervisorHandle,
    clock: Instant,
    every_s: f64,
    done: Arc<AtomicBool>,
) -> Result<Vec<f64>, String> {
    let (conn, screen) =
        x11rb::connect(None).map_err(|e| format!("cannot reach the X server: {e}"))?;
    let root = conn.setup().roots[screen].root;
    let keycode = space_keycode(&conn)?;
    let fail = |e: &dyn std::fmt::Display| format!("X server: {e}");
    let now_s = || clock.elapsed().as_secs_f64();
    let mut latencies_ms = Vec::new();
    let mut presses = 0u32;
    while !done.load(Ordering::Relaxed) {
        if !back_to_autonomous(&supervisor, &done) {
            break;
        }
        // Spread the presses over the GUI's frame phases: a press just after a frame
        // and one in the middle of drawing wait differently.
        let wait_s = every_s * (0.75 + 0.5 * ((presses * 7 % 11) as f64 / 10.0));
        std::thread::sleep(Duration::from_secs_f64(wait_s));
        if done.load(Ordering::Relaxed) {
            break;
        }
        let window = window_named(&conn, root, TITLE)?
            .ok_or_else(|| format!("no window named {TITLE} on the X server"))?;
        conn.set_input_focus(InputFocus::PARENT, window, x11rb::CURRENT_TIME)
            .map_err(|e| fail(&e))?;
        conn.sync().map_err(|e| fail(&e))?;
        let pressed_s = now_s();
        for kind in [KEY_PRESS_EVENT, KEY_RELEASE_EVENT] {
            conn.xtest_fake_input(kind, keycode, x11rb::CURRENT_TIME, root, 0, 0, 0)
                .map_err(|e| fail(&e))?;
        }
        conn.flush().map_err(|e| fail(&e))?;
        presses += 1;
        // The first status in Halt is from the tick that took the request.
        let give_up = Instant::now() + Duration::from_secs(2);
        loop {
            let status = supervisor.status.snapshot();
            if status.mode == Mode::Halt {
                latencies_ms.push((status.t_s - pressed_s) * 1e3);
                break;
            }
            if Instant::now() > give_up || status.mode == Mode::Fault {
                println!(
                    "Space press {presses}: no HALT within 2 s (mode {})",
                    status.mode
                );
                break;
            }
            std::thread::sleep(Duration::from_micros(500));
        }
    }
    Ok(latencies_ms)
}

/// The keycode the X server gives the space bar.
fn space_keycode(conn: &impl Connection) -> Result<u8, String> {
    let setup = conn.setup();
    let (first, last) = (setup.min_keycode, setup.max_keycode);
    let map = conn
        .get_keyboard_mapping(first, last - first + 1)
        .map_err(|e| format!("X server: {e}"))?
        .reply()
        .map_err(|e| format!("X server: {e}"))?;
    let per = usize::from(map.keysyms_per_keycode).max(1);
    map.keysyms
        .chunks(per)
        .position(|syms| syms.contains(&XK_SPACE))
        .map(|k| first + k as u8)
        .ok_or_else(|| "the X server's keyboard has no space bar".to_string())
}

/// Ask for Autonomous (powering up first, as the operator script does) until the
/// robot is in it; false if it faulted or the bench ended.
fn back_to_autonomous(supervisor: &SupervisorHandle, done: &AtomicBool) -> bool {
    let mut script = OperatorScript::new(&[], Mode::Autonomous);
    while !done.load(Ordering::Relaxed) {
        let status = supervisor.status.snapshot();
        match status.mode {
            Mode::Autonomous => return true,
            Mode::Fault => return false,
            _ => {
                if let Some(request) = script.due(0.0, &status) {
                    let _ = supervisor.request(request);
                }
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    false
}

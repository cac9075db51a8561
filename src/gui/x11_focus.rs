//! The keyboard for the operator's window at start, on X11. A robot computer often runs
//! the GUI on a bare X server with no window manager: nobody gives the new window the
//! keyboard, and egui's own request (`ViewportCommand::Focus`) asks the window manager
//! that is not there. Space = HALT would then do nothing until someone clicks. So the
//! window takes the keyboard from the X server itself, once, as it appears.

use std::time::{Duration, Instant};

use x11rb::connection::Connection;
use x11rb::protocol::xproto::{AtomEnum, ConnectionExt as _, InputFocus, Window};

/// The window's title, as eframe names it (gui/mod.rs).
pub(crate) const TITLE: &str = "mechweed";
/// How long to look for the window after the first frame, s.
const LOOK_FOR_S: f64 = 3.0;

/// Give the keyboard to the top-level window named `TITLE`, trying for a few seconds
/// while it is mapped. Not on X11 (Wayland, no DISPLAY): nothing to do.
pub(crate) fn take_keyboard() -> Result<(), String> {
    if std::env::var_os("DISPLAY").is_none() || std::env::var_os("WAYLAND_DISPLAY").is_some() {
        return Ok(());
    }
    let (conn, screen) =
        x11rb::connect(None).map_err(|e| format!("cannot reach the X server: {e}"))?;
    let root = conn.setup().roots[screen].root;
    let end = Instant::now() + Duration::from_secs_f64(LOOK_FOR_S);
    loop {
        // Refused until the window is viewable (BadMatch): tried again.
        let given = match window_named(&conn, root, TITLE)? {
            Some(window) => conn
                .set_input_focus(InputFocus::PARENT, window, x11rb::CURRENT_TIME)
                .map_err(|e| e.to_string())?
                .check()
                .is_ok(),
            None => false,
        };
        if given {
            return Ok(());
        }
        if Instant::now() > end {
            return Err(format!(
                "no viewable window named {TITLE} within {LOOK_FOR_S} s"
            ));
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The window named `title` among the root's children, or theirs: a window manager
/// wraps each window in a frame of its own, so on a desktop it is a grandchild.
pub(crate) fn window_named(
    conn: &impl Connection,
    root: Window,
    title: &str,
) -> Result<Option<Window>, String> {
    let fail = |e: &dyn std::fmt::Display| format!("X server: {e}");
    let children = |of: Window| -> Result<Vec<Window>, String> {
        let tree = conn.query_tree(of).map_err(|e| fail(&e))?;
        Ok(tree.reply().map_err(|e| fail(&e))?.children)
    };
    let named = |window: Window| -> Result<bool, String> {
        let name = conn
            .get_property(false, window, AtomEnum::WM_NAME, AtomEnum::ANY, 0, 64)
            .map_err(|e| fail(&e))?
            .reply()
            .map_err(|e| fail(&e))?;
        Ok(name.value == title.as_bytes())
    };
    for top in children(root)? {
        if named(top)? {
            return Ok(Some(top));
        }
        for inner in children(top)? {
            if named(inner)? {
                return Ok(Some(inner));
            }
        }
    }
    Ok(None)
}

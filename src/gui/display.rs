//! Is there a display to open the operator GUI on? Asked before anything starts, so that
//! a stale `DISPLAY` (a desktop session that has ended, an SSH session without X
//! forwarding) stops with a message before a controller runs or a record is written,
//! rather than failing inside the window library after the run has begun.

use std::os::unix::net::UnixStream;
use std::path::PathBuf;
use std::time::Duration;

/// Why there is no window to open, if there is none (without advice: `run` and
/// `bench loop` advise differently).
pub fn display_missing() -> Option<String> {
    let var = |name: &str| std::env::var(name).ok().filter(|v| !v.is_empty());
    let (x, wayland) = (var("DISPLAY"), var("WAYLAND_DISPLAY"));
    if x.is_none() && wayland.is_none() {
        return Some(
            "no display for the operator GUI (neither DISPLAY nor WAYLAND_DISPLAY is set)"
                .to_string(),
        );
    }
    let wayland_why = wayland.as_deref().and_then(wayland_missing);
    let x_why = x.as_deref().and_then(x_missing);
    // Either display that answers is enough: the window library tries both.
    let answers = |set: &Option<String>, why: &Option<String>| set.is_some() && why.is_none();
    if answers(&wayland, &wayland_why) || answers(&x, &x_why) {
        return None;
    }
    let reasons: Vec<String> = [wayland_why, x_why].into_iter().flatten().collect();
    Some(reasons.join(", and "))
}

/// The same words when the window library fails after all (the check above passed, but
/// the server refused): its own message quotes source files the user has no use for.
pub fn window_failed() -> String {
    let display = std::env::var("DISPLAY").unwrap_or_default();
    let wayland = std::env::var("WAYLAND_DISPLAY").unwrap_or_default();
    match (display.is_empty(), wayland.is_empty()) {
        (false, _) => format!("cannot open a window on DISPLAY={display}"),
        (true, false) => format!("cannot open a window on WAYLAND_DISPLAY={wayland}"),
        (true, true) => "cannot open a window: no display".to_string(),
    }
}

/// An X display `[host]:N[.S]`: a local one answers on /tmp/.X11-unix/XN, a remote one
/// (SSH forwarding: `localhost:10`) on TCP port 6000 + N.
fn x_missing(display: &str) -> Option<String> {
    let cannot = |why: String| Some(format!("cannot open a window on DISPLAY={display}: {why}"));
    let Some((host, rest)) = display.rsplit_once(':') else {
        return cannot("not of the form :N or HOST:N".to_string());
    };
    let number = rest.split('.').next().unwrap_or("");
    let Ok(n) = number.parse::<u16>() else {
        return cannot("not of the form :N or HOST:N".to_string());
    };
    if host.is_empty() || host == "unix" {
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        match UnixStream::connect(&socket) {
            Ok(_) => None,
            Err(e) => cannot(format!("no X server answers at {} ({e})", socket.display())),
        }
    } else {
        let port = 6000u32 + u32::from(n);
        let answered = std::net::ToSocketAddrs::to_socket_addrs(&(host, port as u16))
            .ok()
            .into_iter()
            .flatten()
            .any(|a| std::net::TcpStream::connect_timeout(&a, Duration::from_secs(1)).is_ok());
        if answered {
            None
        } else {
            cannot(format!("no X server answers on {host} port {port}"))
        }
    }
}

/// A Wayland display: a socket path, absolute or in XDG_RUNTIME_DIR.
fn wayland_missing(name: &str) -> Option<String> {
    let socket = if name.starts_with('/') {
        PathBuf::from(name)
    } else {
        match std::env::var_os("XDG_RUNTIME_DIR") {
            Some(dir) => PathBuf::from(dir).join(name),
            None => {
                return Some(format!(
                    "cannot open a window on WAYLAND_DISPLAY={name}: XDG_RUNTIME_DIR is not set"
                ));
            }
        }
    };
    match UnixStream::connect(&socket) {
        Ok(_) => None,
        Err(e) => Some(format!(
            "cannot open a window on WAYLAND_DISPLAY={name}: no Wayland server answers at {} ({e})",
            socket.display()
        )),
    }
}

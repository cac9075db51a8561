//! The devices robot.ini names: each card's register file, each serial port, the
//! gamepad. Nothing is written: a card's file is opened for reading and writing and
//! closed, a serial port only asked about (opening one can raise its control lines).

use std::ffi::CString;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::FileTypeExt;
use std::path::Path;

use mechweed_hw::cards::pci::{self, CardKind, CardLocation};

use super::{Check, Level, Machine};
use crate::config::{Backend, CameraPort, GamepadDevice, GnssPort, JoystickSource, Settings};

pub(super) fn checks(m: &Machine, s: &Settings) -> Vec<Check> {
    let mut checks = Vec::new();
    match s.backend {
        Backend::Sim => checks.push(Check::ok(
            "cards",
            "[hw] backend = sim: the simulated robot needs no cards",
        )),
        Backend::Cards => {
            for kind in CardKind::ALL {
                checks.push(card(m, kind, s.cards.location(kind)));
            }
        }
    }
    if let CameraPort::Serial { path, .. } = &s.camera_port {
        checks.push(serial("camera_port", "[camera] port", Path::new(path)));
    }
    if let GnssPort::Link(CameraPort::Serial { path, .. }) = &s.gnss.port {
        checks.push(serial("gnss_port", "[gnss] port", Path::new(path)));
    }
    if s.joystick.source == JoystickSource::Gamepad {
        checks.push(gamepad(m, &s.gamepad.device));
    }
    checks
}

/// A card's name for scripts: card_das08, card_dda06, card_quad04.
fn card_check(kind: CardKind) -> &'static str {
    match kind {
        CardKind::Das08 => "card_das08",
        CardKind::Dda06 => "card_dda06",
        CardKind::Quad04 => "card_quad04",
    }
}

const UDEV_FIX: &str = "the package's udev rule (/usr/lib/udev/rules.d/60-mechweed-cards.rules) gives group mechweed the cards' files: be in that group (sudo adduser USER mechweed, then log in again), and 'sudo udevadm trigger --action=add --subsystem-match=pci' if the card was there before the package";

fn card(m: &Machine, kind: CardKind, location: &CardLocation) -> Check {
    let name = card_check(kind);
    let path = match location {
        CardLocation::PortBase(base) => {
            let path = m.path("/dev/port");
            return match usable(&path) {
                Ok(()) => Check::ok(
                    name,
                    format!(
                        "{} at I/O port {base:#06x}: {} readable and writable (the program also needs CAP_SYS_RAWIO)",
                        kind.name(),
                        path.display()
                    ),
                ),
                Err(why) => Check::new(
                    name,
                    Level::Fail,
                    format!("{}: {}: {why}", kind.name(), path.display()),
                    "the /dev/port route needs the example rule /usr/share/doc/mechweed/examples/60-mechweed-port.rules and CAP_SYS_RAWIO; the sysfs route (das08_pci = auto) needs neither",
                ),
            };
        }
        _ => {
            let root = m.path("/sys/bus/pci/devices");
            match pci::find(&root, kind, location) {
                Ok(found) => found.dir.join(format!("resource{}", kind.bar())),
                Err(e) => {
                    return Check::new(
                        name,
                        Level::Fail,
                        e.to_string(),
                        "mechweed probe lists the cards it finds; check the card is seated and [hw] names it (lspci -D)",
                    );
                }
            }
        }
    };
    let enabled =
        std::fs::read_to_string(path.with_file_name("enable")).is_ok_and(|t| t.trim() != "0");
    match (usable(&path), enabled) {
        (Ok(()), true) => Check::ok(
            name,
            format!("{}: {} readable and writable", kind.name(), path.display()),
        ),
        (Ok(()), false) => Check::new(
            name,
            Level::Fail,
            format!(
                "{}: {} is usable but the card's I/O decoding is off (enable = 0)",
                kind.name(),
                path.display()
            ),
            UDEV_FIX,
        ),
        (Err(why), _) => Check::new(
            name,
            Level::Fail,
            format!("{}: {}: {why}", kind.name(), path.display()),
            UDEV_FIX,
        ),
    }
}

/// The file opened for reading and writing, and closed (no byte moves).
fn usable(path: &Path) -> Result<(), String> {
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map(drop)
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => "not there".to_string(),
            std::io::ErrorKind::PermissionDenied => {
                "not readable and writable by this user".to_string()
            }
            _ => e.to_string(),
        })
}

/// Whether this process may read and write `path` (with its effective ids, as an open
/// would be judged), asked of the kernel without opening it.
fn may_read_write(path: &Path) -> bool {
    let Ok(c_path) = CString::new(path.as_os_str().as_bytes()) else {
        return false;
    };
    let (at, mode) = (libc::AT_FDCWD, libc::R_OK | libc::W_OK);
    // SAFETY: faccessat reads the NUL-terminated path we own.
    unsafe { libc::faccessat(at, c_path.as_ptr(), mode, libc::AT_EACCESS) == 0 }
}

fn serial(check: &str, setting: &str, path: &Path) -> Check {
    let shown = path.display();
    let fix_group = "be in the serial ports' group (sudo adduser USER dialout; the mechweed service's user is), then log in again";
    match std::fs::metadata(path) {
        Err(_) => Check::new(
            check,
            Level::Fail,
            format!("{setting} {shown}: not there"),
            format!(
                "plug the device in, or set {setting} to the port it has (ls /dev/serial/by-id/)"
            ),
        ),
        Ok(meta) if !meta.file_type().is_char_device() => Check::new(
            check,
            Level::Fail,
            format!("{setting} {shown}: not a serial device"),
            format!("set {setting} to the device (ls /dev/serial/by-id/)"),
        ),
        Ok(_) if !may_read_write(path) => Check::new(
            check,
            Level::Fail,
            format!("{setting} {shown}: not readable and writable by this user"),
            fix_group,
        ),
        Ok(_) => Check::ok(
            check,
            format!("{setting} {shown}: present, readable and writable"),
        ),
    }
}

fn gamepad(m: &Machine, device: &GamepadDevice) -> Check {
    let fix = "the package's udev rule (60-mechweed-gamepad.rules) gives group mechweed the joysticks (not the keyboards): be in that group, then replug the pad";
    match device {
        GamepadDevice::Path(path) => match usable_for_reading(path) {
            Ok(()) => Check::ok(
                "gamepad",
                format!("[joystick] gamepad_device {}: readable", path.display()),
            ),
            Err(why) => Check::new(
                "gamepad",
                Level::Fail,
                format!("[joystick] gamepad_device {}: {why}", path.display()),
                fix,
            ),
        },
        GamepadDevice::Auto => {
            let dir = m.path("/dev/input");
            match crate::gamepad::device::list(&dir) {
                Err(why) => Check::new("gamepad", Level::Fail, why, fix),
                Ok((found, refused)) => {
                    let pads: Vec<String> = (found.iter())
                        .filter(|(f, _)| f.looks_like_gamepad())
                        .map(|(f, _)| format!("{} ({})", f.name, f.path.display()))
                        .collect();
                    match (pads.is_empty(), refused.len()) {
                        (false, _) => Check::ok("gamepad", format!("gamepad: {}", pads.join(", "))),
                        (true, 0) => Check::new(
                            "gamepad",
                            Level::Fail,
                            format!("no gamepad in {}", dir.display()),
                            "plug the gamepad in (mechweed probe lists the input devices)",
                        ),
                        (true, n) => Check::new(
                            "gamepad",
                            Level::Fail,
                            format!(
                                "no gamepad readable in {}; {n} input devices refused this user",
                                dir.display()
                            ),
                            fix,
                        ),
                    }
                }
            }
        }
    }
}

fn usable_for_reading(path: &Path) -> Result<(), String> {
    std::fs::File::open(path)
        .map(drop)
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => "not there".to_string(),
            std::io::ErrorKind::PermissionDenied => "not readable by this user".to_string(),
            _ => e.to_string(),
        })
}

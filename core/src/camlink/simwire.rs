//! The serial cables of the simulated robot. The simulated camera computer lives inside
//! the simulated plant and talks through an in-memory pipe; this thread carries its
//! bytes to and from one end of a pseudo-terminal, so that the program opens the other
//! end with the same serial code it uses for /dev/ttyS0 on the robot.

use std::io::{Read, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use mechweed_hw::sim::PipeEnd;
use serialport::{SerialPort, TTYPort};

/// Start the cable; returns the pseudo-terminal path for the program to open.
pub fn start(pipe: PipeEnd, stop: Arc<AtomicBool>) -> std::io::Result<(String, JoinHandle<()>)> {
    start_named(pipe, stop, "camera-cable")
}

/// The same for another simulated device's line (the GNSS receiver's), its thread named
/// `name`.
pub fn start_named(
    mut pipe: PipeEnd,
    stop: Arc<AtomicBool>,
    name: &str,
) -> std::io::Result<(String, JoinHandle<()>)> {
    let (mut master, slave) = TTYPort::pair()?;
    let path = slave
        .name()
        .ok_or_else(|| std::io::Error::other("the pseudo-terminal has no name"))?;
    master.set_timeout(Duration::from_millis(2))?;
    let handle = std::thread::Builder::new()
        .name(name.into())
        .spawn(move || {
            // Keep our handle on the terminal's far end open, so that the link may close and
            // reopen it (as after a USB adapter comes back) without the terminal vanishing.
            let _slave = slave;
            let mut buf = [0u8; 256];
            while !stop.load(Ordering::Relaxed) {
                let n = pipe.try_read(&mut buf);
                if n > 0 && master.write_all(&buf[..n]).is_err() {
                    // Nobody has the far end open: the bytes are lost, as on a real line.
                }
                match master.read(&mut buf) {
                    Ok(n) => {
                        let _ = pipe.write(&buf[..n]);
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                    // The far end is closed (the link is reopening it): wait instead of spinning.
                    Err(_) => std::thread::sleep(Duration::from_millis(2)),
                }
            }
        })?;
    Ok((path, handle))
}

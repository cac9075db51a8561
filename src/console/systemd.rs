//! Telling systemd how the controller is, when it runs as a `Type=notify` service
//! (packaging/mechweed.service): READY once the hardware is open and the supervisor
//! ticks, STATUS with the mode and the fault, and the service watchdog fed only while
//! the supervisor's status is fresh. Outside systemd (no `NOTIFY_SOCKET`) nothing of
//! this runs.
//!
//! The charge-pump relay stays the robot's real watchdog: it opens the motor contactor
//! within tens of milliseconds of a hung supervisor, with no software in the way.
//! systemd's watchdog is slower (seconds) and only restarts the program or leaves it
//! failed, after which `ExecStopPost=mechweed safe` writes the safe outputs; it tells
//! the journal and whoever watches the service that the controller hung.
//!
//! The thread that notifies runs at normal priority and only reads the status the
//! supervisor publishes: a hung supervisor stops the feeding, a busy notifier never
//! delays a tick.

use std::os::unix::net::UnixDatagram;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::state::Reader;
use crate::state::status::Status;

/// Where systemd listens, and how often it wants to hear that all is well.
pub struct Notifier {
    socket: UnixDatagram,
    address: std::os::unix::net::SocketAddr,
    /// Half of `WatchdogSec=` (systemd's advice), or None without a watchdog.
    feed_every: Option<Duration>,
}

/// The notifier of this process, read from the environment once.
static FROM_ENV: OnceLock<Option<Notifier>> = OnceLock::new();

/// Send `message` to systemd if this process runs under it (for programs with a loop
/// of their own, such as the launcher: "READY=1", "WATCHDOG=1", "STATUS=...").
pub fn notify(message: &str) {
    if let Some(notifier) = Notifier::from_env() {
        notifier.send(message);
    }
}

impl Notifier {
    /// The notifier systemd asks for through the environment, or None outside systemd.
    /// A socket that cannot be reached is said once and the program goes on without it.
    pub fn from_env() -> Option<&'static Notifier> {
        FROM_ENV.get_or_init(Notifier::read_env).as_ref()
    }

    fn read_env() -> Option<Notifier> {
        let path = std::env::var_os("NOTIFY_SOCKET")?;
        let watchdog_usec = std::env::var("WATCHDOG_USEC").ok();
        let watchdog_pid = std::env::var("WATCHDOG_PID").ok();
        match Notifier::new(&path, watchdog_usec.as_deref(), watchdog_pid.as_deref()) {
            Ok(notifier) => Some(notifier),
            Err(e) => {
                crate::say!(
                    "systemd: cannot reach NOTIFY_SOCKET {}: {e}; running without READY or the service watchdog",
                    path.to_string_lossy()
                );
                None
            }
        }
    }

    /// A notifier for `path` (an abstract name if it starts with '@'); the watchdog only
    /// if `watchdog_usec` is set and `watchdog_pid`, if set, is this process.
    pub fn new(
        path: &std::ffi::OsStr,
        watchdog_usec: Option<&str>,
        watchdog_pid: Option<&str>,
    ) -> std::io::Result<Notifier> {
        use std::os::unix::ffi::OsStrExt;
        let bytes = path.as_bytes();
        let address = match bytes.strip_prefix(b"@") {
            Some(name) => {
                use std::os::linux::net::SocketAddrExt;
                std::os::unix::net::SocketAddr::from_abstract_name(name)?
            }
            None => std::os::unix::net::SocketAddr::from_pathname(path)?,
        };
        let ours = watchdog_pid.is_none_or(|pid| pid.trim() == std::process::id().to_string());
        let feed_every = watchdog_usec
            .and_then(|usec| usec.trim().parse::<u64>().ok())
            .filter(|&usec| usec > 0 && ours)
            .map(|usec| Duration::from_micros(usec / 2));
        Ok(Notifier {
            socket: UnixDatagram::unbound()?,
            address,
            feed_every,
        })
    }

    /// Send one message (lines of KEY=VALUE); a lost message is not worth a stop.
    fn send(&self, message: &str) {
        let _ = self.socket.send_to_addr(message.as_bytes(), &self.address);
    }

    /// Notify from a thread of its own until the run's `stop` is set (before the
    /// supervisor ends, so that its silence then is not taken for a hang): READY at the
    /// supervisor's first tick, STATUS on each change, WATCHDOG while the status is
    /// younger than `fresh_s`, STOPPING at the end.
    pub fn start(
        &'static self,
        status: Reader<Status>,
        clock: Instant,
        fresh_s: f64,
        stop: Arc<AtomicBool>,
    ) -> JoinHandle<()> {
        std::thread::Builder::new()
            .name("systemd".into())
            .spawn(move || self.notify_until(&status, clock, fresh_s, &stop))
            .expect("cannot start the systemd notify thread")
    }

    fn notify_until(
        &self,
        status: &Reader<Status>,
        clock: Instant,
        fresh_s: f64,
        stop: &AtomicBool,
    ) {
        let look_every = self
            .feed_every
            .unwrap_or(Duration::from_millis(500))
            .min(Duration::from_millis(500));
        let mut ready = false;
        let mut said = String::new();
        let mut last_feed: Option<Instant> = None;
        let mut stale_said = false;
        while !stop.load(Ordering::Relaxed) {
            let s = status.snapshot();
            let age_s = clock.elapsed().as_secs_f64() - s.t_s;
            let fresh = s.tick > 0 && age_s <= fresh_s;
            if fresh && !ready {
                ready = true;
                self.send(&format!("READY=1\nMAINPID={}", std::process::id()));
            }
            let words = status_words(&s, fresh, age_s);
            if ready && words != said {
                self.send(&format!("STATUS={words}"));
                said = words;
            }
            if let Some(every) = self.feed_every {
                if fresh && last_feed.is_none_or(|t| t.elapsed() >= every) {
                    self.send("WATCHDOG=1");
                    last_feed = Some(Instant::now());
                    stale_said = false;
                } else if ready && !fresh && !stale_said {
                    crate::say!(
                        "systemd: the supervisor's status is {age_s:.2} s old: the service watchdog is no longer fed"
                    );
                    stale_said = true;
                }
            }
            std::thread::sleep(look_every);
        }
        self.send("STOPPING=1\nSTATUS=stopping: the supervisor writes the safe outputs");
    }
}

/// What `systemctl status mechweed` shows on its Status line.
fn status_words(s: &Status, fresh: bool, age_s: f64) -> String {
    if !fresh {
        return format!("supervisor silent for {age_s:.1} s");
    }
    match &s.fault {
        Some(fault) => format!(
            "{}; fault at {:.1} s: {}",
            s.mode.name(),
            fault.t_s,
            fault.cause
        ),
        None => format!("{}; no fault", s.mode.name()),
    }
}

#[cfg(test)]
#[path = "systemd_tests.rs"]
mod tests;

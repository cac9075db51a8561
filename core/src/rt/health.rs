//! The supervisor's watch over the other threads. Each thread beats by publishing its
//! object (the steer command, the link status, later the GUI's frame time); a panic
//! anywhere is caught by a panic hook that tells the supervisor which thread it was
//! and waits until the supervisor has written the safe outputs, so that no panic
//! leaves the robot with a frozen last command.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Arc, Once};
use std::time::{Duration, Instant};

/// The threads of the program, for fault messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThreadName {
    Supervisor = 1,
    Steer = 2,
    CameraLink = 3,
    Gui = 4,
    Console = 5,
    /// The bus thread: not a safety channel, but a panic anywhere stops the robot.
    Bus = 6,
    /// The gamepad thread ([joystick] source = gamepad).
    Gamepad = 7,
    /// The GNSS link thread ([gnss] port).
    Gnss = 8,
}

impl ThreadName {
    pub fn label(self) -> &'static str {
        match self {
            ThreadName::Supervisor => "supervisor",
            ThreadName::Steer => "steer",
            ThreadName::CameraLink => "camera link",
            ThreadName::Gui => "GUI",
            ThreadName::Console => "console",
            ThreadName::Bus => "bus",
            ThreadName::Gamepad => "gamepad",
            ThreadName::Gnss => "GNSS link",
        }
    }

    /// The thread of this `label` (as a record writes it), or None.
    pub fn from_label(label: &str) -> Option<ThreadName> {
        (1..=8)
            .filter_map(ThreadName::from_code)
            .find(|t| t.label() == label)
    }

    fn from_code(code: u8) -> Option<ThreadName> {
        [
            ThreadName::Supervisor,
            ThreadName::Steer,
            ThreadName::CameraLink,
            ThreadName::Gui,
            ThreadName::Console,
            ThreadName::Bus,
            ThreadName::Gamepad,
            ThreadName::Gnss,
        ]
        .into_iter()
        .find(|t| *t as u8 == code)
    }
}

/// What the supervisor learns each tick about the threads that do not publish to it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThreadHealth {
    /// The GUI's last frame, s (None without a GUI).
    pub gui_beat_s: Option<f64>,
    /// A thread of this run that panicked.
    pub panicked: Option<ThreadName>,
    /// Deadline overruns of the supervisor loop so far.
    pub supervisor_overruns: u64,
    /// The computer's load as last read (None where it is not read: lockstep, replay).
    pub cpu_load: Option<crate::rt::load::CpuLoad>,
}

/// One run's panic flag, shared by its threads.
#[derive(Debug, Default)]
pub struct PanicFlag {
    thread: AtomicU8,
    safe_written: AtomicBool,
}

impl PanicFlag {
    pub fn panicked(&self) -> Option<ThreadName> {
        ThreadName::from_code(self.thread.load(Ordering::Acquire))
    }

    /// The supervisor wrote the safe outputs after a panic: the panicking thread may go on.
    pub(crate) fn safe_outputs_written(&self) {
        self.safe_written.store(true, Ordering::Release);
    }
}

thread_local! {
    static WATCHED: RefCell<Option<(Arc<PanicFlag>, ThreadName)>> = const { RefCell::new(None) };
}

/// How long a panicking thread waits for the supervisor's safe outputs.
const SAFE_WAIT: Duration = Duration::from_millis(500);

/// Call at the start of each thread of a run: its panics will be reported on `flag`.
pub fn watch_this_thread(flag: &Arc<PanicFlag>, name: ThreadName) {
    install_panic_hook();
    WATCHED.with(|w| *w.borrow_mut() = Some((Arc::clone(flag), name)));
}

fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let watched = WATCHED.with(|w| w.borrow().clone());
            // Tell the supervisor first: printing the message (and a backtrace) is slow.
            if let Some((flag, name)) = &watched {
                // The first panic of a run is the one the fault names.
                let _ = flag.thread.compare_exchange(
                    0,
                    *name as u8,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
            }
            previous(info);
            let Some((flag, name)) = watched else {
                return;
            };
            if name == ThreadName::Supervisor {
                return; // its hardware handle writes the safe outputs as it unwinds
            }
            let end = Instant::now() + SAFE_WAIT;
            while !flag.safe_written.load(Ordering::Acquire) && Instant::now() < end {
                std::thread::sleep(Duration::from_millis(1));
            }
        }));
    });
}

//! The gamepad thread: opens the pad, feeds its events to the mapping as they come and
//! publishes the result; when the pad goes away it says so and looks for it again twice
//! a second, so a pad plugged back in is found (and needs a new press of the dead-man).
//! It runs at normal priority: the supervisor never waits for it, and a thread that
//! stops publishing leaves a silent pad, which stops the robot.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use evdev::EventType;

use super::device::{Found, INPUT_DIR, InputDevices};
use super::mapping::{DeadMan, Opened, PadMap};
use super::{Label, PadState};
use crate::config::Settings;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::state::{Reader, Writer, shared};

/// How often a missing pad is looked for again.
const LOOK_AGAIN: Duration = Duration::from_millis(500);
/// The longest wait for an event before looking at the stop flag.
const WAIT_FOR_EVENTS: Duration = Duration::from_millis(100);

/// Where the thread's pad comes from: the kernel's input devices, or a test's.
pub(crate) trait PadSource: Send {
    /// Open the pad robot.ini names: what it is and its state now; or why not.
    fn open(&mut self, map: &PadMap) -> Result<(Found, Opened), String>;
    /// Add the events that came within `wait` (none if nothing did) to `out`, or say
    /// why the pad is gone.
    fn events(
        &mut self,
        wait: Duration,
        out: &mut Vec<(EventType, u16, i32)>,
    ) -> Result<(), String>;
    /// The pad's sticks and button as the kernel has them now (it drops events when its
    /// buffer overflows), or why the pad is gone.
    fn state(&mut self, map: &PadMap) -> Result<Opened, String>;
}

/// Start the gamepad thread; its object is what the supervisor and the GUI read.
pub fn start(
    settings: &Settings,
    panics: Arc<PanicFlag>,
    stop: Arc<AtomicBool>,
) -> (Reader<PadState>, JoinHandle<()>) {
    let map = PadMap::new(&settings.gamepad, &settings.joystick);
    let (writer, reader) = shared(PadState::new(map));
    let source = InputDevices::new(settings.gamepad.device.clone(), Path::new(INPUT_DIR));
    let thread = std::thread::Builder::new()
        .name("gamepad".into())
        .spawn(move || {
            health::watch_this_thread(&panics, ThreadName::Gamepad);
            run(source, writer, &stop);
        })
        .unwrap_or_else(|e| panic!("cannot start the gamepad thread: {e}"));
    (reader, thread)
}

/// Look for the pad, take its events while it is there, say when it goes; until `stop`.
pub fn run(mut source: impl PadSource, writer: Writer<PadState>, stop: &AtomicBool) {
    let mut state = writer.reader().snapshot();
    let mut said = String::new();
    while !stop.load(Ordering::Relaxed) {
        match source.open(&state.pad.map) {
            Ok((found, opened)) => {
                connected(&mut state, &found, opened);
                writer.publish(&state);
                let why = read_until_gone(&mut source, &mut state, &writer, stop);
                state.pad.disconnect();
                state.problem = Label::new(&why);
                writer.publish(&state);
                if !stop.load(Ordering::Relaxed) {
                    tracing::warn!(
                        "gamepad {} lost ({why}): the dead-man counts as released; looking for it again",
                        found.name
                    );
                }
                said = why;
            }
            Err(why) => {
                if why != said {
                    tracing::warn!("no gamepad: {why}; looking again every 0.5 s");
                    said = why.clone();
                }
                state.problem = Label::new(&why);
                writer.publish(&state);
                let until = Instant::now() + LOOK_AGAIN;
                while Instant::now() < until && !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(20));
                }
            }
        }
    }
}

fn connected(state: &mut PadState, found: &Found, opened: Opened) {
    state.pad.connect(opened, Instant::now());
    state.name = Label::new(&found.name);
    state.place = Label::new(&found.path.display().to_string());
    state.problem = Label::EMPTY;
    let button = format!("{:?}", state.pad.map.deadman);
    let dead_man = if opened.deadman_held {
        "held: release it and press it again to drive"
    } else {
        "released"
    };
    tracing::info!(
        "gamepad {} ({}) connected; dead-man {button} {dead_man}",
        found.name,
        found.path.display()
    );
}

/// Take events until the pad goes away or the program stops; returns why it ended.
fn read_until_gone(
    source: &mut impl PadSource,
    state: &mut PadState,
    writer: &Writer<PadState>,
    stop: &AtomicBool,
) -> String {
    let mut events = Vec::new();
    let mut silent_said = false;
    loop {
        if stop.load(Ordering::Relaxed) {
            return "the program stopped".into();
        }
        events.clear();
        if let Err(why) = source.events(WAIT_FOR_EVENTS, &mut events) {
            return why;
        }
        let now = Instant::now();
        for &(kind, code, value) in &events {
            state.pad.event(kind, code, value, now);
        }
        // At least every 0.1 s: what the kernel has, in case it dropped an event.
        match source.state(&state.pad.map) {
            Ok(kernel) => state.pad.reconcile(kernel),
            Err(why) => return why,
        }
        writer.publish(state);
        // Said once per silence: the supervisor applies the time-out at every tick.
        match state.pad.joystick(Instant::now()).dead_man {
            DeadMan::Silent(s) if !silent_said => {
                tracing::warn!(
                    "nothing from the gamepad for {s:.1} s: the dead-man counts as released until it is released and pressed again"
                );
                silent_said = true;
            }
            DeadMan::Silent(_) => {}
            _ => silent_said = false,
        }
    }
}

#[cfg(test)]
#[path = "thread_tests.rs"]
mod tests;

//! The gamepad thread over a pad the test plugs in, drives and pulls out, on a real
//! thread. Waits are for the published state, never for a time.

use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use evdev::{AbsoluteAxisCode, KeyCode};
use mechweed_hw::{Hw, HwError, Inputs, Outputs};
use parking_lot::Mutex;

use super::*;
use crate::gamepad::mapping::AxisRange;
use crate::gamepad::{PadHw, PadJoystick};

/// The pad as the test handles it.
#[derive(Default)]
struct Hand {
    plugged: Option<Opened>,
    events: VecDeque<(EventType, u16, i32)>,
}

#[derive(Clone, Default)]
struct TestPad(Arc<Mutex<Hand>>);

impl TestPad {
    fn plug_in(&self, deadman_held: bool) {
        let range = AxisRange {
            min: -32768,
            max: 32767,
        };
        self.0.lock().plugged = Some(Opened {
            speed: (range, 0),
            steer: (range, 0),
            deadman_held,
        });
    }
    /// An event, and the kernel's state it leaves.
    fn send(&self, kind: EventType, code: u16, value: i32) {
        let mut hand = self.0.lock();
        hand.events.push_back((kind, code, value));
        if let Some(kernel) = hand.plugged.as_mut() {
            if kind == EventType::KEY && code == KeyCode::BTN_TL.code() {
                kernel.deadman_held = value != 0;
            }
            if kind == EventType::ABSOLUTE && code == AbsoluteAxisCode::ABS_Y.0 {
                kernel.speed.1 = value;
            }
        }
    }
    fn pull_out(&self) {
        self.0.lock().plugged = None;
    }
}

impl PadSource for TestPad {
    fn open(&mut self, _: &PadMap) -> Result<(Found, Opened), String> {
        let hand = self.0.lock();
        let opened = hand.plugged.ok_or("no input device looks like a gamepad")?;
        let found = Found {
            path: PathBuf::from("/dev/input/event7"),
            name: "test pad".into(),
            buttons: vec!["BTN_TL".into()],
            axes: vec!["ABS_X".into(), "ABS_Y".into()],
            phys: String::new(),
        };
        Ok((found, opened))
    }
    fn events(&mut self, _: Duration, out: &mut Vec<(EventType, u16, i32)>) -> Result<(), String> {
        let mut hand = self.0.lock();
        if hand.plugged.is_none() {
            return Err("No such device (os error 19)".into());
        }
        out.extend(hand.events.drain(..));
        drop(hand);
        std::thread::sleep(Duration::from_millis(2));
        Ok(())
    }
    fn state(&mut self, _: &PadMap) -> Result<Opened, String> {
        (self.0.lock().plugged).ok_or_else(|| "No such device (os error 19)".into())
    }
}

/// Wait (up to 10 s) until the published pad satisfies `ok`; the last state if never.
fn until(pad: &Reader<PadState>, ok: impl Fn(&PadState, &PadJoystick) -> bool) -> PadState {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let state = pad.snapshot();
        let joystick = state.pad.joystick(Instant::now());
        if ok(&state, &joystick) || Instant::now() > end {
            return state;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn the_thread_finds_the_pad_follows_it_and_loses_it_when_pulled_out() {
    let settings = Settings::shipped();
    let map = PadMap::new(&settings.gamepad, &settings.joystick);
    let (writer, pad) = shared(PadState::new(map));
    let hand = TestPad::default();
    let stop = Arc::new(AtomicBool::new(false));
    let thread = {
        let (source, stop) = (hand.clone(), stop.clone());
        std::thread::spawn(move || run(source, writer, &stop))
    };
    let state = until(&pad, |s, _| s.problem.as_str().contains("looks like"));
    assert!(!state.pad.connected, "{state:?}");

    // Plugged in by someone holding the dead-man: it stands until pressed again.
    hand.plug_in(true);
    let state = until(&pad, |s, _| s.pad.connected);
    let now = Instant::now();
    assert_eq!(state.pad.joystick(now).dead_man, DeadMan::ReleaseFirst);
    assert_eq!(
        (state.name.as_str(), state.place.as_str()),
        ("test pad", "/dev/input/event7")
    );
    hand.send(EventType::KEY, KeyCode::BTN_TL.code(), 0);
    hand.send(EventType::KEY, KeyCode::BTN_TL.code(), 1);
    hand.send(EventType::ABSOLUTE, AbsoluteAxisCode::ABS_Y.0, -32768);
    let state = until(&pad, |_, j| j.enable && j.speed_v > 3.9);
    assert!(state.pad.joystick(Instant::now()).enable, "{state:?}");

    // Pulled out while driving: released at once, and why is said.
    hand.pull_out();
    let state = until(&pad, |s, _| !s.pad.connected);
    let j = state.pad.joystick(Instant::now());
    assert_eq!(
        (j.dead_man, j.enable, j.speed_v),
        (DeadMan::NotConnected, false, 0.0)
    );
    // Why: the pad's error, or, once looked for again, that there is none.
    let why = state.problem.as_str();
    assert!(
        why.contains("No such device") || why.contains("looks like"),
        "{state:?}"
    );

    // Back in, held: again it waits for a new press.
    hand.plug_in(true);
    let state = until(&pad, |s, _| s.pad.connected);
    assert_eq!(
        state.pad.joystick(Instant::now()).dead_man,
        DeadMan::ReleaseFirst
    );
    assert_eq!(state.pad.connections, 2);

    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    thread.join().unwrap();
}

/// Hardware whose wired joystick reads full forward with its button held.
struct WiredJoystick;

impl Hw for WiredJoystick {
    fn read(&mut self) -> Result<Inputs, HwError> {
        Ok(Inputs {
            joystick_speed_v: 4.0,
            joystick_enable: true,
            battery_v: 24.0,
            ..Inputs::default()
        })
    }
    fn write(&mut self, _: &Outputs) -> Result<(), HwError> {
        Ok(())
    }
    fn name(&self) -> &'static str {
        "wired"
    }
}

#[test]
fn the_supervisor_reads_the_pad_in_place_of_the_wired_joystick_and_judges_silence_itself() {
    let settings = Settings::shipped();
    let map = PadMap::new(&settings.gamepad, &settings.joystick);
    let mut state = PadState::new(map);
    let (writer, reader) = shared(state);
    let mut hw = PadHw::new(Box::new(WiredJoystick), reader);
    // No pad: the wired joystick's button does not count.
    let i = hw.read().unwrap();
    assert_eq!(
        (i.joystick_enable, i.joystick_speed_v, i.battery_v),
        (false, 0.0, 24.0)
    );

    let range = AxisRange {
        min: -32768,
        max: 32767,
    };
    let opened = Opened {
        speed: (range, 0),
        steer: (range, 0),
        deadman_held: false,
    };
    let now = Instant::now();
    state.pad.connect(opened, now);
    let y = AbsoluteAxisCode::ABS_Y.0;
    state.pad.event(EventType::ABSOLUTE, y, 32767, now);
    state
        .pad
        .event(EventType::KEY, KeyCode::BTN_TL.code(), 1, now);
    writer.publish(&state);
    let i = hw.read().unwrap();
    // Pushed back (positive on ABS_Y): reverse.
    assert!(i.joystick_enable && i.joystick_speed_v < -3.9, "{i:?}");

    // The thread stopped publishing 2 s ago: the read itself sees the silence.
    let Some(then) = now.checked_sub(Duration::from_secs(2)) else {
        return; // a computer up for less than 2 s: nothing to test against
    };
    let mut silent = PadState::new(map);
    silent.pad.connect(opened, then);
    silent
        .pad
        .event(EventType::KEY, KeyCode::BTN_TL.code(), 1, then);
    writer.publish(&silent);
    assert!(!hw.read().unwrap().joystick_enable);
    // The thread then publishes a pad that looks alive and held (an event it took just
    // before the silence was judged here): the robot still waits for the dead-man to be
    // released and pressed again.
    let mut alive = PadState::new(map);
    alive.pad.connect(opened, Instant::now());
    alive
        .pad
        .event(EventType::KEY, KeyCode::BTN_TL.code(), 1, Instant::now());
    writer.publish(&alive);
    assert!(alive.pad.joystick(Instant::now()).enable);
    assert!(!hw.read().unwrap().joystick_enable);
    let mut silent = alive;
    silent
        .pad
        .event(EventType::KEY, KeyCode::BTN_TL.code(), 0, Instant::now());
    writer.publish(&silent);
    assert!(!hw.read().unwrap().joystick_enable);
    silent
        .pad
        .event(EventType::KEY, KeyCode::BTN_TL.code(), 1, Instant::now());
    writer.publish(&silent);
    assert!(hw.read().unwrap().joystick_enable);
}

//! The supervisor tick does no heap allocation after start: a counting allocator
//! watches this thread while the simulated robot drives along the row, the camera
//! link decodes and the steer thread's tick runs, and sees none; nor when a card's
//! read fails; nor the row filter's predict and updates.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use mechweed_core::config::{CameraPort, GnssPort, Settings, SteerLaw, SteerSource};
use mechweed_core::state::modes::{Mode, Request};
use mechweed_core::threads::lockstep::{Io, Lockstep};

struct Counting;

// Both per thread: the tests run in parallel, and one test's allocations must not be
// counted in another's.
thread_local! {
    static WATCHING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// Count one allocation if this thread is watched.
fn count_one() {
    if WATCHING.try_with(Cell::get).unwrap_or(false) {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
    }
}

// SAFETY: forwards to the system allocator; only counts on the watched thread.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f` on this thread.
fn allocations_in(f: impl FnOnce()) -> u64 {
    let before = ALLOCATIONS.with(Cell::get);
    WATCHING.with(|w| w.set(true));
    f();
    WATCHING.with(|w| w.set(false));
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn no_allocation_per_tick_while_driving_or_faulting() {
    let settings = Settings::shipped();
    let mut sim = Lockstep::new(&settings, Mode::Autonomous);
    sim.run_for(3.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    let driving = allocations_in(|| {
        for _ in 0..2000 {
            sim.tick();
        }
    });
    assert_eq!(
        driving, 0,
        "allocations in 2000 ticks of autonomous driving"
    );

    // Joystick, halt and a fault take other paths through the tick.
    sim.request(Request::Mode(Mode::Joystick)).unwrap();
    sim.robot.set_joystick(2.0, 3.0, true);
    let other_modes = allocations_in(|| {
        for _ in 0..300 {
            sim.tick();
        }
        sim.robot.apply(&mechweed_hw::sim::EventAction::EstopFront);
        for _ in 0..300 {
            sim.tick();
        }
    });
    assert_eq!(sim.supervisor.mode(), Mode::Fault);
    assert_eq!(
        other_modes, 0,
        "allocations in joystick mode and in a fault"
    );
}

#[test]
fn no_allocation_per_tick_steering_by_each_law() {
    // The shipped law is pure pursuit; the lqr law's gains are designed when the steer
    // thread starts, and its update must touch only fixed-size state. Both steer through
    // the row filter, from the camera alone and fused with GNSS.
    for law in [SteerLaw::Lqr, SteerLaw::Pursuit] {
        for source in [SteerSource::Camera, SteerSource::Fused] {
            let mut settings = Settings::shipped();
            settings.steer.law = law;
            settings.sources.source = source;
            settings.gnss.port = GnssPort::Link(CameraPort::Sim);
            let mut sim = Lockstep::new(&settings, Mode::Autonomous);
            sim.run_for(3.0);
            let driving = allocations_in(|| {
                for _ in 0..2000 {
                    sim.tick();
                }
            });
            assert_eq!(
                sim.supervisor.mode(),
                Mode::Autonomous,
                "{law:?} {source:?}"
            );
            assert_eq!(
                driving, 0,
                "allocations steering by {law:?} from {source:?}"
            );
        }
    }
}

#[test]
fn no_allocation_per_tick_through_the_emulated_cards() {
    // The whole real I/O path: plant -> card registers -> drivers -> wiring -> controller.
    let settings = Settings::shipped();
    let io = Io::cards(&settings).expect("emulated cards open");
    let mut sim = Lockstep::with_io(&settings, Mode::Autonomous, io);
    sim.run_for(3.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    let driving = allocations_in(|| {
        for _ in 0..2000 {
            sim.tick();
        }
    });
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    assert_eq!(
        driving, 0,
        "allocations in 2000 ticks through the emulated cards"
    );
}

#[test]
fn no_allocation_per_tick_when_a_card_read_fails() {
    // A DAS08 whose A/D never finishes: every tick's read fails, from the one that
    // finds it (and latches the fault) onwards; the error names the card and the
    // register in numbers, not in a formatted message.
    let settings = Settings::shipped();
    let io = Io::cards(&settings).expect("emulated cards open");
    let mut sim = Lockstep::with_io(&settings, Mode::Autonomous, io);
    sim.run_for(3.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    let Io::Cards(rig) = &sim.io else {
        unreachable!("opened on the emulated cards")
    };
    rig.das08.set_eoc_stuck(true);
    let failing = allocations_in(|| {
        for _ in 0..200 {
            sim.tick();
        }
    });
    assert_eq!(
        sim.supervisor.mode(),
        Mode::Fault,
        "the failing read was seen"
    );
    assert_eq!(failing, 0, "allocations in 200 ticks whose card read fails");
}

#[test]
fn no_allocation_per_tick_while_recording() {
    // The real-time path offers each tick to the recorder without waiting for the disk.
    let dir = tempfile::tempdir().unwrap();
    let mut settings = Settings::shipped();
    settings.record.folder = dir.path().to_path_buf();
    let (tap, recorder) =
        mechweed_core::record::start(&settings, None, mechweed_core::record::Delivery::NeverWait)
            .expect("a record in the temporary folder");
    let mut sim = Lockstep::new(&settings, Mode::Autonomous);
    sim.record_into(tap);
    sim.run_for(3.0);
    let recording = allocations_in(|| {
        for _ in 0..2000 {
            sim.tick();
        }
        // A fault is an event in the record as well.
        sim.robot.apply(&mechweed_hw::sim::EventAction::EstopFront);
        for _ in 0..100 {
            sim.tick();
        }
    });
    sim.stop_recording();
    let outcome = recorder.finish();
    assert_eq!(recording, 0, "allocations in 2100 offered ticks");
    // Lockstep runs much faster than the disk is asked to keep up with: with the
    // real-time delivery, what does not fit in the queue is dropped and counted.
    assert!(outcome.ticks_recorded > 0, "{outcome:?}");
    assert!(
        outcome.ticks_recorded + outcome.ticks_dropped >= 2100,
        "{outcome:?}"
    );
}

#[test]
fn the_row_filter_predicts_and_updates_without_allocating() {
    use mechweed_core::steer::filter::{FilterSettings, RowFilter, Travel};
    let mut f = RowFilter::new(FilterSettings::default());
    let since = Travel {
        travelled_m: 0.05,
        turned_rad: 0.001,
    };
    // Used, rejected and reset updates, and refused input, each take their own path.
    let allocations = allocations_in(|| {
        for k in 0..1000 {
            f.predict(0.01, 0.0002);
            f.update_camera(0.01 * (k % 7) as f64, 0.001, 0.8, 0.01, 0.01, since);
            f.update_gnss(if k % 50 < 25 { 0.0 } else { 0.6 }, 0.01, Travel::default());
            f.update_gnss(f64::NAN, 0.01, Travel::default());
        }
    });
    assert_eq!(allocations, 0);
    assert!(f.counters().gnss_resets > 0 && f.counters().gnss_rejected > 0);
}

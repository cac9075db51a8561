//! The promise that the hot paths never touch the heap, checked with a counting
//! allocator. Counts are per thread, so tests running in parallel do not disturb them.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::{Read, Write};
use std::time::Duration;

use crate::camproto::CMD_START;
use crate::sim::{RowShape, SimHw, SimParams, SimRobot, byte_pipe, parse_events};
use crate::{Hw, Outputs};

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count_one() {
    // try_with: the thread-local may already be gone while a thread shuts down.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

pub(crate) fn allocations() -> u64 {
    ALLOCATIONS.with(|n| n.get())
}

fn driving() -> Outputs {
    Outputs {
        amp_left_v: 6.0,
        amp_right_v: 6.0,
        amp_steer_v: 0.3,
        main_power_on: true,
        brake_release_left: true,
        brake_release_right: true,
        tool_on: true,
    }
}

#[test]
fn lockstep_robot_camera_and_pipe_do_not_allocate() {
    let events =
        parse_events("3 link_silent 1, 6 camera_reboot, 7 encoder_stuck right, 8 estop_back")
            .unwrap();
    let params = SimParams {
        camera_corrupt: 0.01,
        events,
        ..SimParams::benchmark(RowShape::Arc, 4)
    };
    let (camera, mut robot_end) = byte_pipe(256);
    let mut robot = SimRobot::new(&params, camera);
    robot_end.set_read_timeout(Duration::ZERO);
    robot_end.write_all(&[CMD_START]).unwrap();
    let mut buf = [0u8; 64];

    let before = allocations();
    for k in 1..=1500 {
        let t_s = k as f64 * 0.01;
        robot.advance_to(t_s);
        let inputs = robot.inputs();
        robot.set_outputs(&driving());
        let _ = (
            inputs,
            robot.truth(),
            robot.outputs(),
            robot.cross_track().summary(),
        );
        let _ = robot_end.read(&mut buf);
        let _ = robot_end.try_read(&mut buf);
        if k == 700 {
            robot_end.write_all(&[CMD_START]).unwrap();
        }
    }
    assert_eq!(allocations() - before, 0);
    assert!(robot.truth().distance_m > 5.0);
    assert!(robot.cross_track().samples() > 0);
}

#[test]
fn sim_hw_read_and_write_do_not_allocate() {
    let (camera, _robot_end) = byte_pipe(256);
    let mut hw = SimHw::new(SimRobot::new(&SimParams::default(), camera));
    let control = hw.control();
    hw.write(&driving()).unwrap();
    let before = allocations();
    for _ in 0..200 {
        std::thread::sleep(Duration::from_millis(1));
        let _ = hw.read().unwrap();
        hw.write(&driving()).unwrap();
        control.set_joystick(0.0, 1.0, true);
    }
    assert_eq!(allocations() - before, 0);
}

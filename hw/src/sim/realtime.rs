//! The simulated robot on the wall clock, as hardware behind the `Hw` trait.
//!
//! Each `read()` first advances the plant to the time elapsed since `SimHw::new`, then
//! publishes the truth and the cross-track figures for other threads (GUI, reports)
//! through a mutex held only to copy. The figures are those of the truth at each read,
//! that is at each supervisor tick: the points a run's record holds, so that the run
//! report and `record summary` give the same (crosstrack_ticks.rs). Publishing never
//! allocates. Other threads operate the plant (e-stop buttons, joystick) through
//! `SimControl`, whose requests wait in a fixed queue until the next `read()`.

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Instant;

use super::Truth;
use super::crosstrack::CrossTrackSummary;
use super::crosstrack_ticks::TickCrossTrack;
use super::events::EventAction;
use super::robot::SimRobot;
use crate::{Hw, HwError, Inputs, Outputs};

/// Requests that can wait for the next `read()` at once.
const QUEUE_LEN: usize = 16;

struct Shared {
    truth: Truth,
    cross: TickCrossTrack,
    actions: [Option<EventAction>; QUEUE_LEN],
    joystick: Option<(f64, f64, bool)>,
}

fn lock(shared: &Mutex<Shared>) -> MutexGuard<'_, Shared> {
    // A panic elsewhere cannot leave a copy of plain values half-written in a harmful way.
    shared
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The simulated robot as hardware, on real time. Implements [`Hw`] ("simulated robot").
pub struct SimHw {
    robot: SimRobot,
    start: Instant,
    shared: Arc<Mutex<Shared>>,
}

/// Read the newest truth and cross-track statistics from any thread.
#[derive(Clone)]
pub struct TruthHandle {
    shared: Arc<Mutex<Shared>>,
}

/// Operate the simulated robot from any thread (the GUI's e-stop buttons and joystick).
#[derive(Clone)]
pub struct SimControl {
    shared: Arc<Mutex<Shared>>,
}

impl SimHw {
    /// The clock starts here.
    pub fn new(robot: SimRobot) -> SimHw {
        let shared = Shared {
            truth: robot.truth(),
            cross: TickCrossTrack::new(robot.cross_track_from_m()),
            actions: [None; QUEUE_LEN],
            joystick: None,
        };
        SimHw {
            robot,
            start: Instant::now(),
            shared: Arc::new(Mutex::new(shared)),
        }
    }

    pub fn truth_handle(&self) -> TruthHandle {
        TruthHandle {
            shared: Arc::clone(&self.shared),
        }
    }

    pub fn control(&self) -> SimControl {
        SimControl {
            shared: Arc::clone(&self.shared),
        }
    }

    pub fn robot(&self) -> &SimRobot {
        &self.robot
    }

    /// Apply what other threads asked for since the last read.
    fn take_requests(&mut self) {
        let (actions, joystick) = {
            let mut shared = lock(&self.shared);
            let actions = shared.actions;
            shared.actions = [None; QUEUE_LEN];
            (actions, shared.joystick.take())
        };
        for action in actions.iter().flatten() {
            self.robot.apply(action);
        }
        if let Some((steer_v, speed_v, enable)) = joystick {
            self.robot.set_joystick(steer_v, speed_v, enable);
        }
    }

    /// Advance to `t_s`, then publish the truth there and take it into the figures.
    fn advance_and_publish(&mut self, t_s: f64) {
        self.robot.advance_to(t_s);
        let truth = self.robot.truth();
        let mut shared = lock(&self.shared);
        shared.truth = truth;
        (shared.cross).tick(truth.tool_cross_track_m, truth.distance_m, truth.row_done);
    }
}

impl Hw for SimHw {
    fn read(&mut self) -> Result<Inputs, HwError> {
        self.take_requests();
        self.advance_and_publish(self.start.elapsed().as_secs_f64());
        Ok(self.robot.inputs())
    }

    fn write(&mut self, outputs: &Outputs) -> Result<(), HwError> {
        self.robot.set_outputs(outputs);
        Ok(())
    }

    fn name(&self) -> &'static str {
        "simulated robot"
    }
}

impl TruthHandle {
    /// A handle with no simulated robot behind it (on the real robot there is no
    /// truth): the truth stays zero and the cross-track statistics empty.
    pub fn none() -> TruthHandle {
        let shared = Shared {
            truth: Truth::default(),
            cross: TickCrossTrack::new(0.0),
            actions: [None; QUEUE_LEN],
            joystick: None,
        };
        TruthHandle {
            shared: Arc::new(Mutex::new(shared)),
        }
    }

    pub fn truth(&self) -> Truth {
        lock(&self.shared).truth
    }

    /// The cross-track figures of the ticks so far (none on the real robot).
    pub fn cross_track_summary(&self) -> CrossTrackSummary {
        lock(&self.shared).cross.summary()
    }
}

impl SimControl {
    /// Queue an action for the next `read()`; false if the queue is full.
    pub fn apply(&self, action: EventAction) -> bool {
        let mut shared = lock(&self.shared);
        match shared.actions.iter_mut().find(|slot| slot.is_none()) {
            Some(slot) => {
                *slot = Some(action);
                true
            }
            None => false,
        }
    }

    /// The operator's joystick (volts as wired) and dead-man button, from the next `read()`.
    pub fn set_joystick(&self, steer_v: f64, speed_v: f64, enable: bool) {
        lock(&self.shared).joystick = Some((steer_v, speed_v, enable));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::{RowShape, SimParams};
    use crate::sim::pipe::byte_pipe;
    use std::time::Duration;

    fn sim_hw() -> SimHw {
        let (camera, _robot_end) = byte_pipe(1024);
        SimHw::new(SimRobot::new(
            &SimParams::benchmark(RowShape::Straight, 3),
            camera,
        ))
    }

    #[test]
    fn read_follows_the_wall_clock_and_publishes_truth() {
        let mut hw = sim_hw();
        let handle = hw.truth_handle();
        assert_eq!(hw.name(), "simulated robot");
        std::thread::sleep(Duration::from_millis(50));
        let inputs = hw.read().unwrap();
        assert!(inputs.estop_front_released && !inputs.motor_power_present);
        let t_s = handle.truth().t_s;
        assert!((0.049..1.0).contains(&t_s), "{t_s}");
        assert!((handle.truth().y_m - 0.05).abs() < 1e-12);
    }

    #[test]
    fn control_reaches_the_robot_at_the_next_read() {
        let mut hw = sim_hw();
        let control = hw.control();
        assert!(control.apply(EventAction::EstopBack));
        control.set_joystick(1.0, -2.0, true);
        let inputs = hw.read().unwrap();
        assert!(!inputs.estop_back_released);
        assert_eq!(
            (
                inputs.joystick_steer_v,
                inputs.joystick_speed_v,
                inputs.joystick_enable
            ),
            (1.0, -2.0, true)
        );
        for _ in 0..QUEUE_LEN {
            control.apply(EventAction::PowerUp);
        }
        assert!(!control.apply(EventAction::PowerUp), "a full queue says so");
    }

    #[test]
    fn published_figures_are_those_of_the_truth_at_each_read() {
        let mut hw = sim_hw();
        hw.robot.set_outputs(&Outputs {
            amp_left_v: 6.0,
            amp_right_v: 6.0,
            main_power_on: true,
            brake_release_left: true,
            brake_release_right: true,
            ..Outputs::SAFE
        });
        // 20 s of 10 ms ticks, each tick's truth taken as a record takes it.
        let handle = hw.truth_handle();
        let mut recorded = TickCrossTrack::new(hw.robot.cross_track_from_m());
        for tick in 1..=2000 {
            hw.advance_and_publish(tick as f64 * 0.01);
            let t = handle.truth();
            recorded.tick(t.tool_cross_track_m, t.distance_m, t.row_done);
        }
        let published = handle.cross_track_summary();
        assert!(published.distance_m > 5.0, "{published:?}");
        assert_eq!(published, recorded.summary());
        // The plant's own figures, a sample per centimetre of its 1 ms steps, are close.
        let plant = hw.robot.cross_track().summary();
        assert!((published.distance_m - plant.distance_m).abs() < 0.05);
        assert!((published.max_cm - plant.max_cm).abs() < 0.05 + 0.05 * plant.max_cm);
    }
}

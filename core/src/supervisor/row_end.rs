//! The normal end of a row, told apart from a row lost in mid-field.
//!
//! A camera that stops seeing the row is a fault (faults/), because in mid-field it
//! means the robot has left the row or the camera is blind. At the end of the row it
//! is what should happen, so the supervisor counts the distance driven in Autonomous
//! along the row and stops the robot in Halt, with a notice, when the weeding tool
//! has passed the row's end: before the camera, which looks ahead, runs out of plants.
//!
//! The row's length comes from `[supervisor] row_length_m`; with 0 (not known) on
//! the simulated robot with its own camera it is the simulated field's, and on the
//! real robot nothing ends a row but the operator, so every lost row is a fault.
//! The robot starts a row with its rear axle at the row's start (as the simulated
//! field places it); the tool, `[robot] tool_offset_m` from the axle, passes the end
//! after `row_length_m - tool_offset_m` of odometry.

use crate::config::{Backend, CameraPort, Settings};
use crate::state::modes::Mode;

/// The row length in force for these settings, m; None when no row end is known.
pub fn row_length_m(s: &Settings) -> Option<f64> {
    if s.supervisor.row_length_m > 0.0 {
        Some(s.supervisor.row_length_m)
    } else if s.backend == Backend::Sim && s.camera_port == CameraPort::Sim {
        Some(s.sim.row_length_m)
    } else {
        None
    }
}

/// Counts the distance driven along the present row.
#[derive(Debug, Clone)]
pub(crate) struct RowEnd {
    /// Axle odometry at which the tool passes the end, m; None: no end known.
    end_m: Option<f64>,
    driven_m: f64,
    last_odometry_m: Option<f64>,
}

impl RowEnd {
    pub fn new(s: &Settings) -> RowEnd {
        RowEnd {
            end_m: row_length_m(s).map(|length_m| length_m - s.robot.tool_offset_m),
            driven_m: 0.0,
            last_odometry_m: None,
        }
    }

    /// Distance driven along this row so far, m.
    #[cfg(test)]
    fn driven_m(&self) -> f64 {
        self.driven_m
    }

    /// One tick: `odometry_m` is the distance driven since the start of the run. Returns
    /// the distance driven along the row when the tool has just passed its end.
    ///
    /// Driving in Autonomous adds to the row; moving in any other mode (the operator
    /// drives to the next row in Joystick) starts a new one, and so does its end.
    /// Standing in Halt or Fault in mid-row keeps the count, so Autonomous after a
    /// stop finishes the same row.
    pub fn update(&mut self, mode: Mode, odometry_m: f64) -> Option<f64> {
        let step_m = odometry_m - self.last_odometry_m.unwrap_or(odometry_m);
        self.last_odometry_m = Some(odometry_m);
        match mode {
            Mode::Autonomous => self.driven_m += step_m,
            Mode::Joystick | Mode::Test if step_m > 0.0 => self.driven_m = 0.0,
            _ => {}
        }
        let end_m = self.end_m?;
        if mode == Mode::Autonomous && self.driven_m >= end_m {
            let driven_m = self.driven_m;
            self.driven_m = 0.0;
            return Some(driven_m);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(row_length_m: f64) -> Settings {
        let mut s = Settings::shipped();
        s.supervisor.row_length_m = row_length_m;
        s.robot.tool_offset_m = -0.4;
        s
    }

    /// Drives `metres` in `mode` in 1 cm steps from `odometry_m`; the first end seen.
    fn drive(row: &mut RowEnd, mode: Mode, odometry_m: &mut f64, metres: f64) -> Option<f64> {
        let mut ended = None;
        for _ in 0..(metres * 100.0).round() as usize {
            *odometry_m += 0.01;
            ended = ended.or(row.update(mode, *odometry_m));
        }
        ended
    }

    #[test]
    fn the_row_ends_when_the_tool_behind_the_axle_passes_its_length() {
        let mut row = RowEnd::new(&settings(10.0));
        let mut odo = 0.0;
        assert_eq!(drive(&mut row, Mode::Autonomous, &mut odo, 10.3), None);
        let ended = drive(&mut row, Mode::Autonomous, &mut odo, 0.2).expect("end of row");
        assert!((ended - 10.4).abs() < 0.011, "ended after {ended} m");
    }

    #[test]
    fn a_stop_in_mid_row_keeps_the_count_and_joystick_driving_starts_a_new_row() {
        let mut row = RowEnd::new(&settings(10.0));
        let mut odo = 0.0;
        assert_eq!(drive(&mut row, Mode::Autonomous, &mut odo, 6.0), None);
        row.update(Mode::Halt, odo);
        assert!((row.driven_m() - 6.0).abs() < 0.011);
        assert!(drive(&mut row, Mode::Autonomous, &mut odo, 4.5).is_some());
        // To the next row in Joystick, then 6 m of it: not yet its end.
        drive(&mut row, Mode::Autonomous, &mut odo, 3.0);
        drive(&mut row, Mode::Joystick, &mut odo, 1.0);
        assert_eq!(row.driven_m(), 0.0);
        assert_eq!(drive(&mut row, Mode::Autonomous, &mut odo, 6.0), None);
    }

    #[test]
    fn joystick_or_test_without_moving_keeps_the_row() {
        // The operator takes the joystick in mid-row, or opens the test panel, and
        // does not move: Autonomous after it finishes the same row.
        let mut row = RowEnd::new(&settings(10.0));
        let mut odo = 0.0;
        drive(&mut row, Mode::Autonomous, &mut odo, 6.0);
        row.update(Mode::Joystick, odo);
        row.update(Mode::Test, odo);
        assert!((row.driven_m() - 6.0).abs() < 0.011, "{} m", row.driven_m());
    }

    #[test]
    fn the_real_robot_with_no_row_length_never_ends_a_row() {
        let mut s = settings(0.0);
        s.backend = Backend::Cards;
        assert_eq!(row_length_m(&s), None);
        let mut row = RowEnd::new(&s);
        let mut odo = 0.0;
        assert_eq!(drive(&mut row, Mode::Autonomous, &mut odo, 200.0), None);
    }

    #[test]
    fn the_simulated_robot_takes_the_fields_row_unless_a_length_is_set() {
        let mut s = settings(0.0);
        s.sim.row_length_m = 25.0;
        assert_eq!(row_length_m(&s), Some(25.0));
        s.supervisor.row_length_m = 12.0;
        assert_eq!(row_length_m(&s), Some(12.0));
        // An outside camera follows a field the simulated one is not.
        s.supervisor.row_length_m = 0.0;
        s.camera_port = CameraPort::Tcp {
            address: "localhost:5000".into(),
        };
        assert_eq!(row_length_m(&s), None);
    }
}

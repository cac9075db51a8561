//! What the supervisor follows from the steer thread and the plant between its checks:
//! a finished end-switch procedure, the row's end, and which sensors steer (each a
//! notice for the operator).

use crate::config::SteerSource;
use crate::state::modes::Mode;
use crate::state::status::Notice;
use crate::steer::SteerCommand;

use super::Supervisor;

impl Supervisor {
    /// At the row's end (row_end.rs), stop in Halt and say how far the robot drove.
    pub(super) fn follow_row_end(&mut self, now_s: f64, distance_m: f64) {
        if let Some(driven_m) = self.row_end.update(self.status.mode, distance_m) {
            self.say(Notice::RowEnded {
                driven_m,
                t_s: now_s,
            });
            self.set_mode(Mode::Halt);
        }
    }

    /// The steer thread finished an end-switch procedure: stop in Halt and say so.
    pub(super) fn follow_endswitch_procedure(&mut self, steer: &SteerCommand, now_s: f64) {
        let finished = self
            .endswitch
            .finished(&mut self.status.endswitch_hit, steer);
        if self.status.mode.drives()
            && let Some(side) = finished
        {
            self.say(Notice::EndSwitchRecovered { side, t_s: now_s });
            self.set_mode(Mode::Halt);
        }
    }

    /// Each change of the sensors that steer, or of why, while autonomous is a notice
    /// (the console's line, the GUI's, the record's event): GNSS's fall-backs, and the
    /// camera alone's gaps and search for its first plants.
    pub(super) fn say_steering(&mut self, steer: &SteerCommand, now_s: f64) {
        let autonomous = self.status.mode == Mode::Autonomous && steer.mode == Mode::Autonomous;
        // The camera alone says only what it lacks: a gap, the first plants not seen yet.
        let camera_alone = self.settings.sources.source == SteerSource::Camera;
        if !autonomous || (camera_alone && steer.sources.why.is_none()) {
            self.steering_said = None;
            return;
        }
        let (steering, why) = (steer.sources.steering, steer.sources.why);
        if self.steering_said != Some((steering, why)) {
            self.steering_said = Some((steering, why));
            self.say(Notice::Steering {
                steering,
                why: steer.sources.why,
                t_s: now_s,
            });
        }
    }
}

//! The whole simulated plant on simulated time: wheels, steering, body, sensors, power,
//! the field and the camera computer, integrated in fixed steps (1 ms by default).
//!
//! Each step: the amplifiers drive the wheels and the steering (0 V unless the contactor
//! is closed), the body moves, the tool's cross-track error is measured (tool.rs), the
//! camera computer runs, and events whose time has come are applied. Nothing here allocates
//! after `new`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::body::Pose;
use super::camera::CameraComputer;
use super::crosstrack::CrossTrackStats;
use super::drive::DriveWheel;
use super::events::SimEvent;
use super::field::Field;
use super::field_tier::FieldTier;
use super::gnss::SimReceiver;
use super::miswire::{Miswire, Wires};
use super::params::SimParams;
use super::pipe::PipeEnd;
use super::steering::Steering;
use super::tool::ToolTrack;
use super::{SEED_POT, Truth};
use crate::EncoderId;
use crate::{Inputs, Outputs};

/// Amplifier output range, V.
const AMP_MAX_V: f64 = 10.0;

/// The operator's joystick, volts as wired, and its dead-man button.
#[derive(Debug, Clone, Copy, Default)]
struct Joystick {
    steer_v: f64,
    speed_v: f64,
    enable: bool,
}

pub struct SimRobot {
    p: SimParams,
    field: Field,
    /// What a real field adds; nothing in the clean field.
    tier: FieldTier,
    camera: CameraComputer,
    /// The GNSS receiver, once a pipe is attached for it.
    gnss: Option<SimReceiver>,
    left: DriveWheel,
    right: DriveWheel,
    steering: Steering,
    pose: Pose,
    /// Time is counted in whole steps, so it does not drift.
    steps: u64,
    distance_m: f64,
    outputs: Outputs,
    joystick: Joystick,
    estop_front_released: bool,
    estop_back_released: bool,
    power_lost: bool,
    battery_v: f64,
    pot_broken: bool,
    contactor_welded: bool,
    /// Counts the steering encoder has gained by slipping.
    steer_slip_counts: i64,
    /// Drawn once per step, so `inputs()` can stay `&self`.
    pot_noise_v: f64,
    pot_rng: ChaCha8Rng,
    /// Frozen counts of stuck encoders: left, right, steer.
    stuck_counts: [Option<i64>; 3],
    events: Vec<SimEvent>,
    next_event: usize,
    tool: ToolTrack,
    /// How the amplifiers and encoders are wired ([sim] miswire).
    wires: Wires,
}

impl SimRobot {
    /// `camera` is the simulated camera computer's end of the byte pipe.
    pub fn new(params: &SimParams, camera: PipeEnd) -> SimRobot {
        SimRobot::with_gnss(params, camera, None)
    }

    /// With a GNSS receiver that writes its NMEA lines into `gnss` (its end), there from
    /// the start, so that events at time 0 reach it too.
    pub fn with_gnss(params: &SimParams, camera: PipeEnd, gnss: Option<PipeEnd>) -> SimRobot {
        let p = params.sanitized();
        let field = Field::new(&p);
        let (x_m, y_m, heading_rad) = field.point_at(0.0);
        let pose = Pose {
            x_m: x_m - heading_rad.sin() * p.start_offset_m,
            y_m: y_m + heading_rad.cos() * p.start_offset_m,
            heading_rad,
        };
        let gain = |share: f64| p.motor_gain_mps_per_v * (1.0 + share * p.motor_mismatch);
        let wheel =
            |gain: f64| DriveWheel::new(gain, p.motor_tau_s, p.motor_deadband_v, p.brake_stop_s);
        let mut events = p.events.clone();
        events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        let mut robot = SimRobot {
            camera: CameraComputer::new(&p, camera),
            gnss: gnss.map(|pipe| SimReceiver::new(&p, pipe)),
            left: wheel(gain(0.5)),
            right: wheel(gain(-0.5)),
            steering: Steering::new(
                p.steer_rate_dps_per_v,
                p.steer_lag_s,
                p.steer_limit_deg,
                p.end_switch_deg,
                p.initial_wheel_angle_deg,
            ),
            pose,
            steps: 0,
            distance_m: 0.0,
            outputs: Outputs::SAFE,
            joystick: Joystick::default(),
            estop_front_released: true,
            estop_back_released: true,
            power_lost: false,
            battery_v: p.battery_v,
            pot_broken: false,
            contactor_welded: false,
            steer_slip_counts: 0,
            pot_noise_v: 0.0,
            pot_rng: ChaCha8Rng::seed_from_u64(p.seed.wrapping_add(SEED_POT)),
            stuck_counts: [None; 3],
            events,
            next_event: 0,
            tool: ToolTrack::new(p.tool_offset_m, p.cross_track_from_m),
            wires: Wires {
                miswire: p.miswire,
                ..Wires::default()
            },
            // The robot drives a little past the row's line, so lay the field out beyond it.
            tier: FieldTier::new(&p, field.length_m() + 10.0),
            field,
            p,
        };
        robot.draw_pot_noise();
        robot.tool.measure(&robot.field, &robot.pose, 0.0);
        robot.apply_due_events();
        robot
    }

    /// Integrate up to `t_s` in whole steps; does nothing if `t_s` is not later than now.
    pub fn advance_to(&mut self, t_s: f64) {
        // A target within a millionth of a step of a step boundary reaches it.
        let target_steps = (t_s / self.p.step_s + 1e-6).floor();
        while (self.steps as f64) < target_steps {
            self.step();
        }
    }

    pub(crate) fn time_s(&self) -> f64 {
        self.steps as f64 * self.p.step_s
    }

    fn step(&mut self) {
        let dt_s = self.p.step_s;
        let o = self.outputs;
        let v_before = self.speed_mps();
        self.left
            .step(self.amp_v(0, o.amp_left_v), !o.brake_release_left, dt_s);
        self.right
            .step(self.amp_v(1, o.amp_right_v), !o.brake_release_right, dt_s);
        self.steering.step(self.amp_v(2, o.amp_steer_v), dt_s);
        // The body moves at the step's mean wheel speed, as the encoders count it, less
        // what the wheels slip on loose soil (then the encoders over-read).
        let rim_mps = 0.5 * (v_before + self.speed_mps());
        let v_mps = rim_mps * (1.0 - self.tier.wheel_slip(self.distance_m));
        let slip_rad = self.tier.side_slip_rad(self.distance_m);
        self.pose.step(
            v_mps,
            self.steering.angle_rad(),
            self.p.wheelbase_m,
            slip_rad,
            dt_s,
        );
        self.distance_m += v_mps.abs() * dt_s;
        while let Some(bump) = self.tier.bump_reached(self.distance_m) {
            self.pose.kick(bump.heading_rad, bump.side_m);
        }
        self.steps += 1;
        self.draw_pot_noise();
        self.tool.measure(&self.field, &self.pose, self.distance_m);
        self.camera.tick(
            self.time_s(),
            &self.pose,
            &self.field,
            &self.tier,
            self.distance_m,
        );
        let now_s = self.time_s();
        if let Some(gnss) = &mut self.gnss {
            gnss.tick(now_s, &self.pose, v_mps, self.distance_m);
        }
        self.apply_due_events();
    }

    /// What amplifier `k` (left, right, steering) puts on its motor: its command,
    /// clamped, through its wires, while the contactor is closed.
    fn amp_v(&self, k: usize, commanded_v: f64) -> f64 {
        if self.motor_power_present() && commanded_v.is_finite() {
            let v = commanded_v.clamp(-AMP_MAX_V, AMP_MAX_V);
            self.wires.motor_v(k, v, AMP_MAX_V)
        } else {
            0.0
        }
    }

    /// The contactor: closed while the relay asks for it, both e-stops are released and
    /// the battery is there. A welded contactor stays closed whatever the relay and the e-stops say.
    fn motor_power_present(&self) -> bool {
        let closed = self.contactor_welded
            || (self.outputs.main_power_on
                && self.estop_front_released
                && self.estop_back_released);
        closed && !self.power_lost
    }

    fn speed_mps(&self) -> f64 {
        0.5 * (self.left.speed_mps() + self.right.speed_mps())
    }

    fn draw_pot_noise(&mut self) {
        let unit: f64 = self.pot_rng.sample(StandardNormal);
        self.pot_noise_v = unit * self.p.pot_noise_v;
    }

    /// What the encoder would count if it were not stuck.
    fn encoder_counts(&self, id: EncoderId) -> i64 {
        // `as` saturates (and maps NaN to 0), so no input can make this panic.
        match id {
            EncoderId::Left => (self.left.travel_m() * self.p.enc_counts_per_m).floor() as i64,
            EncoderId::Right => (self.right.travel_m() * self.p.enc_counts_per_m).floor() as i64,
            EncoderId::Steer => {
                let turned_deg = self.steering.angle_deg() - self.p.initial_wheel_angle_deg;
                (turned_deg * self.p.steer_counts_per_deg).floor() as i64 + self.steer_slip_counts
            }
        }
    }

    fn encoder(&self, id: EncoderId) -> i64 {
        let k = id as usize;
        self.stuck_counts[k].unwrap_or_else(|| self.wires.count(k, self.encoder_counts(id)))
    }

    /// Wire the amplifiers and encoders as `miswire` says from now on.
    fn rewire(&mut self, miswire: Miswire) {
        let counts =
            [EncoderId::Left, EncoderId::Right, EncoderId::Steer].map(|id| self.encoder_counts(id));
        self.wires.rewire(miswire, counts);
    }

    /// The wiring mistake made now ([sim] miswire, or the last `miswire` event).
    pub fn miswire(&self) -> Miswire {
        self.wires.miswire
    }

    /// The amplifiers' commands come through emulated cards from now on, whose DDA06
    /// models its own range switches (`dda06_unipolar` is theirs to apply).
    pub fn dacs_on_cards(&mut self) {
        self.wires.dacs_on_cards = true;
    }

    /// The sensors now.
    pub fn inputs(&self) -> Inputs {
        Inputs {
            pot_v: if self.pot_broken {
                0.0
            } else {
                self.steering.pot_v() + self.pot_noise_v
            },
            joystick_steer_v: self.joystick.steer_v,
            joystick_speed_v: self.joystick.speed_v,
            battery_v: if self.power_lost { 0.0 } else { self.battery_v },
            estop_front_released: self.estop_front_released,
            estop_back_released: self.estop_back_released,
            motor_power_present: self.motor_power_present(),
            end_switch_left: self.steering.end_switch_left(),
            end_switch_right: self.steering.end_switch_right(),
            joystick_enable: self.joystick.enable,
            enc_left_counts: self.encoder(EncoderId::Left),
            enc_right_counts: self.encoder(EncoderId::Right),
            enc_steer_counts: self.encoder(EncoderId::Steer),
        }
    }

    /// Commanded outputs, held until the next call.
    pub fn set_outputs(&mut self, outputs: &Outputs) {
        self.outputs = *outputs;
    }

    pub fn outputs(&self) -> Outputs {
        self.outputs
    }

    /// The operator's joystick (volts as wired) and dead-man button.
    pub fn set_joystick(&mut self, steer_v: f64, speed_v: f64, enable: bool) {
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        self.joystick = Joystick {
            steer_v: finite(steer_v),
            speed_v: finite(speed_v),
            enable,
        };
    }

    pub fn truth(&self) -> Truth {
        Truth {
            t_s: self.time_s(),
            x_m: self.pose.x_m,
            y_m: self.pose.y_m,
            heading_rad: self.pose.heading_rad,
            speed_mps: self.speed_mps(),
            wheel_angle_rad: self.steering.angle_rad(),
            v_left_mps: self.left.speed_mps(),
            v_right_mps: self.right.speed_mps(),
            tool_cross_track_m: self.tool.cross_track_m(),
            distance_m: self.distance_m,
            row_done: self.tool.row_done(),
        }
    }

    pub fn cross_track(&self) -> &CrossTrackStats {
        self.tool.stats()
    }

    pub fn field(&self) -> &Field {
        &self.field
    }

    /// The field's own row map, as its planting machine recorded it (field_map.rs).
    pub fn planted_map(&self) -> Vec<crate::geo::Geodetic> {
        super::field_map::planted_map(&self.field, &self.p)
    }

    /// The simulated GNSS receiver, if one is attached.
    pub fn gnss(&self) -> Option<&SimReceiver> {
        self.gnss.as_ref()
    }

    /// The simulated camera computer (its state and counters).
    pub fn camera(&self) -> &CameraComputer {
        &self.camera
    }

    /// Travel before this is left out of the cross-track figures, m.
    pub(crate) fn cross_track_from_m(&self) -> f64 {
        self.p.cross_track_from_m
    }
}

#[path = "robot_events.rs"]
mod events_applied;

#[cfg(test)]
#[path = "robot_tests.rs"]
mod tests;

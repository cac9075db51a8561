//! robot.ini -> typed settings. Every setting lives in config/robot.ini with a comment
//! and its unit; there are no hidden defaults in the code, so what the file says is
//! what the robot does. Errors name the file, line, section and key.

mod bus;
mod camera_port;
mod cards_only;
mod checks;
mod filter;
mod gnss;
mod gui;
mod io;
mod joystick;
mod lines;
mod motion_faults;
mod pid;
mod reader;
mod real_robot;
mod record;
mod ros2;
mod rt;
mod sim;
mod source;
mod steer;
mod test_panel;
pub mod upgrade;
mod watchdog_relay;

use std::path::Path;

pub use bus::{
    AcceptRequests, BusSettings, ROSTER_FILE, TlsFiles, endpoint_address, is_loopback,
    listen_refusal, optional_yes, parse_endpoints, parse_prefix, tls_files,
};
pub use camera_port::{BAUD_RATES, CameraPort};
pub use cards_only::CardsOnly;
pub use filter::{FILTER_MAX_STEP_M, FilterConfig};
pub use gnss::{GnssPort, GnssSettings, MapSource, SourceSettings, SteerSource};
pub use joystick::{GamepadDevice, GamepadSettings, JoystickSettings, JoystickSource};
pub use lines::{parse_seconds, read_text};
pub use motion_faults::MotionFaultSettings;
pub use pid::{PdSettings, PiSettings};

pub use gui::{GuiSettings, Theme};
pub use reader::{ConfigError, Place, Reader, override_parts};
pub use record::{RecordFormats, RecordSettings};
pub use ros2::{Distro, MAX_DOMAIN_ID, Ros2Settings, parse_namespace, parse_router};
pub use source::SettingsSource;
pub use steer::{SteerLaw, SteerSettings};
pub use test_panel::TestSettings;
pub use watchdog_relay::{NO_RELAY, WatchdogRelay};

/// The settings file shipped with the program, used when no file is given and
/// config/robot.ini is not in the working directory.
pub const DEFAULT_INI: &str = include_str!("../../../config/robot.ini");

/// Every section the file must have.
const SECTIONS: &[&str] = &[
    "robot",
    "supervisor",
    "faults",
    "pid.left",
    "pid.right",
    "pid.steer",
    "steer",
    "joystick",
    "camera",
    "hw",
    "rt",
    "io",
    "sim",
    "record",
    "bus",
    "gnss",
    "filter",
    "gui",
];

/// The controller's model of the robot (the simulated plant has its own, in [sim]).
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSettings {
    pub wheelbase_m: f64,
    pub track_m: f64,
    pub enc_counts_per_m: f64,
    pub steer_counts_per_deg: f64,
    pub pot_centre_v: f64,
    pub pot_v_per_deg: f64,
    pub max_wheel_angle_deg: f64,
    pub end_switch_deg: f64,
    pub tool_offset_m: f64,
    pub camera_lookahead_m: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct SupervisorSettings {
    pub rate_hz: f64,
    pub max_speed_mps: f64,
    pub accel_mps2: f64,
    pub wheel_angle_rate_dps: f64,
    pub calibration_s: f64,
    pub power_up_timeout_s: f64,
    pub speed_filter_s: f64,
    /// Length of the rows, m; 0 = not known (see `Settings::row_length_m`).
    pub row_length_m: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct FaultSettings {
    pub battery_min_v: f64,
    pub battery_low_s: f64,
    pub pot_min_v: f64,
    pub pot_max_v: f64,
    pub pot_disagree_deg: f64,
    pub pot_disagree_s: f64,
    pub encoder_stuck_v: f64,
    pub encoder_stuck_s: f64,
    pub endswitch_unhandled_s: f64,
    pub endswitch_timeout_s: f64,
    pub contactor_drop_s: f64,
    /// Steering by GNSS or the fused row: the row filter's row farther than this from
    /// the rear axle is the robot off its row, m.
    pub off_row_m: f64,
    /// Wrong-way, speed and uncommanded-motion checks (motion_faults.rs).
    pub motion: MotionFaultSettings,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSettings {
    pub link_timeout_s: f64,
    pub restart_after_s: f64,
    pub min_quality: u8,
    /// A camera repeating its last estimate (a gap in the row) steers for this far, m.
    pub gap_hold_m: f64,
    /// In a gap, and while looking for the first plants, the robot drives this fast at
    /// most, m/s.
    pub gap_speed_mps: f64,
    /// Autonomous mode begun where the camera sees no row: the robot drives straight
    /// ahead for at most this far to find the first plants, m.
    pub first_row_m: f64,
}

/// Real-time scheduling and the supervisor's watch over the other threads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RtSettings {
    pub supervisor_priority: u8,
    pub steer_priority: u8,
    pub camlink_priority: u8,
    pub lock_memory: bool,
    pub supervisor_cpu: i32,
    /// CPU the operator GUI (and its software renderer) is pinned to, -1 = any.
    pub gui_cpu: i32,
    pub heartbeat_timeout_s: f64,
    pub gui_heartbeat_timeout_s: f64,
    pub max_overruns: u32,
    pub overrun_window_s: f64,
    pub max_late_periods: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    Sim,
    /// The robot's three I/O cards, wired as [io] says.
    Cards,
}

/// Everything in robot.ini, typed.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub robot: RobotSettings,
    pub supervisor: SupervisorSettings,
    pub faults: FaultSettings,
    pub pid_left: PiSettings,
    pub pid_right: PiSettings,
    pub pid_steer: PdSettings,
    pub steer: SteerSettings,
    /// Which sensors steer ([steer] source and its fallbacks).
    pub sources: SourceSettings,
    /// The row filter ([filter]).
    pub filter: FilterConfig,
    pub joystick: JoystickSettings,
    /// The gamepad's device, buttons and axes ([joystick] gamepad_*).
    pub gamepad: GamepadSettings,
    pub camera: CameraSettings,
    /// Where the camera computer is: [camera] port and baud.
    pub camera_port: CameraPort,
    pub rt: RtSettings,
    pub backend: Backend,
    /// Where the I/O cards are and how they are set ([hw]).
    pub cards: mechweed_hw::cards::CardsSettings,
    /// How the robot is wired to the cards ([io]).
    pub io: mechweed_hw::cards::wiring::Wiring,
    /// Whether the robot has the charge-pump relay ([io] watchdog_relay).
    pub watchdog_relay: WatchdogRelay,
    pub sim: mechweed_hw::sim::SimParams,
    /// Where and how each run is recorded.
    pub record: RecordSettings,
    /// The data flows to and from other programs ([bus]).
    pub bus: BusSettings,
    /// The RTK GNSS receiver and the row map ([gnss]).
    pub gnss: GnssSettings,
    /// The operator's window ([gui]).
    pub gui: GuiSettings,
    /// How `mechweed ros2` shows the robot to ROS 2 tools; None: no [ros2] section.
    pub ros2: Option<Ros2Settings>,
    /// The limits of mode Test ([test]).
    pub test: TestSettings,
    /// The text these settings were read from, for the bus's configuration ports.
    pub source: SettingsSource,
}

impl Settings {
    /// Read and check a settings file, with `--set SECTION.KEY=VALUE` overrides.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Settings, Vec<ConfigError>> {
        let label = path.display().to_string();
        let text = lines::read_text(path, "the settings file")?;
        Settings::parse(&label, &text, overrides)
    }

    /// The settings shipped with the program, as in config/robot.ini.
    pub fn shipped() -> Settings {
        Settings::parse("config/robot.ini", DEFAULT_INI, &[])
            .expect("the shipped config/robot.ini is checked by the tests")
    }

    /// As `load`, for a file meant for the real robot (`check-config --real-robot`).
    pub fn load_real_robot(path: &Path) -> Result<Settings, Vec<ConfigError>> {
        let text = lines::read_text(path, "the settings file")?;
        Settings::read(&path.display().to_string(), &text, &[], true)
    }

    /// Read settings from text (`file` names it in messages).
    pub fn parse(
        file: &str,
        text: &str,
        overrides: &[String],
    ) -> Result<Settings, Vec<ConfigError>> {
        Settings::read(file, text, overrides, false)
    }

    fn read(
        file: &str,
        text: &str,
        overrides: &[String],
        real_robot: bool,
    ) -> Result<Settings, Vec<ConfigError>> {
        let mut r = Reader::new(file, text, overrides);
        let mut settings = Settings {
            robot: robot(&mut r),
            supervisor: supervisor(&mut r),
            faults: faults(&mut r),
            pid_left: pid::pi(&mut r, "pid.left"),
            pid_right: pid::pi(&mut r, "pid.right"),
            pid_steer: pid::pd(&mut r, "pid.steer"),
            steer: steer::load(&mut r),
            sources: gnss::sources(&mut r),
            filter: filter::load(&mut r),
            joystick: joystick::load(&mut r),
            gamepad: joystick::gamepad(&mut r),
            camera: camera(&mut r),
            camera_port: camera_port::load(&mut r),
            rt: rt::load(&mut r),
            backend: [Backend::Sim, Backend::Cards][r.choice("hw", "backend", &["sim", "cards"])],
            cards: io::cards(&mut r),
            io: io::wiring(&mut r),
            watchdog_relay: watchdog_relay::load(&mut r),
            sim: sim::load(&mut r),
            record: record::load(&mut r),
            bus: bus::load(&mut r),
            gnss: gnss::load(&mut r),
            gui: gui::load(&mut r),
            ros2: ros2::load(&mut r),
            test: TestSettings::shipped(),
            source: SettingsSource {
                label: file.to_string(),
                text: text.to_string(),
                overrides: overrides.to_vec(),
            },
        };
        settings.test = test_panel::load(&mut r, &settings.faults);
        checks::across(&settings, &mut r);
        real_robot::check(&settings, &mut r);
        watchdog_relay::check(&settings, &mut r);
        test_panel::check(&settings, &mut r);
        if real_robot {
            real_robot::require_cards(&settings, &mut r);
        }
        gnss::check(&settings, &mut r);
        let errors = r.finish_with(SECTIONS, &["ros2", "test"]);
        if errors.is_empty() {
            Ok(settings)
        } else {
            Err(errors)
        }
    }
}

fn robot(r: &mut Reader) -> RobotSettings {
    let s = "robot";
    RobotSettings {
        wheelbase_m: r.f64(s, "wheelbase_m", 0.2, 5.0),
        track_m: r.f64(s, "track_m", 0.2, 5.0),
        enc_counts_per_m: r.f64(s, "enc_counts_per_m", 1.0, 1e7),
        steer_counts_per_deg: r.f64(s, "steer_counts_per_deg", 1.0, 1e6),
        pot_centre_v: r.f64(s, "pot_centre_v", 0.0, 5.0),
        pot_v_per_deg: r.f64(s, "pot_v_per_deg", 0.001, 1.0),
        max_wheel_angle_deg: r.f64(s, "max_wheel_angle_deg", 1.0, 45.0),
        end_switch_deg: r.f64(s, "end_switch_deg", 1.0, 60.0),
        tool_offset_m: r.f64(s, "tool_offset_m", -3.0, 3.0),
        camera_lookahead_m: r.f64(s, "camera_lookahead_m", 0.0, 5.0),
    }
}

fn supervisor(r: &mut Reader) -> SupervisorSettings {
    let s = "supervisor";
    SupervisorSettings {
        rate_hz: r.f64(s, "rate_hz", 10.0, 2000.0),
        max_speed_mps: r.f64(s, "max_speed_mps", 0.0, 3.0),
        accel_mps2: r.f64(s, "accel_mps2", 0.01, 10.0),
        wheel_angle_rate_dps: r.f64(s, "wheel_angle_rate_dps", 1.0, 200.0),
        calibration_s: r.f64(s, "calibration_s", 0.0, 5.0),
        power_up_timeout_s: r.f64(s, "power_up_timeout_s", 0.05, 10.0),
        speed_filter_s: r.f64(s, "speed_filter_s", 0.0, 1.0),
        row_length_m: r.f64(s, "row_length_m", 0.0, 10000.0),
    }
}

fn faults(r: &mut Reader) -> FaultSettings {
    let s = "faults";
    FaultSettings {
        battery_min_v: r.f64(s, "battery_min_v", 0.0, 60.0),
        // The robot drives on a low battery this long: enough to ride out a load dip.
        battery_low_s: r.f64(s, "battery_low_s", 0.0, 10.0),
        pot_min_v: r.f64(s, "pot_min_v", 0.0, 5.0),
        pot_max_v: r.f64(s, "pot_max_v", 0.0, 5.0),
        // 30 deg of disagreement would hide a slipping steering encoder on a 25 deg robot.
        pot_disagree_deg: r.f64(s, "pot_disagree_deg", 0.1, 10.0),
        // Times that guard motion (a wrong wheel angle, a wheel without feedback, a
        // steering at its end switch): at most about a second of driving.
        pot_disagree_s: r.f64(s, "pot_disagree_s", 0.0, 1.0),
        encoder_stuck_v: r.f64(s, "encoder_stuck_v", 0.5, 10.0),
        encoder_stuck_s: r.f64(s, "encoder_stuck_s", 0.05, 1.0),
        endswitch_unhandled_s: r.f64(s, "endswitch_unhandled_s", 0.01, 1.0),
        // The robot stands while the procedure steers back, so this one may be longer.
        endswitch_timeout_s: r.f64(s, "endswitch_timeout_s", 0.1, 10.0),
        // A real contactor drops in tens of milliseconds; a second is plenty.
        contactor_drop_s: r.f64(s, "contactor_drop_s", 0.02, 1.0),
        off_row_m: r.f64(s, "off_row_m", 0.02, 2.0),
        motion: motion_faults::load(r),
    }
}

fn camera(r: &mut Reader) -> CameraSettings {
    let s = "camera";
    CameraSettings {
        // The oldest estimate the robot steers by: at most about a second of driving.
        link_timeout_s: r.f64(s, "link_timeout_s", 0.05, 1.0),
        // Only when START is sent again (link_timeout_s guards the driving); longer than a
        // few seconds just delays finding a rebooted camera computer.
        restart_after_s: r.f64(s, "restart_after_s", 0.05, 5.0),
        // Quality 0 means "no row seen" (function_spec.md section 7): such a frame must never steer.
        min_quality: r.u64(s, "min_quality", 1, 100) as u8,
        // Beyond a few metres odometry alone no longer keeps the tool on the row.
        gap_hold_m: r.f64(s, "gap_hold_m", 0.0, 10.0),
        gap_speed_mps: r.f64(s, "gap_speed_mps", 0.0, 3.0),
        first_row_m: r.f64(s, "first_row_m", 0.0, 10.0),
    }
}

//! `mechweed ros2`: the robot's flows as ROS 2 topics, for rviz2, `ros2 topic echo`,
//! PlotJuggler and Foxglove on the ROS machines (src/ros2/, docs/ros2.md). Its
//! settings are robot.ini's [ros2]; each flag here overrides one.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};

use crate::config::{Distro, Ros2Settings, TlsFiles, parse_namespace, parse_router};
use crate::console::ctrl_c;
use crate::programs::bus::tools::Tool;
use crate::programs::{load_settings, print_errors};
use crate::ros2::halt::AskHalt;
use crate::ros2::model::RobotModel;
use crate::ros2::odom::Frames;

#[derive(clap::Args)]
pub struct Ros2Args {
    /// The ROS machines' router, rmw_zenohd ([ros2] connect), e.g. tcp/192.168.1.20:7447.
    #[arg(long, value_name = "ENDPOINT", value_parser = parse_router)]
    pub connect: Option<String>,
    /// ROS_DOMAIN_ID of the ROS machines ([ros2] domain_id, 0..232).
    #[arg(long, value_name = "ID", value_parser = clap::value_parser!(u32).range(0..=crate::config::MAX_DOMAIN_ID as i64))]
    pub domain_id: Option<u32>,
    /// The namespace of the node and the robot's topics ([ros2] namespace), e.g. /mechweed.
    #[arg(long, value_name = "NAMESPACE", value_parser = parse_namespace)]
    pub namespace: Option<String>,
    /// The ROS 2 release of the ROS machines ([ros2] distro).
    #[arg(long, value_name = "RELEASE", value_parser = clap::builder::PossibleValuesParser::new(Distro::NAMES))]
    pub distro: Option<String>,
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, value_name = "ENDPOINT", default_value = crate::programs::bus::tools::DEFAULT_ENDPOINT)]
    pub robot_connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(long, value_name = "NAME", default_value = "mechweed")]
    pub robot: String,
    /// Stop after this many seconds (default: at Ctrl-C).
    #[arg(long, value_name = "SECONDS", value_parser = crate::config::parse_seconds)]
    pub seconds: Option<f64>,
    /// Print the robot's URDF (made from the settings file, as robot_description
    /// carries it) and end, connecting to nothing.
    #[arg(long)]
    pub urdf: bool,
    /// Settings file (its [ros2]) [default: config/robot.ini, or the built-in copy]
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Override one setting, e.g. --set ros2.wheel_radius_m=0.25 (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// This program's identity on a secured bus (--keys DIR --as NAME, a viewer).
    #[command(flatten)]
    pub identity: crate::programs::keys::IdentityArgs,
}

impl Ros2Args {
    /// [ros2] from the settings file (the shipped values when it has none, said), with
    /// the flags over it, and the robot's model from the same file.
    fn settings(&self) -> Result<(Ros2Settings, RobotModel), ExitCode> {
        let settings = load_settings(self.config.as_deref(), &self.set).map_err(|errors| {
            print_errors(&errors);
            ExitCode::FAILURE
        })?;
        let model = RobotModel::of(&settings);
        let mut ros = settings.ros2.unwrap_or_else(|| {
            eprintln!("ros2: the settings file has no [ros2]: using the shipped values");
            Ros2Settings::shipped()
        });
        if let Some(connect) = &self.connect {
            ros.connect = connect.clone();
        }
        if let Some(id) = self.domain_id {
            ros.domain_id = id;
        }
        if let Some(namespace) = &self.namespace {
            ros.namespace = namespace.clone();
        }
        if let Some(distro) = self.distro.as_deref().and_then(Distro::from_name) {
            ros.distro = distro;
        }
        Ok((ros, model))
    }
}

/// The ROS router and the robot's bus at one endpoint would be one Zenoh network, the
/// robot's flows and ROS's mixed, and no ROS machine would hear the topics: refused.
/// The shipped ends are apart (7447 and 7510); a robot.ini that still listens on 7447,
/// or a flag, can put them together.
fn check_apart(router: &str, robot: &str) -> Result<(), String> {
    if router == robot {
        return Err(format!(
            "the ROS router and the robot's bus are both at {router}: one Zenoh network, where no ROS machine would hear the robot's topics. rmw_zenohd listens on port 7447, the robot program on 7510 unless its [bus] listen says otherwise. Start rmw_zenohd on the ROS machine and name it with --connect, or move one: [bus] listen on the robot, --robot-connect here"
        ));
    }
    Ok(())
}

pub fn run(args: Ros2Args) -> ExitCode {
    let (ros, model) = match args.settings() {
        Ok(settings) => settings,
        Err(code) => return code,
    };
    if args.urdf {
        print!("{}", model.urdf(&Frames::new(&ros.frame_prefix)));
        return ExitCode::SUCCESS;
    }
    if let Err(why) = check_apart(&ros.connect, &args.robot_connect) {
        eprintln!("{why}");
        return ExitCode::FAILURE;
    }
    let halt = (ros.halt_service)
        .then(|| ask_halt(&args.robot_connect, &args.robot, args.identity.files()));
    let opts = crate::ros2::bridge::Options {
        connect: args.robot_connect,
        robot: args.robot,
        halt,
        ros,
        model,
        tls: args.identity.files(),
        seconds: args.seconds,
    };
    crate::programs::said(crate::ros2::bridge::run(&opts, &ctrl_c()))
}

/// How the HALT service asks the robot: `request halt` on its bus, as `mechweed bus
/// request halt` does, through a session made at the first call and made again after
/// a call that failed (the robot restarted, say).
fn ask_halt(endpoint: &str, robot: &str, tls: Option<TlsFiles>) -> AskHalt {
    let (endpoint, robot) = (endpoint.to_string(), robot.to_string());
    let tool: Mutex<Option<Tool>> = Mutex::new(None);
    Arc::new(move || {
        let mut tool = tool.lock().unwrap_or_else(|e| e.into_inner());
        if tool.is_none() {
            *tool = Some(Tool::connect(&endpoint, &robot, false, tls.as_ref())?);
        }
        let halt = serde_json::json!({ "request": "halt" }).to_string();
        let answer = tool.as_ref().map(|t| t.ask("request", Some(halt)));
        let answer = answer.unwrap_or_else(|| Err("no session".to_string()));
        if answer.is_err() {
            *tool = None;
        }
        answer
    })
}

#[cfg(test)]
mod tests {
    use super::check_apart;
    use crate::config::Settings;
    use crate::programs::bus::tools::DEFAULT_ENDPOINT;

    #[test]
    fn the_shipped_router_and_robot_are_apart_and_one_endpoint_is_refused() {
        let router = Settings::shipped()
            .ros2
            .expect("robot.ini has [ros2]")
            .connect;
        assert_eq!(check_apart(&router, DEFAULT_ENDPOINT), Ok(()));
        let why = check_apart(&router, &router).unwrap_err();
        assert!(why.contains(&format!("both at {router}")), "{why}");
    }
}

//! `mechweed record ...`: a record's summary, and the off-board recorder.

use std::process::ExitCode;

use std::path::PathBuf;

use clap::Subcommand;

use crate::console::ctrl_c;
use crate::programs::{load_settings, parse_metres, print_errors};

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
#[command(group(clap::ArgGroup::new("from_bus").args(["bus", "ros2"])))]
pub struct RecordArgs {
    #[command(subcommand)]
    pub command: Option<RecordCommand>,
    /// Record the robot's flows on the bus, on this computer: the same CSV and MCAP
    /// files as a run record, into [record] folder, until Ctrl-C.
    #[arg(long)]
    pub bus: bool,
    /// Record the robot's flows on the bus as a ROS 2 bag: the topics of `mechweed
    /// ros2`, CDR in MCAP (mechweed-ros2-UTC.mcap in [record] folder), which `ros2 bag
    /// play` and Foxglove take, until Ctrl-C.
    #[arg(long)]
    pub ros2: bool,
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, value_name = "ENDPOINT", default_value = crate::programs::bus::tools::DEFAULT_ENDPOINT, requires = "from_bus")]
    pub connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(
        long,
        value_name = "NAME",
        default_value = "mechweed",
        requires = "from_bus"
    )]
    pub robot: String,
    /// Stop after this many seconds.
    #[arg(long, value_name = "SECONDS", value_parser = crate::config::parse_seconds, requires = "from_bus")]
    pub seconds: Option<f64>,
    /// Settings file (its [record] folder and formats) [default: config/robot.ini, or the built-in copy]
    #[arg(long, value_name = "FILE", requires = "from_bus")]
    pub config: Option<PathBuf>,
    /// Override one setting, e.g. --set record.folder=field-records (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE", requires = "from_bus")]
    pub set: Vec<String>,
    /// With --bus or --ros2: this program's identity on a secured bus (--keys DIR --as
    /// recorder, or a viewer).
    #[command(flatten)]
    pub identity: crate::programs::keys::IdentityArgs,
}

#[derive(Subcommand)]
pub enum RecordCommand {
    /// Print a record's duration, distance, modes, faults and cross-track figures.
    Summary {
        /// The record: NAME.csv (with NAME.events.csv beside it) or NAME.mcap, or
        /// `latest` for the newest record in the settings' [record] folder.
        file: PathBuf,
        /// Settings file, for `latest` [default: config/robot.ini, or the built-in copy]
        #[arg(long, value_name = "FILE")]
        config: Option<PathBuf>,
        /// Override one setting, e.g. --set record.folder=old-records (repeatable).
        #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Cross-track figures from this distance on, m (the run report's 5 m; 0 for
        /// short runs).
        #[arg(long, value_name = "METRES", default_value_t = 5.0, value_parser = parse_metres)]
        from_m: f64,
    },
}

pub fn record(mut args: RecordArgs) -> ExitCode {
    match (args.bus || args.ros2, args.command.take()) {
        (false, Some(command)) => summary(command),
        (true, _) => from_bus(args),
        (false, None) => {
            eprintln!(
                "say what to do with records: `mechweed record summary FILE`, `mechweed record --bus` to record the robot's flows here, or `mechweed record --ros2` for a ROS 2 bag of them"
            );
            ExitCode::FAILURE
        }
    }
}

/// `record --bus` (the run's CSV and MCAP files) or `record --ros2` (a ROS 2 bag): the
/// robot's flows recorded on this computer.
fn from_bus(args: RecordArgs) -> ExitCode {
    let settings = match load_settings(args.config.as_deref(), &args.set) {
        Ok(settings) => settings,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let tls = args.identity.files();
    let done = if args.ros2 {
        let opts = crate::ros2::bag::Options {
            connect: args.connect,
            robot: args.robot,
            seconds: args.seconds,
            model: crate::ros2::model::RobotModel::of(&settings),
            record: settings.record,
            ros: settings
                .ros2
                .unwrap_or_else(crate::config::Ros2Settings::shipped),
            tls,
        };
        crate::ros2::bag::record(&opts, &ctrl_c())
    } else {
        let opts = crate::programs::bus::record::Options {
            connect: args.connect,
            robot: args.robot,
            seconds: args.seconds,
            record: settings.record,
            tls,
        };
        crate::programs::bus::record::record(&opts, &ctrl_c())
    };
    match done {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

fn summary(command: RecordCommand) -> ExitCode {
    let RecordCommand::Summary {
        file,
        from_m,
        config,
        set,
    } = command;
    let file = if file.as_os_str() == "latest" {
        let settings = match load_settings(config.as_deref(), &set) {
            Ok(settings) => settings,
            Err(errors) => {
                print_errors(&errors);
                return ExitCode::FAILURE;
            }
        };
        match crate::record::keep::latest(&settings.record.folder) {
            Ok(newest) => {
                println!("the newest record: {}", newest.display());
                newest
            }
            Err(why) => {
                eprintln!("{why}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        file
    };
    if crate::ros2::bag_read::is_ros2_bag(&file) {
        return crate::programs::said(crate::ros2::bag_read::summary(&file).map(|text| {
            print!("{text}");
            String::new()
        }));
    }
    match crate::record::summary::summarise(&file, from_m) {
        Ok(summary) => {
            print!("{}", summary.text());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

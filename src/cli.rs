//! The command line's words: every command and option of `mechweed`, as clap reads them.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

use mechweed::gui::Tab;

#[derive(Parser)]
#[command(
    name = "mechweed",
    version,
    about = "Control program for the weeding robot. Runs on the simulated robot unless config/robot.ini [hw] says otherwise.",
    after_help = "Without a command, mechweed runs as `mechweed run` and takes its options (e.g. `mechweed --headless`): the operator GUI on the simulated robot.",
    // `mechweed --headless` is `mechweed run --headless`; the run's options mean nothing
    // before another command.
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The options of `run`, for `mechweed` without a command.
    #[command(flatten)]
    pub run: RunArgs,
}

#[derive(Subcommand)]
pub enum Command {
    /// Run the controller on real threads and real time.
    Run(RunArgs),
    /// Check a settings file: prints "ok", or every error found (exit 1).
    CheckConfig {
        /// The settings file [default: config/robot.ini]
        file: Option<PathBuf>,
    },
    /// Benchmarks on the simulated robot.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// A stand-alone simulated camera computer, for bench tests of a link.
    Camsim(mechweed::camsim_main::CamsimArgs),
    /// Teach a row for the row map: drive it in joystick mode with the weeding tool on the
    /// row (or give a record of such a drive); the tool's path goes into the map file.
    Teach(TeachArgs),
    /// A stand-alone simulated RTK GNSS receiver (NMEA on a serial device or TCP), for
    /// bench tests of the GNSS link.
    Gnsssim(mechweed::gnsssim::GnssSimArgs),
    /// List the gamepads; find the I/O cards and read every input once (writes nothing
    /// but safe outputs).
    Probe {
        /// Also print the cards' registers.
        #[arg(long)]
        raw: bool,
        /// Settings file (card locations, wiring) [default: config/robot.ini, or the built-in copy]
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Run records (CSV or MCAP) left by `mechweed run`, and the off-board recorder
    /// (`record --bus`).
    Record(RecordArgs),
    /// Feed a record's inputs through the supervisor again: the same outputs, or with
    /// --set a what-if on the same inputs.
    Replay(crate::replay_command::ReplayArgs),
    /// The robot's data flows on the bus, from this or another computer.
    Bus(BusArgs),
    /// The virtual cluster: one graph file starts the programs of several machines.
    #[command(subcommand)]
    Cluster(crate::cluster_command::ClusterCommand),
    /// The operator GUI on another computer, fed by the robot's flows on the bus.
    Watch(crate::cluster_command::WatchArgs),
    /// The cluster's certificates: who may do what on the bus and the cluster.
    #[command(subcommand)]
    Keys(mechweed::keys::command::KeysCommand),
}

#[derive(clap::Args)]
pub struct TeachArgs {
    /// The row's name in the map (e.g. 3 or north-3).
    pub row: String,
    /// The row map file to put it in: made if missing; a row of that name is replaced.
    #[arg(long, value_name = "FILE")]
    pub map: PathBuf,
    /// Teach from a record of a drive already made (NAME.csv, NAME.mcap, or latest)
    /// instead of driving now.
    #[arg(long, value_name = "RECORD")]
    pub record: Option<PathBuf>,
    /// Write the simulated field's own map instead (its planting record, [sim]
    /// gnss_map_error_*): no driving.
    #[arg(long, conflicts_with = "record")]
    pub field: bool,
    /// The run to drive the row in, as `mechweed run` takes it (it starts in joystick
    /// mode whatever --mode says).
    #[command(flatten)]
    pub run: RunArgs,
}

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct RecordArgs {
    #[command(subcommand)]
    pub command: Option<RecordCommand>,
    /// Record the robot's flows on the bus, on this computer: the same CSV and MCAP
    /// files as a run record, into [record] folder, until Ctrl-C.
    #[arg(long)]
    pub bus: bool,
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, value_name = "ENDPOINT", default_value = mechweed::bus_tools::DEFAULT_ENDPOINT, requires = "bus")]
    pub connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(
        long,
        value_name = "NAME",
        default_value = "mechweed",
        requires = "bus"
    )]
    pub robot: String,
    /// Stop after this many seconds.
    #[arg(long, value_name = "SECONDS", value_parser = mechweed::config::parse_seconds, requires = "bus")]
    pub seconds: Option<f64>,
    /// Settings file (its [record] folder and formats) [default: config/robot.ini, or the built-in copy]
    #[arg(long, value_name = "FILE", requires = "bus")]
    pub config: Option<PathBuf>,
    /// Override one setting, e.g. --set record.folder=field-records (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE", requires = "bus")]
    pub set: Vec<String>,
    /// With --bus: this program's identity on a secured bus (--keys DIR --as recorder).
    #[command(flatten)]
    pub identity: mechweed::keys::args::IdentityArgs,
}

#[derive(clap::Args)]
pub struct BusArgs {
    #[command(subcommand)]
    pub command: BusCommand,
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, global = true, value_name = "ENDPOINT", default_value = mechweed::bus_tools::DEFAULT_ENDPOINT)]
    pub connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(long, global = true, value_name = "NAME", default_value = "mechweed")]
    pub robot: String,
    /// This program's identity on a secured bus (--keys DIR --as operator).
    #[command(flatten)]
    pub identity: mechweed::keys::args::IdentityArgs,
}

#[derive(Subcommand)]
pub enum BusCommand {
    /// Print a flow's messages as JSON lines: status, tick, event, camera/row, or any key.
    Echo {
        key: String,
        /// Stop after this many messages.
        #[arg(long, value_name = "N")]
        count: Option<u64>,
        /// Stop after this many seconds.
        #[arg(long, value_name = "SECONDS", value_parser = mechweed::config::parse_seconds)]
        seconds: Option<f64>,
        /// Take this long over each message: a slow receiver, for tests and measurements.
        #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = mechweed::config::parse_seconds)]
        slow: f64,
        /// At the end, print how old the messages were on arrival (p50, p99, max), from
        /// the time each was sent (status carries it; needs the same clock).
        #[arg(long)]
        latency: bool,
    },
    /// Send a request and print the robot's answer: halt, power_up, or mode MODE.
    Request {
        #[arg(value_enum)]
        request: BusRequest,
        /// For `mode`: halt, joystick, autonomous or test.
        mode: Option<String>,
    },
    /// Print one setting of the running robot, e.g. pid.left.kp.
    Get {
        #[arg(value_name = "SECTION.KEY")]
        setting: String,
    },
    /// Change one setting of the running robot (in halt, gains and [steer] only).
    Set {
        #[arg(value_name = "SECTION.KEY")]
        setting: String,
        value: String,
    },
    /// Who is on the bus, and which flows carry messages at what rate.
    List {
        /// How long to count messages.
        #[arg(long, default_value_t = 2.0, value_name = "SECONDS", value_parser = mechweed::config::parse_seconds)]
        seconds: f64,
    },
}

#[derive(Clone, Copy, ValueEnum)]
pub enum BusRequest {
    Halt,
    /// The same word as in the request's JSON (power-up is taken too).
    #[value(name = "power_up", alias = "power-up")]
    PowerUp,
    Mode,
}

#[derive(clap::Args, Default)]
pub struct RunArgs {
    /// Settings file [default: config/robot.ini, or the built-in copy if there is none]
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Run without the operator GUI: the console prints the status instead.
    #[arg(long)]
    pub headless: bool,
    /// The operator GUI's tab at start.
    #[arg(
        long,
        value_enum,
        default_value = "status",
        conflicts_with = "headless"
    )]
    pub tab: Tab,
    /// Mode to bring the robot into at start (powering up first).
    #[arg(long, value_enum, default_value = "halt")]
    pub mode: StartMode,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Seed of the simulation (overrides [sim] seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override one setting, e.g. --set steer.speed_mps=0.3 (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// Write the run report as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Tool cross-track figures from this distance on, m [default: 5, while the robot
    /// settles onto the row; 0 for short runs]
    #[arg(long, value_name = "METRES", value_parser = parse_metres)]
    pub from_m: Option<f64>,
    /// List every scripted event of [sim] events, with its argument and an example.
    #[arg(long)]
    pub list_events: bool,
}

#[derive(Clone, Copy, ValueEnum, Default)]
pub enum StartMode {
    #[default]
    Halt,
    Joystick,
    Autonomous,
}

#[derive(Subcommand)]
pub enum BenchCommand {
    /// The real threads on the simulated robot: loop lateness and execution time.
    Loop {
        /// Supervisor rate.
        #[arg(long, default_value_t = 100.0, value_name = "HZ")]
        rate: f64,
        #[arg(long, default_value_t = 10.0, value_name = "N")]
        seconds: f64,
        /// With the operator GUI open (needs a display).
        #[arg(long)]
        gui: bool,
        /// The GUI's tab while it is open [default: status]
        #[arg(long, value_enum, requires = "gui")]
        tab: Option<Tab>,
        /// Press the Space key (HALT) in the window about every S seconds through the X
        /// server, and measure the time to the supervisor's HALT (needs the X server's
        /// test extension, as Xvfb has).
        #[arg(long, value_name = "S", requires = "gui")]
        press_space: Option<f64>,
        /// Override one setting (SECTION.KEY=VALUE), e.g. --set bus.enabled=no; repeatable.
        #[arg(long, value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Also write the figures as JSON to this file.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
    },
    /// The row-following benchmark: 3 rows x 3 speeds, in simulated time.
    Rows {
        /// Settings file (the controller's; [sim] is the benchmark's own) [default: config/robot.ini, or the built-in copy]
        #[arg(long)]
        config: Option<PathBuf>,
        /// Override one setting (SECTION.KEY=VALUE); repeatable.
        #[arg(long, value_name = "SECTION.KEY=VALUE")]
        set: Vec<String>,
        /// Seed of the simulation.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The field: clean (0.3, 0.5, 1.0 m/s) or realistic (what real fields add, [sim]
        /// field_*; 0.5, 1.0, 2.0 m/s).
        #[arg(long, value_enum, default_value_t = BenchField::Clean)]
        field: BenchField,
        /// Which sensors steer, each over every row and speed, side by side: camera, gnss,
        /// fused (comma-separated; the simulated robot's GNSS receiver on its field's map).
        #[arg(long, value_enum, value_delimiter = ',', default_value = "camera")]
        sources: Vec<BenchSource>,
        /// Also write the results as JSON to this file.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchSource {
    Camera,
    Gnss,
    Fused,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchField {
    Clean,
    Realistic,
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

pub fn parse_metres(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(m) if m.is_finite() && m >= 0.0 => Ok(m),
        _ => Err(format!("'{text}' is not a distance in m (0 or more)")),
    }
}

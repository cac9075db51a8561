//! The mechweed command line: picks the program asked for. Each program, with its
//! options, is a file of src/programs/.

use std::process::ExitCode;

use clap::Parser;
use mechweed::console::log_style;
use mechweed::programs::{
    Cli, Command, bench, bus, camsim, check_config, cluster, done, gnsssim, keys, probe, record,
    replay, ros2, run, safe, said, teach, watch,
};

fn main() -> ExitCode {
    log_style::init();
    let cli = Cli::parse();
    match cli.command {
        None => run::run(cli.run),
        Some(Command::Run(args)) => run::run(args),
        Some(Command::CheckConfig(args)) => check_config::check_config(args),
        Some(Command::Bench(command)) => bench::bench(command),
        Some(Command::Teach(args)) => teach::teach(args),
        Some(Command::Gnsssim(args)) => done(gnsssim::run(args)),
        Some(Command::Camsim(args)) => done(camsim::run(args)),
        Some(Command::Probe(args)) => probe::program(args),
        Some(Command::Safe(args)) => safe::program(args),
        Some(Command::Record(args)) => record::record(args),
        Some(Command::Replay(args)) => replay::replay(args),
        Some(Command::Bus(args)) => bus::bus(args),
        Some(Command::Cluster(command)) => cluster::cluster(command),
        Some(Command::Watch(args)) => watch::watch(args),
        Some(Command::Ros2(args)) => ros2::run(args),
        Some(Command::Keys(command)) => said(keys::run(command)),
        Some(Command::Doctor(args)) => mechweed::programs::doctor::doctor(args),
        Some(Command::Config(command)) => mechweed::programs::config::config(command),
        Some(Command::ManPages { dir }) => said(mechweed::programs::man_pages::write(&dir)),
        Some(Command::BusGateway) => mechweed::bus::gateway::child::program(),
    }
}

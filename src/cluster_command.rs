//! `mechweed cluster ...`: the master, the launcher, the cluster's status and its
//! picture (src/cluster/); and `mechweed watch`, the operator view on another computer.

use std::process::ExitCode;

use mechweed::cluster::graph::Graph;
use mechweed::cluster::{dot, launcher, master, status};

use crate::cli::{ClusterCommand, WatchArgs};
use crate::print_errors;
use crate::record_command::ctrl_c;

/// Read the graph, or print every error in it.
fn graph(path: &std::path::Path) -> Result<Graph, ExitCode> {
    Graph::load(path).map_err(|errors| {
        print_errors(&errors);
        eprintln!(
            "{}: {} error(s); nothing was started",
            path.display(),
            errors.len()
        );
        ExitCode::FAILURE
    })
}

fn done(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

pub fn cluster(command: ClusterCommand) -> ExitCode {
    match command {
        ClusterCommand::Master { graph: path } => match graph(&path) {
            Ok(graph) => done(master::serve(&graph, &ctrl_c())),
            Err(code) => code,
        },
        ClusterCommand::Launcher {
            machine,
            connect,
            robot,
        } => done(launcher::run(&machine, &connect, &robot, &ctrl_c())),
        ClusterCommand::Status {
            connect,
            robot,
            seconds,
            json,
        } => match status::fetch(&connect, &robot, seconds) {
            Ok(found) if json => {
                println!("{found}");
                ExitCode::SUCCESS
            }
            Ok(found) => {
                print!("{}", status::text(&found));
                ExitCode::SUCCESS
            }
            Err(why) => done(Err(why)),
        },
        ClusterCommand::Dot { graph: path } => match graph(&path) {
            Ok(graph) => {
                print!("{}", dot::dot(&graph));
                ExitCode::SUCCESS
            }
            Err(code) => code,
        },
        ClusterCommand::Check { graph: path } => match graph(&path) {
            Ok(_) => {
                println!("ok");
                ExitCode::SUCCESS
            }
            Err(code) => code,
        },
    }
}

/// `mechweed watch`: the operator GUI fed by the robot's flows.
pub fn watch(args: WatchArgs) -> ExitCode {
    let settings = match crate::load_settings(None, &[]) {
        Ok(settings) => settings,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let remote = match mechweed::gui::remote::RemoteView::connect(&args.connect, &args.robot) {
        Ok(remote) => remote,
        Err(why) => return done(Err(why)),
    };
    println!("watching {} at {}", args.robot, args.connect);
    let advice = "watch needs a window; on a computer without one, `mechweed bus echo status` prints the status";
    let shown =
        mechweed::gui::run_watch(remote, settings, args.duration, args.tab, ctrl_c(), advice);
    done(shown.map(|frames| println!("window closed after {frames} frames")))
}

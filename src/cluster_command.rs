//! `mechweed cluster ...`: the master, the launcher, the cluster's status and its
//! picture (src/cluster/).

use std::process::ExitCode;

use mechweed::cluster::graph::Graph;
use mechweed::cluster::{dot, launcher, master, status};

use crate::cli::ClusterCommand;
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

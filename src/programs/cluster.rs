//! `mechweed cluster ...`: the master, the launcher, the cluster's status and its
//! picture (src/cluster/).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Subcommand;

use crate::cluster::graph::Graph;
use crate::cluster::{dot, launcher, master, status};

use crate::config::parse_seconds;
use crate::console::ctrl_c;
use crate::programs::{done, print_errors};

#[derive(Subcommand)]
pub enum ClusterCommand {
    /// Serve a graph file to the launchers and wait; Ctrl-C stops the cluster, the
    /// controller first.
    Master {
        /// The graph file, e.g. config/cluster.ini.
        graph: PathBuf,
    },
    /// Start, watch and stop the processes the master's graph gives this machine.
    Launcher {
        /// This machine's name in the graph ([machine NAME]).
        #[arg(long, value_name = "NAME")]
        machine: String,
        /// Where the master listens ([cluster] master in the graph).
        #[arg(long, value_name = "ENDPOINT", default_value = crate::cluster::DEFAULT_MASTER)]
        connect: String,
        /// The robot's name ([cluster] robot in the graph).
        #[arg(long, value_name = "NAME", default_value = "mechweed")]
        robot: String,
        /// An executable besides mechweed that plans may run here (repeatable); nothing
        /// else is run, whatever a plan says.
        #[arg(long, value_name = "PATH")]
        allow: Vec<String>,
        /// On a secured cluster: --keys DIR --as MACHINE (the launcher's identity is its
        /// machine's name); each program it starts gets its role's identity from DIR.
        #[command(flatten)]
        identity: crate::programs::keys::IdentityArgs,
    },
    /// Print the cluster: machines, processes and their states, flows and their rates.
    Status {
        /// Where the master listens ([cluster] master in the graph).
        #[arg(long, value_name = "ENDPOINT", default_value = crate::cluster::DEFAULT_MASTER)]
        connect: String,
        /// The robot's name ([cluster] robot in the graph).
        #[arg(long, value_name = "NAME", default_value = "mechweed")]
        robot: String,
        /// How long to count each flow's messages.
        #[arg(long, value_name = "SECONDS", default_value_t = 2.0, value_parser = parse_seconds)]
        seconds: f64,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// On a secured cluster: --keys DIR --as operator (or viewer).
        #[command(flatten)]
        identity: crate::programs::keys::IdentityArgs,
    },
    /// Print the graph as a Graphviz picture (DOT): `... | dot -Tsvg > cluster.svg`.
    Dot { graph: PathBuf },
    /// Check a graph file: prints "ok", or every error found (exit 1).
    Check { graph: PathBuf },
}

/// What this launcher lets run, or why it does not start: a plan over plain TCP
/// beyond this computer could come from anyone on that network; a launcher's identity
/// is its machine's name (the access rules give it that machine's plan alone).
fn launcher_admission(
    machine: &str,
    connect: &str,
    tls: Option<&crate::config::TlsFiles>,
    allowed: Vec<String>,
) -> Result<crate::cluster::admit::Admission, String> {
    let Some(tls) = tls else {
        if !crate::config::is_loopback(connect) {
            return Err(format!(
                "launcher {machine}: --connect {connect} reaches the master over plain TCP beyond this computer: anyone on that network could answer with a plan. Give the cluster's keys (--keys DIR --as {machine}) and a tls/ endpoint"
            ));
        }
        return Ok(crate::cluster::admit::Admission {
            allowed,
            keys: None,
            file_options: file_options(),
        });
    };
    let name = tls.name();
    if name != machine {
        return Err(format!(
            "launcher {machine}: its identity must be its machine's name (--as {machine}), not {name}: the access rules give a launcher the plan of its own machine alone"
        ));
    }
    // The name the links know: the certificate's own, whatever its file is called.
    let certified = crate::bus::keys::certificate_name(&tls.cert)?;
    if certified != machine {
        return Err(format!(
            "launcher {machine}: the certificate {} is {certified}'s, not {machine}'s: the master and the access rules would take this launcher for {certified}; use {machine}'s own files (keys add DIR launcher {machine})",
            tls.cert.display()
        ));
    }
    let roster = crate::bus::keys::Roster::read(&tls.roster())?;
    if roster.role_of(machine) != Some(crate::bus::keys::Role::Launcher) {
        return Err(format!(
            "launcher {machine}: the roster {} gives {machine} no launcher's role (revoked, or never added: keys add DIR launcher {machine})",
            tls.roster().display()
        ));
    }
    let dir = tls.folder();
    Ok(crate::cluster::admit::Admission {
        allowed,
        keys: Some((dir, roster)),
        file_options: file_options(),
    })
}

/// The options of each program a plan may start that take a file or folder, from the
/// same definitions as --help (paths, or values named FILE, DIR or FOLDER).
fn file_options() -> std::collections::BTreeMap<String, Vec<String>> {
    use clap::CommandFactory;
    let cli = crate::programs::Cli::command();
    let takes_path = |arg: &clap::Arg| {
        use clap::ValueHint::{AnyPath, DirPath, FilePath};
        let hinted = matches!(arg.get_value_hint(), AnyPath | FilePath | DirPath);
        let named = (arg.get_value_names().unwrap_or_default().iter())
            .any(|n| ["FILE", "DIR", "FOLDER", "PATH"].contains(&n.as_str()));
        hinted || named
    };
    let options = |program: &clap::Command| -> Vec<String> {
        (program.get_arguments())
            .filter(|arg| takes_path(arg))
            .filter_map(|arg| arg.get_long().map(|long| format!("--{long}")))
            .collect()
    };
    (crate::cluster::admit::PROGRAMS.iter())
        .filter_map(|name| Some((name.to_string(), options(cli.find_subcommand(name)?))))
        .collect()
}

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
            allow,
            identity,
        } => {
            let tls = identity.files();
            let admission = match launcher_admission(&machine, &connect, tls.as_ref(), allow) {
                Ok(admission) => admission,
                Err(why) => return done(Err(why)),
            };
            done(launcher::run(
                &machine,
                &connect,
                &robot,
                tls.as_ref(),
                &admission,
                &ctrl_c(),
            ))
        }
        ClusterCommand::Status {
            connect,
            robot,
            seconds,
            json,
            identity,
        } => match status::fetch(&connect, &robot, seconds, identity.files().as_ref()) {
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

#[cfg(test)]
mod tests {
    #[test]
    fn the_options_that_take_a_file_are_found_from_the_command_line_definitions() {
        let options = super::file_options();
        assert!(
            options["run"].contains(&"--report".to_string()),
            "{options:?}"
        );
        assert!(
            options["run"].contains(&"--config".to_string()),
            "{options:?}"
        );
        assert!(
            !options["run"].contains(&"--duration".to_string()),
            "{options:?}"
        );
    }
}

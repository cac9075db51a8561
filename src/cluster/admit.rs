//! What a launcher lets a plan run on its computer. The plan comes from the master's
//! identity alone (the access rules), but the launcher still decides: mechweed's own
//! programs always; any other executable only if the launcher's command line allows its
//! path (`--allow PATH`); no environment variable from a plan but the robot's own
//! (MECHWEED_*), so none changes how programs load (LD_*) or which are found (PATH).
//! On a secured cluster each mechweed program is given an identity of its role from the
//! launcher's own keys folder (the first the roster names whose files are there).

use std::path::{Path, PathBuf};

use super::plan::Launch;
use crate::bus::keys::{Role, Roster};
use crate::config::TlsFiles;

/// The mechweed programs a plan may start: the cluster's own (not, say, `keys` or a
/// second `cluster launcher`).
pub(crate) const PROGRAMS: [&str; 5] = ["run", "camsim", "watch", "record", "ros2"];

/// The launcher's own rules for what may run.
#[derive(Debug, Clone, Default)]
pub(crate) struct Admission {
    /// Executables besides mechweed that plans may name, as given on the command line.
    pub allowed: Vec<String>,
    /// On a secured cluster, the keys folder and the roster: each program gets the
    /// identity of its role that this folder holds.
    pub keys: Option<(PathBuf, Roster)>,
    /// Each of PROGRAMS' options that take a file or folder (the command line's
    /// definitions, given by the program that starts the launcher): a plan may name
    /// files in them only inside the launcher's working folder.
    pub file_options: std::collections::BTreeMap<String, Vec<String>>,
}

/// Where `program` is: a path as it is, a bare name through PATH.
fn resolve(program: &str) -> Option<PathBuf> {
    if program.contains('/') {
        return std::fs::canonicalize(program).ok();
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
        .and_then(|p| std::fs::canonicalize(p).ok())
}

/// The role a mechweed program runs as.
fn role_of(command: &str) -> Option<Role> {
    match command {
        "run" => Some(Role::Robot),
        "camsim" => Some(Role::Camera),
        "watch" => Some(Role::Operator),
        "record" => Some(Role::Recorder),
        // Read-only on the robot's bus: it takes the flows and asks for nothing.
        "ros2" => Some(Role::Viewer),
        _ => None,
    }
}

/// The identity of `role` whose files are in `dir`: the first the roster names (an
/// operator's laptop may hold laptop-2 rather than operator).
fn identity_in(dir: &Path, roster: &Roster, role: Role) -> Option<String> {
    roster
        .names(role)
        .find(|name| {
            let files = TlsFiles::in_folder(dir, name);
            files.cert.is_file() && files.key.is_file()
        })
        .map(str::to_string)
}

impl Admission {
    /// `launch` as this launcher runs it, or why it does not.
    pub(crate) fn admit(&self, mut launch: Launch) -> Result<Launch, String> {
        if let Some(why) = super::plan_check::refusal(&launch, &self.file_options) {
            return Err(why);
        }
        let command = launch.args.first().cloned().unwrap_or_default();
        if launch.program == "mechweed" && !PROGRAMS.contains(&command.as_str()) {
            return Err(format!(
                "{} is refused: mechweed {command} is not a program of the cluster (a plan starts {})",
                launch.name,
                PROGRAMS.join(", ")
            ));
        }
        if launch.program != "mechweed" {
            let wanted = resolve(&launch.program);
            let allowed = self
                .allowed
                .iter()
                .any(|a| *a == launch.program || (wanted.is_some() && resolve(a) == wanted));
            if !allowed {
                return Err(format!(
                    "{} is refused: {} is not a program this launcher allows (mechweed's own programs always; any other only with --allow PATH on the launcher's command line)",
                    launch.name, launch.program
                ));
            }
        }
        let (kept, dropped): (Vec<_>, Vec<_>) = launch
            .env
            .into_iter()
            .partition(|(name, _)| name.starts_with("MECHWEED_"));
        if let Some((name, _)) = dropped.first() {
            eprintln!(
                "launcher: {}: the plan's environment variable {name} is not taken (only MECHWEED_* come from a plan)",
                launch.name
            );
        }
        launch.env = kept;
        if let Some((dir, roster)) = &self.keys
            && launch.program == "mechweed"
            && let Some(role) = role_of(&command)
        {
            let name = identity_in(dir, roster, role).ok_or_else(|| {
                format!(
                    "{} is refused: {} holds no identity of the role {role} (mechweed keys add DIR {role} NAME makes one; copy NAME.pem and NAME.key here)",
                    launch.name,
                    dir.display()
                )
            })?;
            identity_args(&mut launch.args, dir, &name);
        }
        Ok(launch)
    }
}

/// Give a mechweed program its identity `name` in `dir`: `run` takes it as settings,
/// the tools as `--keys DIR --as NAME`.
fn identity_args(args: &mut Vec<String>, dir: &Path, name: &str) {
    if args.first().map(String::as_str) == Some("run") {
        let files = TlsFiles::in_folder(dir, name);
        for (key, file) in [
            ("tls_ca", &files.ca),
            ("tls_cert", &files.cert),
            ("tls_key", &files.key),
        ] {
            args.extend(["--set".to_string(), format!("bus.{key}={}", file.display())]);
        }
    } else {
        args.extend([
            "--keys".to_string(),
            dir.display().to_string(),
            "--as".to_string(),
            name.to_string(),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn launch(program: &str, args: &[&str]) -> Launch {
        Launch {
            name: "x".into(),
            program: program.into(),
            args: args.iter().map(|a| a.to_string()).collect(),
            env: vec![
                ("MECHWEED_ROBOT".into(), "mechweed".into()),
                ("LD_PRELOAD".into(), "/tmp/evil.so".into()),
                ("PATH".into(), "/tmp".into()),
            ],
            auto: true,
            restart: false,
            restart_delay_s: 0.0,
            after: Vec::new(),
            controller: false,
        }
    }

    #[test]
    fn only_mechweed_and_allowed_programs_run_without_loader_variables() {
        let none = Admission::default();
        let why = none.admit(launch("/bin/sh", &["-c", "id"])).unwrap_err();
        assert!(why.contains("--allow PATH"), "{why}");
        let sh = Admission {
            allowed: vec!["/bin/sh".into()],
            ..Admission::default()
        };
        let taken = sh.admit(launch("/bin/sh", &[])).unwrap();
        assert_eq!(
            taken.env,
            [("MECHWEED_ROBOT".to_string(), "mechweed".to_string())]
        );
        assert!(none.admit(launch("mechweed", &["camsim"])).is_ok());
    }

    #[test]
    fn a_secured_launcher_gives_each_program_its_roles_identity() {
        let dir = tempfile::tempdir().unwrap();
        let keys_dir = dir.path().join("keys");
        crate::bus::keys::new_cluster(&keys_dir, "mechweed", &[]).unwrap();
        crate::bus::keys::add_identity(&keys_dir, Role::Operator, "laptop-2", &[]).unwrap();
        // This laptop holds laptop-2's files, not operator's.
        std::fs::remove_file(keys_dir.join("operator.pem")).unwrap();
        let roster = Roster::read(&crate::bus::keys::roster::path_in(&keys_dir)).unwrap();
        let keys = Admission {
            keys: Some((keys_dir.clone(), roster)),
            ..Admission::default()
        };
        let folder = keys_dir.display().to_string();
        let camsim = keys
            .admit(launch("mechweed", &["camsim", "--bus"]))
            .unwrap();
        assert_eq!(
            camsim.args[2..],
            ["--keys", folder.as_str(), "--as", "camera"]
        );
        let watch = keys.admit(launch("mechweed", &["watch"])).unwrap();
        assert_eq!(
            watch.args[1..],
            ["--keys", folder.as_str(), "--as", "laptop-2"]
        );
        // The ROS 2 bridge reads the flows and asks for nothing: a viewer.
        let ros2 = keys.admit(launch("mechweed", &["ros2"])).unwrap();
        assert_eq!(
            ros2.args[1..],
            ["--keys", folder.as_str(), "--as", "viewer"]
        );
        let run = keys.admit(launch("mechweed", &["run"])).unwrap();
        let cert = format!("bus.tls_cert={}", keys_dir.join("robot.pem").display());
        assert!(run.args.contains(&cert), "{:?}", run.args);
        std::fs::remove_file(keys_dir.join("camera.key")).unwrap();
        let why = keys.admit(launch("mechweed", &["camsim"])).unwrap_err();
        assert!(
            why.contains("holds no identity of the role camera"),
            "{why}"
        );
    }

    #[test]
    fn a_plan_starts_only_the_cluster_s_own_mechweed_programs() {
        let why = Admission::default()
            .admit(launch("mechweed", &["keys", "new", "x"]))
            .unwrap_err();
        assert!(why.contains("not a program of the cluster"), "{why}");
    }
}
